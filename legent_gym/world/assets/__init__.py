"""Assets: the built-in parametric library, user glTF/GLB imports, and the registry.

Importing this package registers the built-in assets.
"""

from legent_gym.world.assets import (
    library,  # noqa: E402,F401  (registers built-ins)
    registry,
)
from legent_gym.world.assets.model import AssetModel, Joint, Link, Part, Receptacle

__all__ = ["AssetModel", "Joint", "Link", "Part", "Receptacle", "registry"]

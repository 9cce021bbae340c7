"""The world: scene format, assets, MuJoCo builder, rendering, navigation, generation.

Nothing here imports Gymnasium: the world can be used on its own (build a scene, render
it, plan paths on it).
"""

from legent_gym.utils import gl_backend  # noqa: F401
from legent_gym.world.scene import (
    Scene,
    SceneError,
    load_scene,
    loads_scene,
    save_scene,
    validate_scene,
)

__all__ = ["Scene", "SceneError", "load_scene", "loads_scene", "save_scene", "validate_scene"]

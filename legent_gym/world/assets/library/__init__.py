"""Built-in parametric assets (furniture and small objects), registered on import."""

from legent_gym.world.assets.library import (  # noqa: F401
    appliances,
    bath_decor,
    decor,
    fittings,
    furniture,
    kitchenware,
    living,
    objects,
    office_bath,
    wall_decor,
)

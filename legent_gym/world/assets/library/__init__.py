"""Built-in parametric assets (furniture and small objects), registered on import."""

from legent_gym.world.assets.library import decor, furniture, kitchenware, objects, office_bath  # noqa: F401

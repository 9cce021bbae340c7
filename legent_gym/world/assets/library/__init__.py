"""Built-in parametric assets (furniture and small objects), registered on import."""

from legent_gym.world.assets.library import furniture, objects  # noqa: F401

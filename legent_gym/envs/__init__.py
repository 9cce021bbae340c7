"""legent_gym.envs (see the package docstring)."""

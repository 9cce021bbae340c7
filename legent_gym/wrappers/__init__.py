"""legent_gym.wrappers (see the package docstring)."""

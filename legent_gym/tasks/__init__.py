"""legent_gym.tasks (see the package docstring)."""

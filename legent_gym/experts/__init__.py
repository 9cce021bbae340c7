"""legent_gym.experts (see the package docstring)."""

"""Gymnasium environments: a world, an agent and a task joined (see ``household.py``)."""

from legent_gym.envs.registration import ENV_IDS, register_envs

__all__ = ["ENV_IDS", "register_envs"]

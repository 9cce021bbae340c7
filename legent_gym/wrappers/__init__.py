"""Wrappers: expert labels and demonstrations, ecosystem adapters (stable-baselines3), history."""

from legent_gym.wrappers.expert import ExpertInfo, ExpertPolicy
from legent_gym.wrappers.history import InterleavedHistory
from legent_gym.wrappers.sb3 import FlatActions, InstructionTokens, for_sb3, tokenize

__all__ = ["ExpertInfo", "ExpertPolicy", "FlatActions", "InstructionTokens", "InterleavedHistory", "for_sb3", "tokenize"]

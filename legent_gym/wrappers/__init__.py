"""Wrappers: ecosystem adapters (stable-baselines3), and later expert and history wrappers."""

from legent_gym.wrappers.history import InterleavedHistory
from legent_gym.wrappers.sb3 import FlatActions, InstructionTokens, tokenize

__all__ = ["FlatActions", "InstructionTokens", "InterleavedHistory", "tokenize"]

"""Checkpoints: the weights, the model's configuration and vocabularies, written atomically."""

from __future__ import annotations

import io
import os
from pathlib import Path
from typing import Any

import torch

from baselines.vla.codec import ActionCodec
from baselines.vla.model import VLA, ModelConfig
from baselines.vla.words import WordVocab
from legent_gym.utils.atomic import atomic_write_bytes

FORMAT = "legent-vla-1"


def save_checkpoint(path: str | os.PathLike, model: VLA, vocab: WordVocab, **extra: Any) -> None:
    """Everything needed to rebuild ``model`` (plus ``extra``: training state, metrics)."""
    state = {"format": FORMAT, "config": model.config.to_dict(), "codec": model.codec.to_dict(),
             "vocab": vocab.to_dict(), "weights": model.state_dict(), **extra}
    buffer = io.BytesIO()
    torch.save(state, buffer)
    atomic_write_bytes(path, buffer.getvalue())


def read_checkpoint(path: str | os.PathLike) -> dict[str, Any]:
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"no checkpoint at {path}")
    # weights_only: a checkpoint is data; loading must not run code from the file.
    state = torch.load(path, map_location="cpu", weights_only=True)
    if not isinstance(state, dict) or state.get("format") != FORMAT:
        raise ValueError(f"{path} is not a VLA checkpoint (format {FORMAT!r})")
    return state


def build_model(state: dict[str, Any]) -> tuple[VLA, WordVocab]:
    config = ModelConfig.from_dict(state["config"])
    codec = ActionCodec.from_dict(state["codec"])
    vocab = WordVocab.from_dict(state["vocab"])
    model = VLA(config, codec, len(vocab), vocab.max_words)
    model.load_state_dict(state["weights"])
    return model, vocab


def load_model(path: str | os.PathLike) -> tuple[VLA, WordVocab]:
    """The model of a checkpoint, in eval mode."""
    model, vocab = build_model(read_checkpoint(path))
    return model.eval(), vocab

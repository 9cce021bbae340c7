"""Loading a Hugging Face image-text-to-text model and its processor, with clear errors.

A model is named by a local folder (``config.json`` and weights, as ``save_pretrained``
writes them) or by a hub id (``org/name``), which ``from_pretrained`` downloads on a
machine that can reach the hub. Training writes ``legent_vlm.json`` next to the weights:
the window and view size it trained on, which the policy reads back.
"""

from __future__ import annotations

import json
import os
import re
from pathlib import Path
from typing import Any

META_FILE = "legent_vlm.json"
_HUB_ID = re.compile(r"^[A-Za-z0-9][\w.-]*/[\w.-]+$")


class ModelError(ValueError):
    """The model named is not something ``from_pretrained`` can load."""


def check_source(source: str | os.PathLike) -> str:
    """A local model folder (absolute) or a hub id; :class:`ModelError` for anything else."""
    text = str(source)
    path = Path(text).expanduser()
    if path.exists():
        if not path.is_dir():
            raise ModelError(f"{path} is a file, not a model folder (a folder with config.json, as "
                             "save_pretrained writes it)")
        if not (path / "config.json").is_file():
            raise ModelError(f"{path} is not a model folder: it has no config.json (give the folder "
                             "fine-tuning wrote, OUT/final, or a Hugging Face model folder)")
        return str(path.resolve())
    if _HUB_ID.match(text) and not text.startswith((".", "/")):
        return text
    raise ModelError(f"no model folder at {path} (and {text!r} is not a hub id of the form org/name)")


def read_meta(source: str) -> dict[str, Any]:
    """What training recorded next to the weights (empty for a model not trained here)."""
    path = Path(source) / META_FILE
    if not path.is_file():
        return {}
    return json.loads(path.read_text())


def load_processor(source: str) -> Any:
    # the vlm extra's libraries take seconds to import: only when a model is made or run
    from transformers import AutoProcessor

    try:
        return AutoProcessor.from_pretrained(source)
    except (OSError, ValueError, KeyError) as err:
        raise ModelError(f"cannot load a processor from {source}: {err}") from None


def load_model(source: str, dtype: Any = None) -> Any:
    """The model as ``AutoModelForImageTextToText`` loads it (weights in ``dtype``)."""
    # the vlm extra's libraries take seconds to import: only when a model is made or run
    from transformers import AutoModelForImageTextToText

    try:
        return AutoModelForImageTextToText.from_pretrained(source, dtype=dtype)
    except (OSError, ValueError, KeyError) as err:
        raise ModelError(f"cannot load an image-text-to-text model from {source}: {err}") from None


def pick_dtype(device: str, dtype: str = "auto") -> Any:
    """``auto``: bfloat16 on a GPU that supports it, float32 elsewhere."""
    # the vlm extra's libraries take seconds to import: only when a model is made or run
    import torch

    if dtype not in ("auto", "bf16", "fp32"):
        raise ValueError(f"dtype must be auto, bf16 or fp32, got {dtype!r}")
    if dtype == "auto":
        bf16 = device.startswith("cuda") and torch.cuda.is_available() and torch.cuda.is_bf16_supported()
        return torch.bfloat16 if bf16 else torch.float32
    return torch.bfloat16 if dtype == "bf16" else torch.float32

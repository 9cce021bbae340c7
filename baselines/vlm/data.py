"""Training samples for a Hugging Face VLM from ``legent-gym collect --format legent`` data.

Each line of ``interleaved.jsonl`` is one sample, as the paper trains VILA: the
instruction, the last <= k views with the actions between them, and the action code as
the target. The lines are read and checked by :func:`baselines.vla.dataset.read_trajectories`
(the compact VLA's loader), so both baselines train on exactly the same windows.

One window becomes one user message in the model's own chat template, with the views
where LEGENT's prompt puts them::

    Instruction: Come here.
    Observation: <image> Action: rotate_right(-90)
    Observation: <image> Action:

and the target is the assistant's reply: the action code, as the chat template closes a
reply (its end-of-turn token included, so that generation stops after the code). Only
the reply's tokens are trained on (:func:`Encoder.batch`).
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from PIL import Image

from baselines.vla.dataset import DatasetError, read_trajectories, resolve_root
from legent_gym.data.legent_format import read_png

IGNORE = -100  # the cross-entropy "no target" index


@dataclass(frozen=True)
class Sample:
    """One step of a trajectory: the model's input and the action code it should write."""

    instruction: str
    images: tuple[Path, ...]   # the window's views, oldest first; the last is the current one
    history: tuple[str, ...]   # the actions between them (len(images) - 1)
    target: str                # the action code to write


def user_message(instruction: str, n_images: int, history: Sequence[str]) -> dict[str, Any]:
    """The user turn of one window: the instruction, then each view and the action after it;
    images are ``{"type": "image"}`` entries (the processor receives the pictures in order)."""
    if len(history) != n_images - 1:
        raise ValueError(f"{n_images} views need {n_images - 1} history actions, got {len(history)}")
    content: list[dict[str, Any]] = [{"type": "text", "text": f"Instruction: {instruction}\n"}]
    for i in range(n_images):
        content.append({"type": "text", "text": "Observation: "})
        content.append({"type": "image"})
        content.append({"type": "text", "text": f" Action: {history[i]}\n" if i < len(history) else " Action:"})
    return {"role": "user", "content": content}


def read_samples(folders: Sequence[str | os.PathLike], limits: Sequence[int | None] | None = None,
                 window: int | None = None) -> list[Sample]:
    """Every step of the first ``limits[i]`` trajectories of each dataset folder, in order.

    ``window``: the most views per sample (default: what the data holds, the paper's 6 for
    ``collect``'s default). Targets are the expert's labels; the history is what was executed.
    """
    limits = list(limits) if limits is not None else [None] * len(folders)
    if len(limits) != len(folders):
        raise ValueError(f"{len(limits)} limits for {len(folders)} data folders")
    if window is not None and window < 1:
        raise ValueError(f"window must be >= 1 view, got {window}")
    samples = []
    for folder, limit in zip(folders, limits):
        root = resolve_root(folder)
        for traj in read_trajectories(root, limit):
            k = window or traj.window
            for n, target in enumerate(traj.labels):
                lo = max(0, n + 1 - k)
                samples.append(Sample(traj.instruction, tuple(root / p for p in traj.image_paths[lo:n + 1]),
                                      tuple(traj.actions[lo:n]), target))
    if not samples:
        raise DatasetError(f"no samples in {', '.join(str(f) for f in folders)}")
    return samples


def load_image(path: Path):
    """A view as a PIL image (RGB)."""
    return Image.fromarray(read_png(path))


class Encoder:
    """Turns samples into model inputs with a processor's chat template and tokenizer."""

    def __init__(self, processor: Any):
        self.processor = processor
        self.tokenizer = getattr(processor, "tokenizer", None)
        if self.tokenizer is None:
            raise ValueError(f"{type(processor).__name__} has no tokenizer: an image-text-to-text model's "
                             "processor is needed")
        if getattr(processor, "chat_template", None) is None and getattr(self.tokenizer, "chat_template", None) is None:
            raise ValueError("the model folder has no chat template (chat_template.jinja or the tokenizer's): "
                             "use an instruction-tuned (chat) model or add a template")
        if self.tokenizer.pad_token_id is None:
            self.tokenizer.pad_token = self.tokenizer.eos_token

    def prompt(self, instruction: str, n_images: int, history: Sequence[str]) -> str:
        """The text of the model's input up to where its reply begins."""
        return self.processor.apply_chat_template([user_message(instruction, n_images, history)],
                                                  tokenize=False, add_generation_prompt=True)

    def reply(self, sample: Sample) -> str:
        """The text the template adds after :meth:`prompt` for the target reply."""
        user = user_message(sample.instruction, len(sample.images), sample.history)
        prompt = self.processor.apply_chat_template([user], tokenize=False, add_generation_prompt=True)
        full = self.processor.apply_chat_template(
            [user, {"role": "assistant", "content": [{"type": "text", "text": sample.target}]}], tokenize=False)
        if not full.startswith(prompt) or sample.target not in full[len(prompt):]:
            raise ValueError("the chat template does not write a reply after the generation prompt "
                             f"(prompt ends {prompt[-40:]!r}, conversation ends {full[-60:]!r})")
        return full[len(prompt):]

    def batch(self, samples: Sequence[Sample], images: Sequence[Sequence[Any]] | None = None) -> dict[str, Any]:
        """A right-padded training batch: the processor's inputs plus ``labels``, which are
        :data:`IGNORE` everywhere but on the reply's tokens."""
        # the vlm extra's libraries take seconds to import: only when a model is made or run
        import torch

        if images is None:
            images = [[load_image(p) for p in s.images] for s in samples]
        texts, replies = [], []
        for sample in samples:
            reply = self.reply(sample)
            texts.append(self.prompt(sample.instruction, len(sample.images), sample.history) + reply)
            replies.append(self.tokenizer(reply, add_special_tokens=False)["input_ids"])
        self.tokenizer.padding_side = "right"
        inputs = self.processor(text=texts, images=[list(i) for i in images], padding=True, return_tensors="pt")
        ids, mask = inputs["input_ids"], inputs["attention_mask"]
        labels = torch.full_like(ids, IGNORE)
        for row, reply_ids in enumerate(replies):
            end = int(mask[row].sum())
            start = end - len(reply_ids)
            if ids[row, start:end].tolist() != reply_ids:
                raise ValueError("the reply's tokens differ when tokenised after the prompt: the tokenizer merges "
                                 f"across the prompt's end ({self.tokenizer.decode(ids[row, start - 3:end])!r})")
            labels[row, start:end] = ids[row, start:end]
        inputs["labels"] = labels
        return dict(inputs)


def image_size(samples: Sequence[Sample]) -> tuple[int, int]:
    """(width, height) of the data's views; :class:`DatasetError` if they differ in size."""
    sizes = {read_png(s.images[-1]).shape[:2] for s in samples[:: max(1, len(samples) // 16)]}
    sizes.add(read_png(samples[-1].images[-1]).shape[:2])
    if len(sizes) != 1:
        raise DatasetError(f"the views have several sizes {sorted(sizes)}: collect every dataset at one size")
    height, width = sizes.pop()
    return int(width), int(height)


__all__ = ["IGNORE", "Encoder", "Sample", "image_size", "load_image", "read_samples", "user_message"]

"""Behaviour cloning of the VLA on interleaved data from ``legent-gym collect``.

::

    python -m baselines.vla.train --data runs/data/ComeHere-OneRoom --out runs/vla/come1 \\
        --trajectories 1000 --epochs 8

``--data`` may be given several times (joint training); ``--trajectories N`` takes the first
N trajectories of each (collection order, so 1K is a prefix of 10K); in code a tuple gives
each dataset its own limit (``None``: all of it). Every epoch ends with
a checkpoint (``last.pt``, with the optimizer: an interrupted run resumes with
``--resume``) and a line of ``log.jsonl``; the final weights are ``model.pt``. The same
data, configuration and seed give the same weights (deterministic algorithms, one fixed
batch order per epoch).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
import time
from collections.abc import Sequence
from dataclasses import MISSING, asdict, dataclass, field, fields
from pathlib import Path

import numpy as np
import torch
from torch.nn import functional as F
from tqdm import tqdm

from baselines.vla.checkpoint import build_model, read_checkpoint, save_checkpoint
from baselines.vla.codec import ActionCodec
from baselines.vla.dataset import (
    DatasetError,
    Encoded,
    batches,
    encode,
    mirror_slots,
    read_trajectories,
    resolve_root,
)
from baselines.vla.model import VLA, ModelConfig
from baselines.vla.words import WordVocab
from legent_gym.utils.atomic import atomic_write_text

LAST, FINAL, LOG = "last.pt", "model.pt", "log.jsonl"


@dataclass(frozen=True)
class TrainConfig:
    data: tuple[str, ...]
    out: str
    trajectories: int | tuple[int | None, ...] | None = None   # per dataset; None: all
    epochs: int = 8
    trajectories_per_batch: int = 16
    lr: float = 1e-3
    weight_decay: float = 0.01
    #: Linear warm-up of the learning rate, at most half the run's optimizer steps (a short
    #: run would otherwise end before the rate reaches ``lr``).
    warmup_steps: int = 100
    augment: bool = True
    #: Random shift of every training view by up to this many pixels (edge pixels repeated
    #: into the gap; 0: none), as DrQ and RAD do for pixel-based control learned from scratch.
    shift: int = 0
    mirror: bool = True
    validation_fraction: float = 0.05
    bins: int = 37
    seed: int = 0
    threads: int | None = None
    #: torch device to train on ("cpu", "cuda", ...). Results are deterministic per device
    #: (CUDA needs CUBLAS_WORKSPACE_CONFIG=:4096:8); checkpoints load onto the CPU either way.
    device: str = "cpu"
    model: ModelConfig = field(default_factory=ModelConfig)

    def __post_init__(self) -> None:
        if not self.data:
            raise ValueError("no --data given")
        if self.epochs < 1:
            raise ValueError(f"epochs must be >= 1, got {self.epochs}")
        limits = self.trajectories if isinstance(self.trajectories, tuple) else (self.trajectories,)
        if isinstance(self.trajectories, tuple) and len(limits) != len(self.data):
            raise ValueError(f"trajectories gives {len(limits)} limits for {len(self.data)} datasets")
        if any(n is not None and n < 1 for n in limits):
            raise ValueError(f"trajectories must be >= 1, got {self.trajectories}")
        if self.trajectories_per_batch < 1:
            raise ValueError(f"trajectories_per_batch must be >= 1, got {self.trajectories_per_batch}")
        check_shift(self.shift, self.model.image_size)
        if not 0.0 <= self.validation_fraction < 1.0:
            raise ValueError(f"validation_fraction must be in [0, 1), got {self.validation_fraction}")

    def limit(self, dataset: int) -> int | None:
        """The number of trajectories to take from ``data[dataset]`` (None: all)."""
        return self.trajectories[dataset] if isinstance(self.trajectories, tuple) else self.trajectories

    def matches(self, stored: dict | None) -> bool:
        """Whether a checkpoint's ``train_config`` is this configuration. A key the
        checkpoint lacks (a field added after it was written) counts as that field's
        default, so older checkpoints of the same run are still recognised."""
        if stored is None:
            return False
        defaults = {f.name: f.default for f in fields(self) if f.default is not MISSING}
        stored = {**defaults, **stored}
        try:  # the model's own fields, the same way (ModelConfig fills in its defaults)
            stored["model"] = ModelConfig.from_dict(stored["model"]).to_dict()
        except (KeyError, TypeError, ValueError):
            return False  # no model, or one with fields this code does not know
        return stored == self.to_dict()

    def to_dict(self) -> dict:
        trajectories = list(self.trajectories) if isinstance(self.trajectories, tuple) else self.trajectories
        return {**asdict(self), "data": list(self.data), "trajectories": trajectories, "model": self.model.to_dict()}


def set_determinism(seed: int, threads: int | None, device: str = "cpu") -> None:
    """Same seed, same threads -> same numbers (torch's CPU kernels are deterministic under
    ``use_deterministic_algorithms``; the thread count changes reduction order). On other
    devices a kernel without a deterministic version warns rather than stops training."""
    torch.manual_seed(seed)
    torch.use_deterministic_algorithms(True, warn_only=device != "cpu")
    if threads:
        torch.set_num_threads(threads)


def augment(images: torch.Tensor, generator: torch.Generator) -> torch.Tensor:
    """Brightness and colour jitter per view (+-15 % and +-5 % per channel): houses differ in
    wall colours and lights, and 1K trajectories show few of them."""
    n = images.shape[0]
    gain = 1.0 + 0.15 * (2 * torch.rand(n, 1, 1, 1, generator=generator) - 1)
    tint = 1.0 + 0.05 * (2 * torch.rand(n, 3, 1, 1, generator=generator) - 1)
    return (images.float() * gain * tint).clamp(0, 255).to(torch.uint8)


def check_shift(pixels: int, image_size: int) -> None:
    """A random shift must leave most of the view in place: fewer pixels than half its side."""
    if not 0 <= pixels < image_size // 2:
        raise ValueError(f"shift must be in [0, {image_size // 2}) pixels, got {pixels}")


def shift_views(images: torch.Tensor, pixels: int, generator: torch.Generator) -> torch.Tensor:
    """Each view moved by its own random (dx, dy) in [-pixels, pixels]; the edge pixels are
    repeated into the gap (DrQ's random shift). A 64 px view that shows a fruit 3 px wide at
    a slightly different place each epoch cannot be learned by its exact pixels."""
    if pixels <= 0:
        return images
    n, _, height, width = images.shape
    padded = F.pad(images.float(), (pixels, pixels, pixels, pixels), mode="replicate")
    dx = torch.randint(0, 2 * pixels + 1, (n,), generator=generator)
    dy = torch.randint(0, 2 * pixels + 1, (n,), generator=generator)
    rows = (dy[:, None] + torch.arange(height))[:, :, None]       # (n, H, 1)
    cols = (dx[:, None] + torch.arange(width))[:, None, :]        # (n, 1, W)
    moved = padded[torch.arange(n)[:, None, None], :, rows, cols]  # (n, H, W, C)
    return moved.permute(0, 3, 1, 2).to(images.dtype).contiguous()


def split(n: int, fraction: float, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """Trajectory indices for training and validation (a fixed random subset)."""
    n_val = int(round(n * fraction)) if n >= 20 else 0
    order = np.random.default_rng(seed).permutation(n)
    return np.sort(order[n_val:]), np.sort(order[:n_val])


def load_data(config: TrainConfig) -> list:
    """(root, trajectory) pairs. Whole trajectories are rebuilt from the lines, so the
    model's window need not be the one the data was written with."""
    loaded = []
    for index, path in enumerate(config.data):
        root = resolve_root(path)
        limit = config.limit(index)
        trajectories = read_trajectories(root, limit)
        if limit is not None and len(trajectories) < limit:
            raise DatasetError(f"{root} holds {len(trajectories)} trajectories, {limit} wanted: "
                               "collect more (legent-gym collect resumes the same run)")
        loaded += [(root, t) for t in trajectories]
    return loaded


@torch.no_grad()
def evaluate_loss(model: VLA, data: Encoded, ids: np.ndarray, per_batch: int) -> dict[str, float]:
    """Mean loss and how often the greedy template and bins match the expert's."""
    model.eval()
    device = next(model.parameters()).device
    total, n, template_hits, bin_hits, bin_n, seen_hits, seen_n = 0.0, 0, 0, 0, 0, 0, 0
    for batch in batches(data, ids, per_batch, rng=None):
        batch = {k: v.to(device) for k, v in batch.items()}
        out = model(**{k: v for k, v in batch.items() if not k.startswith("target")})
        loss, _ = model.loss(out, batch)
        size = len(batch["target_template"])
        total += loss.item() * size
        n += size
        template_hits += int((out["template"].argmax(-1) == batch["target_template"]).sum())
        present = batch["target_bins"] >= 0
        bin_hits += int((out["bins"].argmax(-1)[present] == batch["target_bins"][present]).sum())
        bin_n += int(present.sum())
        if "visible" in out:
            labelled = batch["target_visible"] >= 0
            seen_hits += int((out["visible"].argmax(-1)[labelled] == batch["target_visible"][labelled]).sum())
            seen_n += int(labelled.sum())
    metrics = {"loss": total / max(n, 1), "template_accuracy": template_hits / max(n, 1),
               "bin_accuracy": bin_hits / max(bin_n, 1)}
    if seen_n:
        metrics["visible_accuracy"] = seen_hits / seen_n
    return metrics


def train(config: TrainConfig, *, resume: bool = False, show_progress: bool = True,
          stop_after: int | None = None, epoch_lines: str | None = None) -> dict:
    """Train (or resume from ``last.pt``) and write ``model.pt``; returns the last epoch's
    metrics. ``stop_after`` ends this call after that epoch without writing ``model.pt``
    (a time-boxed share of a run that a later ``resume`` finishes). ``epoch_lines``: without
    a progress bar, still print one line per epoch, prefixed with this name (for runs in
    parallel processes, whose bars would garble each other)."""
    set_determinism(config.seed, config.threads, config.device)
    out = Path(config.out)
    out.mkdir(parents=True, exist_ok=True)
    started = time.monotonic()
    loaded = load_data(config)
    state = read_checkpoint(out / LAST) if resume and (out / LAST).is_file() else None
    if state is not None:
        if not config.matches(state.get("train_config")):
            raise ValueError(f"{out / LAST} was written by another configuration; use a new --out "
                             "or drop --resume")
        model, vocab = build_model(state)
    else:
        codec = ActionCodec.fit((a for _, t in loaded for a in (*t.labels, *t.actions)), bins=config.bins)
        vocab = WordVocab.fit(t.instruction for _, t in loaded)
        model = VLA(config.model, codec, len(vocab), vocab.max_words)
    data = encode(loaded, model.codec, vocab, config.model.window)
    side = data.images.shape[1]
    if data.images.shape[1:3] != (config.model.image_size, config.model.image_size):
        raise DatasetError(f"the views are {data.images.shape[2]}x{side} but the model takes "
                           f"{config.model.image_size}x{config.model.image_size}: collect with "
                           f"--width/--height {config.model.image_size} or set the image size")
    if config.model.aux_weight > 0 and not (data.target_visible >= 0).any():
        raise DatasetError("aux_weight > 0 needs goal_view labels, which this data lacks: collect it again "
                           "with legent-gym collect (its steps then hold goal_view)")
    train_ids, val_ids = split(len(data.traj_samples), config.validation_fraction, config.seed)
    steps_per_epoch = math.ceil(len(train_ids) / config.trajectories_per_batch)
    total_steps = steps_per_epoch * config.epochs
    model.to(config.device)
    optimizer = torch.optim.AdamW(model.parameters(), lr=config.lr, weight_decay=config.weight_decay)

    warmup = min(config.warmup_steps, total_steps // 2)

    def lr_at(step: int) -> float:  # linear warm-up, then cosine to 5 %
        if step < warmup:
            return (step + 1) / warmup
        progress = (step - warmup) / max(total_steps - warmup, 1)
        return 0.05 + 0.95 * 0.5 * (1 + math.cos(math.pi * min(progress, 1.0)))

    scheduler = torch.optim.lr_scheduler.LambdaLR(optimizer, lr_at)
    first_epoch = 0
    if state is not None:
        optimizer.load_state_dict(state["optimizer"])
        scheduler.load_state_dict(state["scheduler"])
        torch.set_rng_state(state["torch_rng"])
        first_epoch = state["epoch"]
    n_params = sum(p.numel() for p in model.parameters())
    if show_progress:
        print(f"VLA: {n_params / 1e6:.2f} M parameters; {len(train_ids)} training / {len(val_ids)} validation "
              f"trajectories, {data.n_samples} steps, {len(data.images)} views of {side}x{side}; "
              f"{model.codec.n_templates - 1} templates, {model.codec.n_speeches - 1} sentences")
    generator = torch.Generator().manual_seed(config.seed)
    metrics: dict = state.get("metrics", {}) if state is not None else {}
    last_epoch = config.epochs if stop_after is None else min(stop_after, config.epochs)
    for epoch in range(first_epoch, last_epoch):
        model.train()
        generator.manual_seed(config.seed * 1000 + epoch)
        rng = np.random.default_rng([config.seed, epoch])
        running, count = 0.0, 0
        mirror = mirror_slots(model.codec) if config.mirror else None
        bar = tqdm(batches(data, train_ids, config.trajectories_per_batch, rng, mirror), total=steps_per_epoch,
                   desc=f"epoch {epoch + 1}/{config.epochs}", unit="batch", disable=not show_progress,
                   leave=False)
        for batch in bar:
            if config.augment:
                batch["images"] = augment(batch["images"], generator)
            if config.shift:
                batch["images"] = shift_views(batch["images"], config.shift, generator)
            batch = {k: v.to(config.device, non_blocking=True) for k, v in batch.items()}
            out_ = model(**{k: v for k, v in batch.items() if not k.startswith("target")})
            loss, _ = model.loss(out_, batch)
            optimizer.zero_grad(set_to_none=True)
            loss.backward()
            torch.nn.utils.clip_grad_norm_(model.parameters(), 1.0)
            optimizer.step()
            scheduler.step()
            running += loss.item()
            count += 1
            bar.set_postfix(loss=f"{running / count:.3f}")
        metrics = {"epoch": epoch + 1, "train_loss": running / max(count, 1),
                   "seconds": round(time.monotonic() - started, 1)}
        if len(val_ids):
            metrics.update({f"val_{k}": v for k, v in
                            evaluate_loss(model, data, val_ids, config.trajectories_per_batch).items()})
        if show_progress or epoch_lines is not None:
            line = "  ".join(f"{k} {v:.4g}" if isinstance(v, float) else f"{k} {v}" for k, v in metrics.items())
            print(f"{epoch_lines}: {line}" if epoch_lines else line, flush=True)
        save_checkpoint(out / LAST, model, vocab, train_config=config.to_dict(), epoch=epoch + 1,
                        optimizer=optimizer.state_dict(), scheduler=scheduler.state_dict(),
                        torch_rng=torch.get_rng_state(), metrics=metrics)
        _append_log(out / LOG, metrics, fresh=epoch == 0)
    if last_epoch < config.epochs:
        return metrics
    metrics = {**metrics, "parameters": n_params, "trajectories": len(data.traj_samples),
               "steps": data.n_samples}
    save_checkpoint(out / FINAL, model, vocab, train_config=config.to_dict(), metrics=metrics)
    return metrics


def _append_log(path: Path, metrics: dict, fresh: bool) -> None:
    previous = "" if fresh or not path.is_file() else path.read_text()
    atomic_write_text(path, previous + json.dumps(metrics) + "\n", durable=False)


def parse_channels(text: str) -> tuple[int, ...]:
    """``--channels``: the image encoder's widths, e.g. ``"32,64,128,256"``."""
    try:
        return tuple(int(c) for c in text.split(","))
    except ValueError:
        raise ValueError(f"--channels must be comma-separated integers, got {text!r}") from None


def parse_args(argv: Sequence[str] | None = None) -> tuple[TrainConfig, argparse.Namespace]:
    p = argparse.ArgumentParser(description="Behaviour cloning of the VLA baseline on legent-gym collect data.")
    p.add_argument("--data", action="append", required=True,
                   help="a collect output (or its legent/ folder); repeat for joint training")
    p.add_argument("--out", required=True, help="folder for last.pt, model.pt and log.jsonl")
    p.add_argument("--trajectories", type=int, help="use the first N trajectories of each dataset")
    p.add_argument("--epochs", type=int, default=8)
    p.add_argument("--batch-trajectories", type=int, default=16, help="trajectories per batch")
    p.add_argument("--lr", type=float, default=1e-3)
    p.add_argument("--no-augment", action="store_true", help="no colour jitter")
    p.add_argument("--shift", type=int, default=0,
                   help="shift every training view by up to N pixels at random (0: none)")
    p.add_argument("--no-mirror", action="store_true", help="no left-right mirrored trajectories")
    p.add_argument("--image-size", type=int, default=64, help="must match the data's views")
    p.add_argument("--d-model", type=int, default=128)
    p.add_argument("--layers", type=int, default=3)
    p.add_argument("--channels", default="16,32,64,128",
                   help="the image encoder's convolution widths, comma-separated (each halves the view)")
    p.add_argument("--window", type=int, default=6, help="views the model reads (the paper: 6)")
    p.add_argument("--aux-weight", type=float, default=0.0,
                   help="weight of the auxiliary goal-view losses (0: none; needs goal_view labels in the data)")
    p.add_argument("--film", action="store_true",
                   help="condition the image encoder on the instruction (FiLM)")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--device", default="cpu", help="torch device to train on, e.g. cuda (default cpu)")
    p.add_argument("--threads", type=int, help="torch threads (fix it for bit-identical runs)")
    p.add_argument("--resume", action="store_true", help="continue from OUT/last.pt")
    p.add_argument("--quiet", action="store_true")
    args = p.parse_args(argv)
    channels = parse_channels(args.channels)
    model = ModelConfig(image_size=args.image_size, window=args.window, d_model=args.d_model,
                        layers=args.layers, channels=channels, aux_weight=args.aux_weight,
                        film=args.film)
    config = TrainConfig(tuple(os.fspath(d) for d in args.data), args.out, args.trajectories, args.epochs,
                         args.batch_trajectories, args.lr, augment=not args.no_augment, shift=args.shift, mirror=not args.no_mirror, seed=args.seed,
                         threads=args.threads, device=args.device, model=model)
    return config, args


def main(argv: Sequence[str] | None = None) -> int:
    try:
        config, args = parse_args(argv)
        metrics = train(config, resume=args.resume, show_progress=not args.quiet)
    except (DatasetError, ValueError, FileNotFoundError) as err:
        print(f"train: error: {err}", file=sys.stderr)
        return 2
    print(json.dumps(metrics))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

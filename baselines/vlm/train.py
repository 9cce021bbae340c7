"""Fine-tune a Hugging Face image-text-to-text model on LEGENT-format data (LoRA or full).

::

    python -m baselines.vlm.train --model Qwen/Qwen2-VL-2B-Instruct --data data/comehere \\
        --out runs/vlm-comehere --epochs 3 --batch-size 4 --grad-accum 4
    accelerate launch --multi_gpu --num_processes 4 -m baselines.vlm.train ...   # several GPUs

The samples are the lines of ``interleaved.jsonl`` (:mod:`baselines.vlm.data`), in the
model's chat template; the loss is the cross-entropy of the reply's tokens only, summed
over the tokens of all micro-batches of one optimizer step and divided by their number
(so gradient accumulation gives the gradient of one large batch). On a GPU the weights
are bfloat16 (LoRA's adapters float32, the forward pass under bfloat16 autocast); on the
CPU everything is float32. With several processes (``accelerate launch``) each takes
every n-th micro-batch and the gradients are averaged (DDP).

``OUT/last/`` holds the trainable weights (LoRA: the adapter; full: the model) and
``state.pt`` (optimizer, scheduler, step), written every ``--save-every`` optimizer
steps and when a run stops early (``--max-steps``); a second run of the same configuration resumes from
it (the data order depends on the seed and the epoch only, so a resumed run takes the
same batches). ``OUT/final/`` is the whole model with its processor and ``legent_vlm.json``
(the window, the view size, the configuration, the metrics): the base model reloaded in
the dtype it is stored in (float32 if training ran in float32) with the trained weights
put in (LoRA merged into it), so frozen weights are the base's exactly; what
``--policy vlm:OUT/final`` evaluates and an inference server loads.
"""

from __future__ import annotations

import argparse
import json
import shutil
import sys
import time
from collections.abc import Sequence
from dataclasses import asdict, dataclass, field, fields
from pathlib import Path
from typing import Any

if __package__ in (None, ""):  # run as a file: make `baselines` importable
    sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

import numpy as np
from tqdm import tqdm

from baselines.vla.dataset import DatasetError  # noqa: E402
from baselines.vlm.data import IGNORE, Encoder, image_size, load_image, read_samples  # noqa: E402
from baselines.vlm.model import (  # noqa: E402
    META_FILE,
    ModelError,
    check_source,
    load_model,
    load_processor,
    pick_dtype,
)
from legent_gym.utils.atomic import atomic_write_text  # noqa: E402

LAST, FINAL, STATE = "last", "final", "state.pt"
#: Where Hugging Face VLMs keep their vision encoder (LLaVA, Qwen2-VL, Idefics3/SmolVLM, ...).
VISION_NAMES = ("vision_tower", "visual.", "vision_model", "vision_encoder")


def _is_vision(name: str) -> bool:
    return any(part in name for part in VISION_NAMES) and "merger" not in name and "projector" not in name


@dataclass(frozen=True)
class FinetuneConfig:
    model: str                       # a model folder or hub id
    data: tuple[str, ...]            # dataset folders (collect output or its legent/ folder)
    out: str
    limit: int | None | tuple[int | None, ...] = None  # trajectories per folder (one for all, or one each)
    epochs: int = 3
    batch_size: int = 4              # samples per micro-batch (per process)
    grad_accum: int = 4              # micro-batches per optimizer step
    lr: float = 2e-4
    weight_decay: float = 0.0
    warmup: float = 0.03             # fraction of the optimizer steps with a linear warm-up
    lora: bool = True                # False: full fine-tuning
    lora_rank: int = 16
    lora_alpha: int = 32
    lora_dropout: float = 0.05
    lora_targets: str | tuple[str, ...] = "all-linear"  # peft's target_modules
    freeze_vision: bool = True       # keep the vision encoder as it is (LLaVA's and VILA's recipe)
    window: int | None = None        # views per sample (default: the data's)
    seed: int = 0
    save_every: int = 200            # optimizer steps between checkpoints
    dtype: str = "auto"              # auto (bf16 on GPU, fp32 on CPU), bf16, fp32
    threads: int | None = None       # torch CPU threads (None: torch's default); not part of the model
    extra: dict = field(default_factory=dict)  # free-form notes kept with the run

    def __post_init__(self) -> None:
        for name in ("epochs", "batch_size", "grad_accum", "save_every"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, int) or value < 1:
                raise ValueError(f"{name} must be a positive integer, got {value!r}")
        if not self.lr > 0:
            raise ValueError(f"lr must be positive, got {self.lr!r}")
        if not 0 <= self.warmup < 1:
            raise ValueError(f"warmup must be a fraction in [0, 1), got {self.warmup!r}")
        if self.lora and self.lora_rank < 1:
            raise ValueError(f"lora_rank must be >= 1, got {self.lora_rank}")
        if not self.data:
            raise ValueError("no data folders given")
        pick_dtype("cpu", self.dtype)

    def limits(self) -> list[int | None]:
        if isinstance(self.limit, tuple | list):
            if len(self.limit) != len(self.data):
                raise ValueError(f"{len(self.limit)} limits for {len(self.data)} data folders")
            return list(self.limit)
        return [self.limit] * len(self.data)

    def to_dict(self) -> dict[str, Any]:
        return json.loads(json.dumps(asdict(self)))

    def matches(self, other: dict[str, Any] | None) -> bool:
        """Whether ``other`` (a :meth:`to_dict`) trains the same model (``save_every`` and ``threads`` aside)."""
        if not isinstance(other, dict):
            return False
        mine = self.to_dict()
        return all(mine.get(f.name) == other.get(f.name) for f in fields(self) if f.name not in ("save_every", "threads"))


def _batches(n: int, config: FinetuneConfig, epoch: int, rank: int, world: int) -> list[list[list[int]]]:
    """The optimizer steps of one epoch on one process: lists of micro-batches of sample
    indices. The order depends on the seed and the epoch only."""
    order = np.random.default_rng([config.seed, epoch]).permutation(n).tolist()
    micro = [order[i:i + config.batch_size] for i in range(0, n, config.batch_size)]
    mine = micro[rank::world] if len(micro) >= world else micro[: 1]
    return [mine[i:i + config.grad_accum] for i in range(0, len(mine), config.grad_accum)]


def _replace_dir(tmp: Path, final: Path) -> None:
    """Put ``tmp`` at ``final``, so that ``final`` is the old or the new folder, never half."""
    old = final.with_name(final.name + ".old")
    if old.exists():
        shutil.rmtree(old)
    if final.exists():
        final.rename(old)
    tmp.rename(final)
    if old.exists():
        shutil.rmtree(old)


def train(config: FinetuneConfig, resume: bool = True, show_progress: bool = True,
          max_steps: int | None = None) -> dict[str, Any]:
    """Fine-tune; returns the metrics (also in ``OUT/final/legent_vlm.json``).

    ``resume``: continue from ``OUT/last`` when it was written by the same configuration.
    ``max_steps``: stop (with a checkpoint in ``OUT/last``, no ``final``) after that many
    optimizer steps in all, e.g. to split a run over several jobs.
    Raises :class:`ModelError` or :class:`DatasetError` (both ``ValueError``) with one line
    naming what is wrong.
    """
    # the vlm extra's libraries take seconds to import: only when a model is made or run
    import torch
    from accelerate import Accelerator
    from transformers import get_linear_schedule_with_warmup
    from transformers.utils import logging as hf_logging

    if not show_progress:
        hf_logging.disable_progress_bar()

    source = check_source(config.model)
    samples = read_samples(config.data, config.limits(), config.window)
    width, height = image_size(samples)
    out = Path(config.out)
    cuda = torch.cuda.is_available()
    dtype = pick_dtype("cuda" if cuda else "cpu", config.dtype)
    bf16 = dtype == torch.bfloat16
    # bfloat16 autocast is torch's own (below), not Accelerator(mixed_precision=...): accelerate
    # keeps that setting process-wide and refuses a second run in another dtype.
    accelerator = Accelerator(cpu=not cuda, mixed_precision="no")
    rank, world = accelerator.process_index, accelerator.num_processes
    if config.threads is not None:
        torch.set_num_threads(config.threads)
    torch.manual_seed(config.seed)

    processor = load_processor(source)
    encoder = Encoder(processor)
    encoder.reply(samples[0])  # fails now, with the template's fault, not after loading the weights
    state_path = out / LAST / STATE
    state = None
    if resume and state_path.is_file():
        state = torch.load(state_path, map_location="cpu", weights_only=False)
        if not config.matches(state.get("config")):
            raise ValueError(f"{out / LAST} was written by another configuration: use another --out, or "
                             "--no-resume to start afresh")
    if state is not None and not config.lora:
        model = load_model(str(out / LAST), dtype)
    else:
        model = load_model(source, dtype)
    if config.lora:
        # the vlm extra's libraries take seconds to import: only when a model is made or run
        from peft import LoraConfig, PeftModel, get_peft_model

        if state is not None:
            model = PeftModel.from_pretrained(model, str(out / LAST), is_trainable=True)
        else:
            targets = config.lora_targets if isinstance(config.lora_targets, str) else list(config.lora_targets)
            model = get_peft_model(model, LoraConfig(r=config.lora_rank, lora_alpha=config.lora_alpha,
                                                     lora_dropout=config.lora_dropout, target_modules=targets))
    model.config.use_cache = False
    if config.freeze_vision:
        frozen = [p for name, p in model.named_parameters() if _is_vision(name)]
        if not frozen:
            raise ValueError("freeze_vision: no vision encoder parameters found (names with "
                             f"{', '.join(VISION_NAMES)}); pass --train-vision")
        for p in frozen:
            p.requires_grad_(False)
    params = [p for p in model.parameters() if p.requires_grad]
    optimizer = torch.optim.AdamW(params, lr=config.lr, weight_decay=config.weight_decay)
    steps_per_epoch = len(_batches(len(samples), config, 0, rank, world))
    total = steps_per_epoch * config.epochs
    scheduler = get_linear_schedule_with_warmup(optimizer, int(config.warmup * total), total)
    model, optimizer = accelerator.prepare(model, optimizer)
    step = 0
    if state is not None:
        optimizer.load_state_dict(state["optimizer"])
        scheduler.load_state_dict(state["scheduler"])
        torch.set_rng_state(state["rng"])
        step = int(state["step"])

    def save_last() -> None:
        if not accelerator.is_main_process:
            return
        tmp = out / (LAST + ".tmp")
        if tmp.exists():
            shutil.rmtree(tmp)
        accelerator.unwrap_model(model).save_pretrained(tmp)
        torch.save({"config": config.to_dict(), "step": step, "optimizer": optimizer.state_dict(),
                    "scheduler": scheduler.state_dict(), "rng": torch.get_rng_state()}, tmp / STATE)
        _replace_dir(tmp, out / LAST)

    out.mkdir(parents=True, exist_ok=True)
    model.train()
    started, start_step = time.monotonic(), step
    tokens = correct = 0
    loss_sum = 0.0
    bar = tqdm(total=total, initial=step, unit="step", disable=not show_progress or not accelerator.is_main_process,
               desc=f"fine-tuning {Path(source).name}")
    stop = total if max_steps is None else min(total, max_steps)
    for epoch in range(step // steps_per_epoch, config.epochs):
        tokens = correct = 0
        loss_sum = 0.0
        for group in _batches(len(samples), config, epoch, rank, world)[step % steps_per_epoch:]:
            if step >= stop:
                break
            batches = [encoder.batch([samples[i] for i in micro], [[load_image(p) for p in samples[i].images]
                                                                  for i in micro]) for micro in group]
            n_target = sum(int((b["labels"] != IGNORE).sum()) for b in batches)
            group_loss = 0.0
            for k, batch in enumerate(batches):
                labels = batch.pop("labels").to(accelerator.device)
                inputs = {key: value.to(accelerator.device) for key, value in batch.items()}
                sync = k == len(batches) - 1
                context = accelerator.no_sync(model) if not sync else _null()
                with context, torch.autocast(accelerator.device.type, dtype=torch.bfloat16, enabled=bf16):
                    logits = model(**inputs).logits[:, :-1].float()
                    target = labels[:, 1:]
                    loss = torch.nn.functional.cross_entropy(logits.reshape(-1, logits.shape[-1]),
                                                             target.reshape(-1), ignore_index=IGNORE,
                                                             reduction="sum") / max(n_target, 1)
                    accelerator.backward(loss)
                group_loss += float(loss.detach())
                picked = target != IGNORE
                correct += int((logits.argmax(-1)[picked] == target[picked]).sum())
            tokens += n_target
            loss_sum += group_loss * n_target
            optimizer.step()
            scheduler.step()
            optimizer.zero_grad(set_to_none=True)
            step += 1
            bar.update(1)
            bar.set_postfix(loss=f"{group_loss:.3f}", epoch=epoch + 1)
            if step % config.save_every == 0 and step < total:
                save_last()
        if step >= stop:
            break
    bar.close()
    seconds = time.monotonic() - started
    metrics = {"steps": step, "epochs": config.epochs, "samples": len(samples), "processes": world,
               "loss": loss_sum / max(tokens, 1), "token_accuracy": correct / max(tokens, 1),
               "seconds": round(seconds, 2), "steps_per_second": round((step - start_step) / max(seconds, 1e-9), 3),
               "trainable_parameters": sum(p.numel() for p in params),
               "parameters": sum(p.numel() for p in accelerator.unwrap_model(model).parameters())}
    if step < total:
        save_last()
        accelerator.wait_for_everyone()
        return {**metrics, "finished": False}
    accelerator.wait_for_everyone()
    if accelerator.is_main_process:
        final = _final_model(accelerator.unwrap_model(model), source, dtype, config.lora)
        final.config.use_cache = True
        tmp = out / (FINAL + ".tmp")
        if tmp.exists():
            shutil.rmtree(tmp)
        final.save_pretrained(tmp)
        processor.save_pretrained(tmp)
        meta = {"window": max(len(s.images) for s in samples), "width": width, "height": height,
                "base_model": source, "config": config.to_dict(), "metrics": {**metrics, "finished": True}}
        atomic_write_text(tmp / META_FILE, json.dumps(meta, indent=1))
        _replace_dir(tmp, out / FINAL)
    return {**metrics, "finished": True}


def _final_model(trained: Any, source: str, dtype: Any, lora: bool) -> Any:
    """The model ``OUT/final`` holds: the base model loaded afresh in the dtype it is stored
    in (float32 if training ran in float32), with the trained weights put into it (LoRA:
    the adapter merged into it). The weights training did not touch (a frozen vision
    encoder) are the base's bit for bit: writing the bfloat16 training copy instead would
    round every weight of a float32 base, and merging into it would add the adapter to
    rounded weights."""
    # the vlm extra's libraries take seconds to import: only when a model is made or run
    import torch

    base = load_model(source, "auto")
    if dtype == torch.float32 and base.dtype != torch.float32:
        base = base.float()
    if lora:
        # the vlm extra's libraries take seconds to import: only when a model is made or run
        from peft import get_peft_model, get_peft_model_state_dict, set_peft_model_state_dict

        merged = get_peft_model(base, trained.peft_config["default"])
        loaded: Any = set_peft_model_state_dict(merged, get_peft_model_state_dict(trained))
        if loaded.unexpected_keys:
            raise RuntimeError(f"the adapter does not fit the base model: {loaded.unexpected_keys[:3]}")
        return merged.merge_and_unload()
    weights = dict(trained.named_parameters())
    with torch.no_grad():
        for name, param in base.named_parameters():
            if weights[name].requires_grad:
                param.copy_(weights[name])
    return base


class _null:
    def __enter__(self) -> None:
        return None

    def __exit__(self, *exc: object) -> None:
        return None


def trained(config: FinetuneConfig) -> bool:
    """Whether ``OUT/final`` holds a model this configuration finished."""
    path = Path(config.out) / FINAL / META_FILE
    try:
        return config.matches(json.loads(path.read_text()).get("config"))
    except (OSError, ValueError):
        return False


def main(argv: Sequence[str] | None = None) -> int:
    p = argparse.ArgumentParser(description="Fine-tune a Hugging Face image-text-to-text model on "
                                            "legent-gym collect --format legent data.")
    p.add_argument("--model", required=True, help="a model folder, or a hub id (downloaded by from_pretrained)")
    p.add_argument("--data", nargs="+", required=True, help="dataset folders (collect --out or its legent/)")
    p.add_argument("--out", required=True, help="output folder: last/ (resume), final/ (the model)")
    p.add_argument("--limit", type=int, help="the first N trajectories of each folder")
    p.add_argument("--epochs", type=int, default=3)
    p.add_argument("--batch-size", type=int, default=4, help="samples per micro-batch and process")
    p.add_argument("--grad-accum", type=int, default=4, help="micro-batches per optimizer step")
    p.add_argument("--lr", type=float, default=None, help="learning rate (default 2e-4 with LoRA, 1e-5 full)")
    p.add_argument("--full", action="store_true", help="full fine-tuning instead of LoRA")
    p.add_argument("--lora-rank", type=int, default=16)
    p.add_argument("--lora-alpha", type=int, default=32)
    p.add_argument("--lora-dropout", type=float, default=0.05)
    p.add_argument("--window", type=int, help="views per sample (default: the data's, 6 for collect's default)")
    p.add_argument("--save-every", type=int, default=200, help="optimizer steps between checkpoints")
    p.add_argument("--dtype", choices=["auto", "bf16", "fp32"], default="auto")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--max-steps", type=int, help="stop after N optimizer steps in all (resumable)")
    p.add_argument("--no-resume", action="store_true", help="start afresh even if OUT/last exists")
    args = p.parse_args(argv)
    try:
        config = FinetuneConfig(args.model, tuple(args.data), args.out, args.limit, args.epochs, args.batch_size,
                                args.grad_accum, args.lr or (1e-5 if args.full else 2e-4), lora=not args.full,
                                lora_rank=args.lora_rank, lora_alpha=args.lora_alpha,
                                lora_dropout=args.lora_dropout, window=args.window, seed=args.seed,
                                save_every=args.save_every, dtype=args.dtype)
        if not args.no_resume and trained(config):
            print(f"{Path(config.out) / FINAL} already holds this configuration's model")
            return 0
        metrics = train(config, resume=not args.no_resume, max_steps=args.max_steps)
    except (ModelError, DatasetError, ValueError, FileNotFoundError) as err:
        print(f"vlm.train: error: {err}", file=sys.stderr)
        return 2
    print(json.dumps(metrics))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

"""The paper's Table 3 with a fine-tuned Hugging Face VLM in place of the compact VLA.

``python baselines/reproduce_table.py --scale large --model vlm:PATH`` collects the same
data, fine-tunes the model at PATH (a folder or hub id) once per Sep set and once on the
joint set (:mod:`baselines.vlm.train`, LoRA, the defaults of :class:`FinetuneConfig`),
and evaluates every fine-tuned model through ``vlm:OUT/vlm/<run>/final`` on the same
seeded episodes as the VLA rows. A run whose ``final`` was written by the same
configuration is not trained again; an interrupted one resumes from its ``last``.
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from pathlib import Path

from baselines.vlm.model import check_source
from baselines.vlm.policy import PREFIX
from baselines.vlm.train import FINAL, FinetuneConfig, train, trained


def base_model(spec: str) -> str:
    """The model of ``vlm:PATH`` (checked: :class:`~baselines.vlm.model.ModelError` if it is not one)."""
    if not spec.startswith(PREFIX):
        raise ValueError(f"--model must be vlm:PATH (a model folder or hub id), got {spec!r}")
    return check_source(spec[len(PREFIX):])


def training_runs(root: Path, folders: dict[str, Path], tasks: Sequence[str], small: int, large: int,
                  model: str, epochs: int) -> dict[str, FinetuneConfig]:
    """Run name -> configuration: Sep on the small and the large amount of each task, Joint
    on the large amounts of all."""
    # the vlm extra's libraries take seconds to import: only when a model is made or run
    import torch

    threads = None if torch.cuda.is_available() else 1  # as the VLA's runs: one thread, the same weights
    runs = {}
    for amount in (small, large):
        for task in tasks:
            name = f"sep{amount}-{task}"
            runs[name] = FinetuneConfig(model, (str(folders[task]),), str(root / "vlm" / name), amount, epochs,
                                        threads=threads)
    name = f"joint{large}"
    runs[name] = FinetuneConfig(model, tuple(str(folders[t]) for t in tasks), str(root / "vlm" / name), large,
                                epochs, threads=threads)
    return runs


def train_models(runs: dict[str, FinetuneConfig], log) -> dict[str, dict]:
    """Fine-tune what is not fine-tuned yet, one model at a time (each takes the GPU)."""
    metrics = {}
    for name, config in runs.items():
        if trained(config):
            log(f"vlm {name}: already fine-tuned")
            metrics[name] = json.loads((Path(config.out) / FINAL / "legent_vlm.json").read_text())["metrics"]
            continue
        log(f"fine-tuning vlm {name}")
        metrics[name] = train(config, show_progress=False)
        log(f"fine-tuned vlm {name}: {json.dumps(metrics[name])}")
    return metrics


def table_rows(root: Path, small: int, large: int, eval_tasks: Sequence[str], sep_model_for: dict[str, str],
               amount_label, random: str, expert: str) -> list[tuple[str, dict[str, str]]]:
    """(row label, eval task -> policy spec), the VLA table's rows with the VLM's models."""
    runs = root / "vlm"
    rows = [("Random", dict.fromkeys(eval_tasks, random))]
    for amount in (small, large):
        rows.append((f"VLM-Sep {amount_label(amount)} (ours)",
                     {t: PREFIX + str(runs / f"sep{amount}-{sep_model_for[t]}" / FINAL) for t in eval_tasks}))
    rows.append((f"VLM-Joint {amount_label(large)} (ours)",
                 dict.fromkeys(eval_tasks, PREFIX + str(runs / f"joint{large}" / FINAL))))
    rows.append(("Expert (privileged)", dict.fromkeys(eval_tasks, expert)))
    return rows

"""The paper's Table 3, end to end: data, behaviour cloning, evaluation, the table.

::

    python baselines/reproduce_table.py --scale small    # every phase in under a minute (CI)
    python baselines/reproduce_table.py --scale medium   # 100 / 1K trajectories per task
    python baselines/reproduce_table.py --scale large    # 1K / 3K
    python baselines/reproduce_table.py --scale full     # the paper's 1K / 10K

1. **data**: ``legent-gym collect`` of the expert on the three training tasks (Come Here in
   one and two rooms, Where Is in one room), LEGENT format; the smaller training sets are
   prefixes of the larger (collection order depends on the seed alone).
2. **training**: the VLA (:mod:`baselines.vla`) per task on the small and the large sets
   ("Sep") and one model on the three large sets together ("Joint").
3. **evaluation**: every model, a random policy and the privileged expert on the same
   seeded episodes of the four tasks (Where Is in two rooms is never trained on; the Sep
   row uses the Where Is model there). Evaluation reset seeds ``0 .. E-1`` are disjoint
   from the data's (``>= 10,000,000``); the house seeds of both are also compared and the
   overlap is reported.
4. **table**: ``table.md`` (the paper's layout, the paper's rows next to ours),
   ``table.csv``, ``table.png`` (bars), and ``results.json`` with every episode, the
   configuration and the wall time of each phase.

``--model vlm:PATH`` fine-tunes a Hugging Face VLM (a folder or hub id) in place of
training the VLA, as the paper fine-tuned VILA: the same data, Sep and Joint runs and
evaluation (:mod:`baselines.vlm.table`; models in ``vlm/<run>/final``; ``docs/vlm.md``).

Every phase resumes: collect tops up its folder, a model whose ``model.pt`` was written by
the same configuration is not trained again. Same scale and seeds, same table.

``--backend ray`` (``--ray-address auto|HOST:PORT``; default: a Ray started on this machine)
runs the collections, the training runs and the evaluation as Ray tasks, ``--workers`` at
a time (the DAgger rollouts stay in worker processes here); a Ray started here serves every
phase, the collections' subprocesses join it. The table does not depend on the backend
(tested at scale small: the same weights, episodes and table). See ``docs/scale.md``.

``--perturb P`` goes beyond the paper's recipe (off by default, so the default table is
the paper's protocol): recovery data. The training sets are collected with ``legent-gym
  collect --perturb P``: with probability P per step a random move or turn is executed in
  place of the expert's action and the expert, replanning from where it left the agent,
  labels that state. Clean demonstrations never show the states a cloned policy drifts
  into (pressed against furniture, the object not yet in sight), so the model never learns
  to get out of them. The data goes to ``data/<task>-perturb<P>``.

``--scan`` (also beyond the paper) collects Where Is with ``--find-strategy scan``: the
expert looks around in place (right turns of 60 degrees) until the object is in view
before it answers, instead of turning straight to an object the image does not show yet.
The data goes to ``data/WhereIs-OneRoom-scan`` (with ``-perturb<P>`` after it).

``--paper-where-is`` asks Where Is LEGENT's questions (its data's four objects, orange,
apple, banana and cola, on its five receptacle kinds; ``legent_gym.tasks.PAPER_WHERE_IS``)
in the data and in both Where Is columns, instead of any small object on any receptacle.
The data goes to ``data/WhereIs-OneRoom-paper`` (then ``-scan``, ``-perturb<P>``).

``--dagger`` (beyond the paper) adds a row: one DAgger round on each Sep model of the large
amount (:mod:`baselines.vla.dagger`). The model drives ``Scale.dagger`` rollouts of its
training task (seeds ``20,000,000 + i * 1,000,000 + k``, disjoint from the data and the
evaluation), the expert labels every state it reached, and a model is trained from scratch
on the large set plus these rollouts (``models/sep<N>-<task>-dagger``). The rollouts go to
``data/<task>-dagger-from-sep<N>`` (Where Is with ``--paper-where-is``:
``data/WhereIs-OneRoom-paper-dagger-from-sep<N>``, rolled out on LEGENT's questions).
"""

from __future__ import annotations

import argparse
import csv
import io
import json
import os
import subprocess
import sys
import time
from collections.abc import Sequence
from dataclasses import asdict, dataclass, replace
from pathlib import Path

if __package__ in (None, ""):  # run as a script: make `baselines` importable
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from baselines.vla.checkpoint import read_checkpoint  # noqa: E402
from baselines.vla.evaluate import EXPERT, RANDOM, evaluate_many, success_rate  # noqa: E402
from baselines.vla.model import ModelConfig  # noqa: E402
from baselines.vla.train import FINAL, LAST, TrainConfig, check_shift, parse_channels, train  # noqa: E402
from legent_gym.data.collect import PROGRESS_FILE
from legent_gym.tasks import PAPER_WHERE_IS, WhereIs, task_class  # noqa: E402
from legent_gym.utils.atomic import atomic_write_bytes, atomic_write_text  # noqa: E402
from legent_gym.utils.scale import Backend, connect_ray  # noqa: E402
from legent_gym.utils.workers import map_ordered  # noqa: E402

TRAIN_TASKS = ("ComeHere-OneRoom", "ComeHere-TwoRoom", "WhereIs-OneRoom")
EVAL_TASKS = ("ComeHere-OneRoom", "ComeHere-TwoRoom", "WhereIs-OneRoom", "WhereIs-TwoRoom")
#: The Sep model that answers each evaluation task (Where Is in two rooms: the Where Is model).
SEP_MODEL_FOR = {"ComeHere-OneRoom": "ComeHere-OneRoom", "ComeHere-TwoRoom": "ComeHere-TwoRoom",
                 "WhereIs-OneRoom": "WhereIs-OneRoom", "WhereIs-TwoRoom": "WhereIs-OneRoom"}
#: Collection seeds: attempt k of task i resets with DATA_SEED + i * DATA_SEED_STRIDE + k.
DATA_SEED, DATA_SEED_STRIDE = 10_000_000, 1_000_000
#: DAgger rollout seeds: rollout k on task i resets with DAGGER_SEED + i * DATA_SEED_STRIDE + k.
DAGGER_SEED = 20_000_000
#: Worker processes on this machine (``--backend ray``: Ray tasks, see ``docs/scale.md``).
PROCESS = Backend()
COLUMNS = ("Come Here, one room", "Come Here, two rooms", "Where Is, one room", "Where Is, two rooms*")

#: The paper's Table 3 (success rates on 100 episodes per task).
PAPER_ROWS = (
    ("GPT-4V (zero-shot)", (0.21, 0.17, 0.25, 0.22)),
    ("VILA-7B-Sep 1K", (0.87, 0.28, 0.30, 0.22)),
    ("VILA-7B-Sep 10K", (0.96, 0.70, 0.94, 0.52)),
    ("VILA-7B-Joint", (0.96, 0.70, 0.92, 0.65)),
)


@dataclass(frozen=True)
class Scale:
    image_size: int
    small: int            # trajectories per task, the "Sep 1K" row
    large: int            # trajectories per task, the "Sep 10K" and "Joint" rows
    epochs_small: int
    epochs_large: int
    episodes: int         # evaluation episodes per task and row
    d_model: int = 128
    layers: int = 3
    channels: tuple[int, ...] = (16, 32, 64, 128)  # the image encoder's widths
    film: bool = False    # the image encoder conditioned on the instruction (``--film``)
    shift: int = 0        # random shift of training views, in pixels (``--shift``)
    dagger: int = 0       # DAgger rollouts per task (``--dagger``); 0: the large amount / 5

    @property
    def dagger_rollouts(self) -> int:
        return self.dagger or max(1, self.large // 5)


SCALES = {
    # CI (the default test suite runs it): every phase, in about a minute on 2 cores; trained
    # enough that the Sep and Joint models together beat the random policy on their training
    # tasks (tests/baselines/test_reproduce_table.py); 10 episodes a task say little more.
    "small": Scale(image_size=48, small=10, large=20, epochs_small=6, epochs_large=16, episodes=10, d_model=64,
                   layers=2, dagger=6),
    # The paper's data / 10: 12 minutes on the shared 2-core machine.
    "medium": Scale(image_size=64, small=100, large=1000, epochs_small=40, epochs_large=15, episodes=100),
    # The paper's 1K, and 3K in place of its 10K: 21 minutes on the shared 2-core machine
    # (3-4 times that while other jobs loaded it).
    "large": Scale(image_size=64, small=1000, large=3000, epochs_small=15, epochs_large=10, episodes=100),
    # The paper's amounts: 1K and 10K trajectories per task (about 50 minutes, estimated).
    "full": Scale(image_size=64, small=1000, large=10000, epochs_small=10, epochs_large=6, episodes=100),
}


def _amount(n: int) -> str:
    return f"{n // 1000}K" if n >= 1000 and n % 1000 == 0 else str(n)


def log(message: str) -> None:
    print(f"[{time.strftime('%H:%M:%S')}] {message}", flush=True)


# -- 1. data ---------------------------------------------------------------------------------
def collect_command(task: str, index: int, episodes: int, out: Path, scale: Scale, workers: int,
                    perturb: float = 0.0, scan: bool = False, paper_where_is: bool = False,
                    backend: Backend = PROCESS) -> list[str]:
    command = [sys.executable, "-m", "legent_gym.cli", "collect", f"Legent/{task}-v0", "--episodes", str(episodes),
               "--out", str(out), "--format", "legent", "--workers", str(workers),
               "--seed", str(DATA_SEED + index * DATA_SEED_STRIDE), "--width", str(scale.image_size),
               "--height", str(scale.image_size), "--quiet"]
    if perturb:
        command += ["--perturb", repr(perturb)]
    if backend.kind != "process":
        command += ["--backend", backend.kind] + (["--ray-address", backend.address] if backend.address else [])
    if scans(task, scan):
        command += ["--find-strategy", "scan"]
    env_kwargs = task_env_kwargs(task, paper_where_is)
    if env_kwargs:
        command += ["--env-kwargs", json.dumps(env_kwargs)]
    return command


def task_options(task: str, paper_where_is: bool) -> dict:
    """The ``task_options`` of this task's envs (data and evaluation alike): LEGENT's
    questions (:data:`PAPER_WHERE_IS`) are WhereIs's options."""
    if paper_where_is and issubclass(task_class(task.split("-")[0]), WhereIs):
        return {name: list(categories) for name, categories in PAPER_WHERE_IS.items()}
    return {}


def task_env_kwargs(task: str, paper_where_is: bool) -> dict:
    """The ``gym.make`` arguments the task adds (``task_options``; none by default)."""
    options = task_options(task, paper_where_is)
    return {"task_options": options} if options else {}


def _paper(task: str, paper_where_is: bool) -> str:
    """The folder-name mark of data asked with LEGENT's questions."""
    return "-paper" if task_options(task, paper_where_is) else ""


def scans(task: str, scan: bool) -> bool:
    """Whether ``--scan`` changes this task's expert (only code that calls ``find``: Where Is)."""
    return scan and "find(" in task_class(task.split("-")[0]).code


def data_folder(root: Path, task: str, perturb: float = 0.0, scan: bool = False, paper_where_is: bool = False) -> Path:
    """``data/<task>``, with ``-paper`` for LEGENT's Where Is questions, ``-scan`` for a
    scanning expert and ``-perturb<P>`` for recovery data."""
    name = (task + _paper(task, paper_where_is) + ("-scan" if scans(task, scan) else "")
            + (f"-perturb{perturb!r}" if perturb else ""))
    return root / "data" / name


def collect_data(root: Path, scale: Scale, workers: int, perturb: float = 0.0, scan: bool = False,
                 paper_where_is: bool = False, backend: Backend = PROCESS) -> dict[str, Path]:
    folders = {}
    for index, task in enumerate(TRAIN_TASKS):
        folder = data_folder(root, task, perturb, scan, paper_where_is)
        command = collect_command(task, index, scale.large, folder, scale, workers, perturb, scan, paper_where_is,
                                  backend)
        log(" ".join(["legent-gym", *command[3:]]))
        done = subprocess.run(command, capture_output=True, text=True)
        if done.returncode != 0:
            raise RuntimeError(f"collect failed for {task}:\n{done.stdout}{done.stderr}")
        log(done.stdout.strip().splitlines()[-1] if done.stdout.strip() else f"collected {task}")
        folders[task] = folder
    return folders


def collection_summary(folders: dict[str, Path]) -> dict[str, dict]:
    """Per task, what its data folder holds (``progress.json`` of ``legent-gym collect``):
    trajectories kept, failed expert attempts skipped, steps."""
    out = {}
    for task, folder in folders.items():
        progress = json.loads((folder / PROGRESS_FILE).read_text())["progress"]
        out[task] = {"trajectories": progress["committed"], "failed_attempts": progress["failures"],
                     "steps": progress["total_steps"]}
    return out


def data_house_seeds(folders: dict[str, Path], limit: int) -> set[int]:
    seeds = set()
    for folder in folders.values():
        trajectories = json.loads((folder / "legent" / "trajectories.json").read_text())
        seeds.update(int(t["house_seed"]) for t in trajectories[:limit] if t.get("house_seed") is not None)
    return seeds


# -- 2. training -----------------------------------------------------------------------------
def model_config(scale: Scale) -> ModelConfig:
    """The VLA every model of a scale is."""
    return ModelConfig(image_size=scale.image_size, d_model=scale.d_model, layers=scale.layers,
                       channels=scale.channels, film=scale.film)


def training_runs(root: Path, folders: dict[str, Path], scale: Scale) -> dict[str, TrainConfig]:
    """Model name -> its training configuration."""
    model = model_config(scale)
    runs = {}
    for amount, epochs in ((scale.small, scale.epochs_small), (scale.large, scale.epochs_large)):
        for task in TRAIN_TASKS:
            name = f"sep{amount}-{task}"
            runs[name] = TrainConfig((str(folders[task]),), str(root / "models" / name), amount, epochs,
                                     shift=scale.shift, threads=1, model=model)
    name = f"joint{scale.large}"
    runs[name] = TrainConfig(tuple(str(folders[t]) for t in TRAIN_TASKS), str(root / "models" / name),
                             scale.large, scale.epochs_large, shift=scale.shift, threads=1, model=model)
    return runs


def dagger_folder(root: Path, task: str, scale: Scale, paper_where_is: bool = False) -> Path:
    return root / "data" / f"{task}{_paper(task, paper_where_is)}-dagger-from-sep{scale.large}"


def collect_dagger_data(root: Path, scale: Scale, workers: int, scan: bool = False,
                        paper_where_is: bool = False) -> tuple[dict[str, Path], dict[str, dict]]:
    """One DAgger round per training task: the large Sep model drives, the expert labels
    (on the task its data asked: with ``paper_where_is``, LEGENT's Where Is questions).
    Returns the rollout folders and, per task, the round's summary (episodes, the learner's
    success, labelled steps, seconds)."""
    # start-up time: imported by the stage that runs it
    from baselines.vla.dagger import DaggerConfig, collect_dagger

    folders, summaries = {}, {}
    for index, task in enumerate(TRAIN_TASKS):
        folder = dagger_folder(root, task, scale, paper_where_is)
        config = DaggerConfig(str(root / "models" / f"sep{scale.large}-{task}" / FINAL), f"Legent/{task}-v0",
                              str(folder), scale.dagger_rollouts, DAGGER_SEED + index * DATA_SEED_STRIDE,
                              workers, "scan" if scans(task, scan) else "direct",
                              task_env_kwargs(task, paper_where_is))
        log(f"dagger {task}: {config.episodes} rollouts of sep{scale.large}-{task}")
        summary = collect_dagger(config, show_progress=False)
        log(f"dagger {task}: learner success {summary['learner_success']:.2f}, {summary['steps']} steps, "
            f"{summary['seconds']:.0f} s")
        folders[task] = folder
        summaries[task] = {k: summary[k] for k in ("episodes", "learner_success", "steps", "seconds")}
    return folders, summaries


def dagger_runs(root: Path, folders: dict[str, Path], dagger: dict[str, Path], scale: Scale) -> dict[str, TrainConfig]:
    """The DAgger models: the large set plus the rollouts of the large Sep model."""
    model = model_config(scale)
    runs = {}
    for task in TRAIN_TASKS:
        name = f"sep{scale.large}-{task}-dagger"
        runs[name] = TrainConfig((str(folders[task]), str(dagger[task])), str(root / "models" / name),
                                 (scale.large, None), scale.epochs_large, shift=scale.shift, threads=1,
                                 model=model)
    return runs


def _size(config: TrainConfig) -> int:
    """Roughly the work of a training run (to start the biggest first)."""
    limits = [config.limit(i) or 0 for i in range(len(config.data))]
    return sum(limits) * config.epochs


def _trained(config: TrainConfig) -> bool:
    path = Path(config.out) / FINAL
    if not path.is_file():
        return False
    try:
        return config.matches(read_checkpoint(path).get("train_config"))
    except (ValueError, OSError, RuntimeError):
        return False


def _train_one(config: TrainConfig) -> dict:
    # Resume an interrupted run of this configuration; start afresh over any other.
    last = Path(config.out) / LAST
    try:
        resume = config.matches(read_checkpoint(last).get("train_config"))
    except (FileNotFoundError, ValueError, RuntimeError):
        resume = False
    return train(config, resume=resume, show_progress=False, epoch_lines=f"  {Path(config.out).name}")


def train_models(runs: dict[str, TrainConfig], workers: int, backend: Backend = PROCESS) -> dict[str, dict]:
    """Train what is not trained yet, ``workers`` models at a time (one torch thread each,
    so the weights do not depend on ``workers``)."""
    todo = {name: config for name, config in runs.items() if not _trained(config)}
    for name in runs:
        if name not in todo:
            log(f"model {name}: already trained")
    metrics = {}
    if (workers == 1 or len(todo) <= 1) and backend.kind == "process":
        for name, config in todo.items():
            log(f"training {name}")
            metrics[name] = _train_one(config)
            log(f"trained {name}: {json.dumps(metrics[name])}")
    else:
        # The biggest runs first, so the two workers finish together.
        order = sorted(todo, key=lambda n: -_size(todo[n]))
        # All handed out at once: a free worker takes the next run whatever the first is doing.
        trained = map_ordered(_train_one, [(todo[name],) for name in order], workers=workers,
                              ahead=len(order), backend=backend)
        for name, result in zip(order, trained, strict=True):
            metrics[name] = result
            log(f"trained {name}: {json.dumps(metrics[name])}")
    for name, config in runs.items():
        if name not in metrics:
            metrics[name] = read_checkpoint(Path(config.out) / FINAL).get("metrics", {})
    return metrics


# -- 3. evaluation ---------------------------------------------------------------------------
def table_rows(root: Path, scale: Scale, dagger: bool = False) -> list[tuple[str, dict[str, str]]]:
    """(row label, eval task -> policy spec) in the table's order."""
    models = root / "models"
    rows = [("Random", dict.fromkeys(EVAL_TASKS, RANDOM))]
    for amount in (scale.small, scale.large):
        rows.append((f"VLA-Sep {_amount(amount)} (ours)",
                     {t: str(models / f"sep{amount}-{SEP_MODEL_FOR[t]}" / FINAL) for t in EVAL_TASKS}))
    rows.append((f"VLA-Joint {_amount(scale.large)} (ours)",
                 dict.fromkeys(EVAL_TASKS, str(models / f"joint{scale.large}" / FINAL))))
    if dagger:
        rows.append((f"VLA-Sep {_amount(scale.large)} + DAgger (ours)",
                     {t: str(models / f"sep{scale.large}-{SEP_MODEL_FOR[t]}-dagger" / FINAL) for t in EVAL_TASKS}))
    rows.append(("Expert (privileged)", dict.fromkeys(EVAL_TASKS, EXPERT)))
    return rows


def evaluate_rows(rows, scale: Scale, episodes: int, seed: int, workers: int,
                  paper_where_is: bool = False, backend: Backend = PROCESS) -> dict[str, dict[str, list]]:
    # The same spec on the same task (the Where Is Sep model on two tasks is two jobs) runs
    # once; tasks whose envs take the same arguments are evaluated together.
    groups: dict[str, tuple[dict, list[tuple[str, str]]]] = {}
    for spec, task in dict.fromkeys((spec, task) for _, specs in rows for task, spec in specs.items()):
        extra = task_env_kwargs(task, paper_where_is)
        groups.setdefault(json.dumps(extra, sort_keys=True), (extra, []))[1].append((spec, f"Legent/{task}-v0"))
    results = {}
    for extra, group in groups.values():
        env_kwargs = {"width": scale.image_size, "height": scale.image_size, **extra}
        results.update(zip(group, evaluate_many(group, episodes, seed, env_kwargs, workers, backend)))
    return {label: {task: results[(spec, f"Legent/{task}-v0")] for task, spec in specs.items()}
            for label, specs in rows}


# -- 4. the table ----------------------------------------------------------------------------
PAPER_WHERE_IS_NOTE = ("Where Is asks LEGENT's questions (`--paper-where-is`): an orange, apple, banana or cola "
                       "on a sofa, chair, table, countertop or dresser.")


def markdown_table(ours: list[tuple[str, list[float]]], episodes: int, paper_where_is: bool = False) -> str:
    lines = ["| Model | " + " | ".join(COLUMNS) + " |", "|---" * (len(COLUMNS) + 1) + "|"]
    for label, rates in PAPER_ROWS:
        lines.append(f"| {label} (paper) | " + " | ".join(f"{r:.2f}" for r in rates) + " |")
    for label, rates in ours:
        lines.append(f"| {label} | " + " | ".join(f"{r:.2f}" for r in rates) + " |")
    lines.append("")
    lines.append(f"Success rates; ours over {episodes} seeded episodes per task (the paper: 100). "
                 "\\* never trained on (generalisation).")
    if paper_where_is:
        lines.append(PAPER_WHERE_IS_NOTE)
    return "\n".join(lines) + "\n"


def csv_table(ours: list[tuple[str, list[float]]]) -> str:
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(["model", "source", *EVAL_TASKS])
    for label, rates in PAPER_ROWS:
        writer.writerow([label, "paper", *(f"{r:.2f}" for r in rates)])
    for label, rates in ours:
        writer.writerow([label, "ours", *(f"{r:.4f}" for r in rates)])
    return buffer.getvalue()


def bar_chart(ours: list[tuple[str, list[float]]], title: str) -> bytes:
    # start-up time: matplotlib only for the figure
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib import pyplot as plt

    rows = [(f"{label} (paper)", rates) for label, rates in PAPER_ROWS[1:]] + ours
    fig, ax = plt.subplots(figsize=(11, 4.8), dpi=100)
    width = 0.8 / len(rows)
    # The paper's rows in hatched blues, random and expert in greys, our models in colours.
    ours_colours = iter(plt.get_cmap("tab10")([1, 2, 3, 4, 6, 8]).tolist())
    colours = plt.get_cmap("Blues")([0.35, 0.55, 0.75]).tolist()
    for label, _ in ours:
        colours.append("#bbbbbb" if label == "Random" else "#555555" if label.startswith("Expert")
                       else next(ours_colours))
    for i, (label, rates) in enumerate(rows):
        xs = [c + (i - (len(rows) - 1) / 2) * width for c in range(len(COLUMNS))]
        hatch = "//" if i < len(PAPER_ROWS) - 1 else None
        ax.bar(xs, rates, width, label=label, color=colours[i], hatch=hatch, edgecolor="white", linewidth=0.5)
    ax.set_xticks(range(len(COLUMNS)), COLUMNS)
    ax.set_ylim(0, 1.05)
    ax.set_ylabel("success rate")
    ax.set_title(title)
    ax.legend(fontsize=8, ncol=4, loc="upper center", bbox_to_anchor=(0.5, -0.1), frameon=False)
    ax.grid(axis="y", alpha=0.3)
    fig.tight_layout()
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png")
    plt.close(fig)
    return buffer.getvalue()


def write_tables(root: Path, scale_name: str, scale: Scale, ours: list[tuple[str, list[float]]],
                 episodes: int, paper_where_is: bool = False) -> None:
    """``table.md``, ``table.csv`` and ``table.png``."""
    atomic_write_text(root / "table.md", markdown_table(ours, episodes, paper_where_is))
    atomic_write_text(root / "table.csv", csv_table(ours))
    title = (f"Table 3 reproduced, scale '{scale_name}' ({_amount(scale.small)} / {_amount(scale.large)} "
             f"trajectories per task, {scale.image_size}x{scale.image_size} views, {episodes} episodes"
             + (", LEGENT's Where Is objects)" if paper_where_is else ")"))
    atomic_write_bytes(root / "table.png", bar_chart(ours, title))


def redraw(root: Path) -> None:
    """Rewrite the tables from ``results.json`` (nothing is run again)."""
    path = root / "results.json"
    if not path.is_file():
        raise FileNotFoundError(f"no {path}: run the table first")
    results = json.loads(path.read_text())
    ours = [(label, [rates[task] for task in EVAL_TASKS]) for label, rates in results["success_rates"].items()]
    episodes = len(next(iter(next(iter(results["episodes"].values())).values())))
    write_tables(root, results["scale"], Scale(**results["config"]), ours, episodes,
                 results.get("paper_where_is", False))


def write_outputs(root: Path, scale_name: str, scale: Scale, evaluated: dict, extra: dict) -> list[tuple[str, list[float]]]:
    ours = [(label, [success_rate(evaluated[label][task]) for task in EVAL_TASKS]) for label in evaluated]
    episodes = len(next(iter(next(iter(evaluated.values())).values())))
    write_tables(root, scale_name, scale, ours, episodes, extra.get("paper_where_is", False))
    results = {"scale": scale_name, "config": asdict(scale), **extra,
               "success_rates": {label: dict(zip(EVAL_TASKS, rates)) for label, rates in ours},
               "episodes": {label: {task: [asdict(r) for r in runs] for task, runs in per_task.items()}
                            for label, per_task in evaluated.items()}}
    atomic_write_text(root / "results.json", json.dumps(results, indent=1))
    return ours


def run(scale_name: str, out: Path, workers: int, episodes: int | None = None, eval_seed: int = 0,
        perturb: float = 0.0, scan: bool = False, dagger: bool = False,
        channels: tuple[int, ...] | None = None, epochs_large: int | None = None, film: bool = False,
        paper_where_is: bool = False, shift: int = 0, backend: Backend = PROCESS, model: str | None = None,
        vlm_epochs: int = 2) -> dict:
    """The whole table; ``perturb``: recovery data; ``scan``: Where Is demonstrations that
    look around first; ``dagger``: a DAgger round on the large Sep models (see the module
    docstring); ``channels`` and ``epochs_large`` replace the scale's encoder widths and
    its epochs on the large sets, ``film`` conditions the image encoder on the instruction
    (use a new ``out``: the model folders keep their names); ``paper_where_is``: Where Is
    asks LEGENT's objects on LEGENT's receptacles; ``shift``: training views shifted at
    random by up to that many pixels; ``backend``: where collection, training and
    evaluation run (worker processes or Ray tasks; the table does not depend on it);
    ``model``: ``vlm:PATH``, a Hugging Face VLM fine-tuned ``vlm_epochs`` epochs per run
    in place of the VLA (:mod:`baselines.vlm.table`)."""
    if scale_name not in SCALES:
        raise ValueError(f"unknown scale {scale_name!r}; known: {', '.join(SCALES)}")
    if workers < 1:
        raise ValueError(f"workers must be >= 1, got {workers}")
    if not 0.0 <= perturb < 1.0:
        raise ValueError(f"perturb must be in [0, 1), got {perturb}")
    scale = SCALES[scale_name]
    if channels is not None:
        scale = replace(scale, channels=tuple(channels))
        model_config(scale)  # checks the widths against the image size now, not after collecting
    if epochs_large is not None:
        if epochs_large < 1:
            raise ValueError(f"epochs_large must be >= 1, got {epochs_large}")
        scale = replace(scale, epochs_large=epochs_large)
    if film:
        scale = replace(scale, film=True)
    check_shift(shift, scale.image_size)  # now, not after collecting
    scale = replace(scale, shift=shift)
    episodes = episodes or scale.episodes
    if model is not None:  # checked now, not after collecting
        # start-up time: imported by the stage that runs it
        from baselines.vlm import table as vlm_table

        base = vlm_table.base_model(model)
        if dagger:
            raise ValueError("--dagger trains the compact VLA; it does not combine with --model")
    if eval_seed + episodes > DATA_SEED:
        raise ValueError(f"evaluation seeds must stay below the data's ({DATA_SEED})")
    out.mkdir(parents=True, exist_ok=True)
    if backend.kind == "ray" and backend.address is None:
        # One Ray on this machine for every phase: the collections (subprocesses) join it.
        ray = connect_ray(None, workers)
        backend = Backend("ray", ray.get_runtime_context().gcs_address)
    times, started = {}, time.monotonic()

    log(f"scale {scale_name}: {asdict(scale)}; output {out}")
    t = time.monotonic()
    folders = collect_data(out, scale, workers, perturb, scan, paper_where_is, backend)
    times["data"] = time.monotonic() - t

    t = time.monotonic()
    if model is not None:
        runs = vlm_table.training_runs(out, folders, TRAIN_TASKS, scale.small, scale.large, base, vlm_epochs)
        metrics = vlm_table.train_models(runs, log)
    else:
        runs = training_runs(out, folders, scale)
        metrics = train_models(runs, workers, backend)
    times["training"] = time.monotonic() - t

    if dagger:
        t = time.monotonic()
        rollouts, dagger_rounds = collect_dagger_data(out, scale, workers, scan, paper_where_is)
        times["dagger_data"] = time.monotonic() - t
        t = time.monotonic()
        more = dagger_runs(out, folders, rollouts, scale)
        metrics.update(train_models(more, workers, backend))
        runs.update(more)
        times["dagger_training"] = time.monotonic() - t

    t = time.monotonic()
    rows = table_rows(out, scale, dagger) if model is None else vlm_table.table_rows(
        out, scale.small, scale.large, EVAL_TASKS, SEP_MODEL_FOR, _amount, RANDOM, EXPERT)
    log(f"evaluating {len(rows)} rows x {len(EVAL_TASKS)} tasks x {episodes} episodes")
    evaluated = evaluate_rows(rows, scale, episodes, eval_seed, workers, paper_where_is, backend)
    times["evaluation"] = time.monotonic() - t

    eval_houses = {r.house_seed for per_task in evaluated.values() for rs in per_task.values() for r in rs}
    overlap = len(eval_houses & data_house_seeds(folders, scale.large))
    times["total"] = time.monotonic() - started
    extra = {"workers": workers, "eval_seeds": [eval_seed, eval_seed + episodes - 1],
             "perturb": perturb, "scan": scan, "paper_where_is": paper_where_is, "dagger": scale.dagger_rollouts if dagger else 0,
             "data_seeds": {t: DATA_SEED + i * DATA_SEED_STRIDE for i, t in enumerate(TRAIN_TASKS)},
             "house_overlap_eval_vs_data": overlap, "wall_seconds": {k: round(v, 1) for k, v in times.items()},
             "collections": collection_summary(folders),
             **({"dagger_rounds": dagger_rounds} if dagger else {}),
             "training": {name: {"config": _within(out, runs[name].to_dict()), "metrics": metrics[name]} for name in runs},
             "command": " ".join([Path(sys.argv[0]).name, *sys.argv[1:]]) if sys.argv else ""}
    ours = write_outputs(out, scale_name, scale, evaluated, extra)
    log(f"house seeds shared by evaluation and training data: {overlap}")
    log("wall time: " + ", ".join(f"{k} {v:.0f} s" for k, v in times.items()))
    print(markdown_table(ours, episodes, paper_where_is))
    return {"rates": dict(ours), "times": times, "overlap": overlap}


def _within(out: Path, config: dict) -> dict:
    """A training configuration as ``results.json`` keeps it: its data and model folders
    relative to the run's folder (where they are inside it), so that the kept file names no
    folder of the machine that ran it."""
    def shown(path: str) -> str:
        try:
            return str(Path(path).relative_to(out))
        except ValueError:
            return path
    return {**config, "data": [shown(d) for d in config["data"]], "out": shown(config["out"])}


def main(argv: Sequence[str] | None = None) -> int:
    p = argparse.ArgumentParser(description="Reproduce the paper's Table 3: data, VLA training, evaluation, table.")
    p.add_argument("--scale", choices=list(SCALES), default="small")
    p.add_argument("--out", help="output folder (default out/table-<scale>); a second run resumes")
    p.add_argument("--workers", type=int, default=min(2, os.cpu_count() or 1),
                   help="processes for collection, training and evaluation")
    p.add_argument("--episodes", type=int, help="evaluation episodes per task (default: the scale's)")
    p.add_argument("--eval-seed", type=int, default=0, help="episode i of every task resets with seed S + i")
    p.add_argument("--perturb", type=float, default=0.0,
                   help="recovery data: per step, the probability of a random move/turn labelled by the expert")
    p.add_argument("--scan", action="store_true",
                   help="Where Is demonstrations from an expert that looks around until the object is in view")
    p.add_argument("--dagger", action="store_true",
                   help="add a row: one DAgger round on the large Sep models (rollouts labelled by the expert)")
    p.add_argument("--channels", help="the image encoder's widths, comma-separated (default: the scale's, "
                                      "16,32,64,128; docs/results.md's best table: 32,64,128,256)")
    p.add_argument("--epochs-large", type=int, help="epochs on the large sets (default: the scale's)")
    p.add_argument("--film", action="store_true", help="condition the image encoder on the instruction (FiLM)")
    p.add_argument("--paper-where-is", action="store_true",
                   help="Where Is asks LEGENT's objects (orange, apple, banana, cola) on its receptacle kinds")
    p.add_argument("--shift", type=int, default=0,
                   help="shift every training view by up to N pixels at random (0: none)")
    p.add_argument("--redraw", action="store_true", help="only rewrite the tables from OUT/results.json")
    p.add_argument("--backend", choices=["process", "ray"], default="process",
                   help="collection, training and evaluation in worker processes or as Ray tasks (the scale extra)")
    p.add_argument("--ray-address", help="with --backend ray: 'auto' or HOST:PORT (default: start a local Ray)")
    p.add_argument("--model", help="vlm:PATH: fine-tune this Hugging Face VLM (folder or hub id) in place of the VLA")
    p.add_argument("--vlm-epochs", type=int, default=2, help="with --model: epochs per fine-tuning run")
    args = p.parse_args(argv)
    out = Path(args.out or f"out/table-{args.scale}")
    try:
        if args.redraw:
            redraw(out)
            return 0
        channels = parse_channels(args.channels) if args.channels else None
        backend = Backend(args.backend, args.ray_address)
        backend.check()
        run(args.scale, out, args.workers, args.episodes, args.eval_seed, args.perturb, args.scan, args.dagger,
            channels, args.epochs_large, args.film, args.paper_where_is, args.shift, backend, args.model,
            args.vlm_epochs)
    except (ValueError, RuntimeError, FileNotFoundError) as err:
        print(f"reproduce_table: error: {err}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

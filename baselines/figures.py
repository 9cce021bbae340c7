"""Figures as data: every table of measured numbers in the docs comes from a JSON file.

A *figure* is one table of measured numbers. Its producer (a function here) runs the
command that measures it and returns the table; :func:`write` saves the table with where it
came from (:func:`provenance`: the commit, whether the tree had uncommitted changes, the
command line, the seeds, the machine, the date and the wall time) to
``docs/data/figures/<name>.json``; and the Markdown docs hold the table between two
markers that :func:`refresh_docs` rewrites from that file::

    <!-- figure: random-policy -->
    | env | success | ... |
    ...
    <!-- /figure -->

Nobody types these tables: ``python -m baselines.refresh`` measures and rewrites them, and
``tests/baselines/test_figures.py`` fails when a block differs from its file (a figure
edited by hand) or when a cheap figure's producer now gives other numbers than the
committed file (a figure gone stale).

*Cheap* figures are deterministic and quick (seeded episodes): the default tests and
``--scale small`` rerun them. The others (timings, long training runs) are rerun by
``--scale full`` only, and each table says beside it the commit it was measured at.

A figure *made from* other data files measures nothing (a table run's models and phases
from the ``results.json`` it kept, two runs' rows side by side, the paper beside us): it is
cheap, and rerun by the default tests like the seeded ones. A number that the prose quotes
from a figure sits between markers that name it (:data:`VALUE`), and is rewritten and
checked with the tables.

A long run measured before its table was a figure is *adopted* (``python -m baselines.refresh
--adopt NAME --commit SHA``, nothing run): from the ``results.json`` the run kept in
``docs/data/<folder>/``, or, when the run kept no file, from the table as typed in the doc at
the commit that added it (``Figure.typed``; the test checks the data against that commit's
text). Such a table says beside it that it was not re-measured on the current code.

This module defines the figures (:data:`FIGURES`, their producers, :func:`adopt`,
:func:`outdated`); the machinery they share (tables, data files, blocks, provenance) is
:mod:`baselines.figure_data`.
"""

from __future__ import annotations

import csv
import functools
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile
from collections.abc import Callable, Sequence
from dataclasses import replace
from pathlib import Path
from typing import Any

if __package__ in (None, ""):  # run as a script: make `baselines` importable
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from baselines.figure_data import (  # noqa: E402
    FORMAT_VERSION,
    ROOT,
    Figure,
    FigureError,
    Table,
    adopt_typed,
    code_changed_since,
    data_path,
    git,
    load,
    machine,
    shown,
)

#: Figures kept as data files only, shown in no doc (the runs behind the docs' tables, other
#: scales, ablations, speed-ups measured against older code): checked and remade like the
#: others; ``python -m baselines.refresh --show NAME`` prints one's table.
DATA_ONLY = frozenset({
    "table-full-wide-run", "wide-against-narrow", "table-full-wide-paper", "table-full-wide-paper-run",
    "where-is-paper-seeds", "table-full-p25-scan", "table-full-p25-scan-run", "recovery-against-clean",
    "table-full-run", "table-large", "table-large-run", "table-medium", "table-medium-run", "full-scale-cost",
    "table-full-p25-scan-dagger", "table-full-p25-scan-dagger-run", "dagger-more-seeds", "ablation-wide-encoder",
    "ablation-epochs16", "ablation-shift", "ablation-recovery", "ablation-scan", "ablation-aux", "variants-medium",
    "render-fast-vs-stock", "render-without-culling", "step-view-culling", "step-episode-engine",
    "step-frame-savings", "step-own-cost", "generation-fast-paths", "collect-speed-all-ids",
    "expert-success", "expert-speed", "multiagent-speed", "soak", "table-full-wide", "ppo-curve",
    "expert-200-seeds", "table-small", "ppo-random-floor", "expert-scan", "scale-backends", "vlm-tiny-speed",
    "collect-speed",
})


def outdated() -> list[tuple[str, str, list[str]]]:
    """(figure, the commit it was measured at, the files of :data:`MEASURED_CODE` changed since)
    for every figure that one command measures and whose code changed after its measurement:
    what ``python -m baselines.refresh --scale full --outdated`` measures again, so that a full
    refresh can be done in parts. Figures made from other data files follow their sources;
    tables typed in a doc that no command measures are left out."""
    found = []
    for name, fig in FIGURES.items():
        if fig.produce is None or not data_path(name).is_file():
            continue
        data = load(name)
        if data.get("made_from"):
            continue
        changed = code_changed_since(data["commit"])
        if data.get("dirty"):  # what the tree held then is not known
            changed.append("(uncommitted changes when it was measured)")
        if changed:
            found.append((name, data["commit"], changed))
    return found


# -- the figures ----------------------------------------------------------------------------------
def _rate_stderr(p: float, n: int) -> float:
    return math.sqrt(max(p * (1.0 - p), 0.0) / n)


RANDOM_ENVS = ("Legent/ComeHere-OneRoom-v0", "Legent/ComeHere-TwoRoom-v0")


def random_policy() -> Table:
    """docs/results.md, "Random policy": ``baselines/evaluate.py --policy random``, 100
    episodes from seed 0, for each ComeHere id (the command's own code path)."""
    # imported here: the baselines' modules import torch (seconds); --check and --show need none
    from baselines.vla.evaluate import evaluate_many, success_rate

    results = evaluate_many([("random", env_id) for env_id in RANDOM_ENVS], 100, 0, {}, workers=1)
    rows, errors = [], []
    for env_id, runs in zip(RANDOM_ENVS, results):
        rate = success_rate(runs)
        steps = sum(r.steps for r in runs) / len(runs)
        rows.append([env_id, rate, round(steps, 2),
                     f"`python baselines/evaluate.py --env {env_id} --episodes 100 --seed 0`"])
        errors.append([None, _rate_stderr(rate, len(runs)), None, None])
    return Table(["env", "success (100 episodes)", "mean actions", "command"], rows, errors, seeds="0-99",
                 formats=["", ".2f", ".1f", ""])


def expert_success() -> Table:
    """docs/experts.md, "Measured" (the quick version): the task expert on seeds 0-5 of
    every registered id, text actions, 32x32 images."""
    # imported here: the baselines' modules import torch (seconds); --check and --show need none
    from baselines.vla.evaluate import evaluate_many
    from legent_gym.envs.registration import ENV_IDS

    ids = sorted(ENV_IDS)
    results = evaluate_many([("expert", env_id) for env_id in ids], 6, 0, {"width": 32, "height": 32}, workers=1)
    rows = []
    for env_id, runs in zip(ids, results):
        won = [r for r in runs if r.success]
        mean = sum(r.steps for r in won) / len(won) if won else float("nan")
        rows.append([env_id, f"{len(won)}/{len(runs)}", round(mean, 2), max((r.steps for r in won), default=0)])
    return Table(["env", "expert successes", "mean actions", "max actions"], rows, seeds="0-5 of every id",
                 formats=["", "", ".1f", "d"])


EXPERT_SEEDS = 200


def expert_200_seeds() -> Table:
    """docs/experts.md, "Measured": the task expert on seeds 0-199 of every registered id,
    text actions, 32x32 images, the 25-action cap (the evaluator's code path)."""
    # imported here: the baselines' modules import torch (seconds); --check and --show need none
    from baselines.vla.evaluate import evaluate_many
    from legent_gym.envs.registration import ENV_IDS

    ids = sorted(ENV_IDS)
    results = evaluate_many([("expert", env_id) for env_id in ids], EXPERT_SEEDS, 0, {"width": 32, "height": 32},
                            workers=1)
    rows = []
    for env_id, runs in zip(ids, results):
        won = [r.steps for r in runs if r.success]
        rows.append([env_id, f"{len(won)}/{len(runs)}", round(sum(won) / len(won), 2) if won else float("nan"),
                     max(won, default=0)])
    return Table(["env", "expert successes", "mean actions", "max actions"], rows,
                 seeds=f"0-{EXPERT_SEEDS - 1} of every id", formats=["", "", ".1f", "d"])


DAGGER_ENVS = ("Legent/ComeHere-TwoRoom-v0", "Legent/BringMe-TwoRoom-v0", "Legent/PutOn-OneRoom-v0",
               "Legent/WhereIs-TwoRoom-v0")
DAGGER_RANDOM_ACTIONS = 5


def expert_takeover() -> Table:
    """docs/experts.md, "Replanning from any state": per id, on seeds 0-199, five random
    actions (a move of up to 1.5 m, a turn, a tilt; one generator seeded 0 per id), then the
    expert; how often it succeeds where success was still possible (the episode not ended by
    the random actions): :func:`baselines.evaluate.expert_takeover`, which
    ``tests/wrappers/test_expert_wrappers.py`` also runs."""
    # imported here: the baselines' modules import torch (seconds); --check and --show need none
    from baselines.evaluate import expert_takeover as takeover

    rows = []
    for env_id in DAGGER_ENVS:
        wins, possible = takeover(env_id, range(EXPERT_SEEDS), DAGGER_RANDOM_ACTIONS)
        rows.append([env_id.split("/")[1].removesuffix("-v0"), f"{wins}/{possible}"])
    return Table(["env", "success where still possible"], rows, seeds=f"0-{EXPERT_SEEDS - 1}")


def ppo_random_floor() -> Table:
    """docs/results.md, PPO's final evaluation: its random row on the current code (the
    random policy on the evaluation's seeds, env and camera, as ``ppo_comehere.final_evaluation``
    runs it)."""
    # imported here: the baselines' modules import torch (seconds); --check and --show need none
    from baselines.evaluate import RandomPolicy, run_episodes
    from baselines.ppo_comehere import EVAL_SEED_OFFSET, Config

    config = Config()
    seed = EVAL_SEED_OFFSET + config.seed
    runs = run_episodes(RandomPolicy(), config.env_id, config.eval_episodes, seed, config.env_kwargs())
    rate = sum(r.success for r in runs) / len(runs)
    rows = [["random", rate, sum(r.episode_return for r in runs) / len(runs), sum(r.steps for r in runs) / len(runs)]]
    return Table(["policy", "success", "mean return", "mean steps"], rows,
                 [[None, _rate_stderr(rate, len(runs)), None, None]], seeds=f"{seed}-{seed + len(runs) - 1}",
                 formats=["", ".3f", ".2f", ".1f"])


SCAN_ENVS = ("Legent/WhereIs-OneRoom-v0", "Legent/WhereIs-TwoRoom-v0", "Legent/WhereIs-FourRoom-v0")


def expert_scan() -> Table:
    """docs/experts.md, ``find(a)`` strategies: the Where Is expert with ``direct`` (LEGENT's)
    and ``scan`` on seeds 0-99 of each layout, text actions, 32x32 images."""
    # imported here: the baselines' modules import torch (seconds); --check and --show need none
    from baselines.evaluate import ExpertBaseline, run_episodes
    from legent_gym.experts import Expert

    class ScanExpert(ExpertBaseline):
        def bind(self, env) -> None:
            self._expert = Expert(env, find_strategy="scan")

    rows = []
    for env_id in SCAN_ENVS:
        row: list[Any] = [env_id]
        for policy in (ExpertBaseline(), ScanExpert()):
            runs = run_episodes(policy, env_id, 100, 0, {"width": 32, "height": 32})
            won = [r.steps for r in runs if r.success]
            row += [f"{len(won)}/{len(runs)}", round(sum(won) / len(won), 2) if won else float("nan")]
        rows.append(row)
    return Table(["env", "direct: successes", "direct: mean actions", "scan: successes", "scan: mean actions"],
                 rows, seeds="0-99 of each id", formats=["", "", ".1f", "", ".1f"])


FIGURES: dict[str, Figure] = {f.name: f for f in (
    Figure("random-policy", "python -m baselines.refresh --only random-policy", random_policy, cheap=True),
    Figure("expert-success", "python -m baselines.refresh --only expert-success", expert_success, cheap=True),
    Figure("expert-200-seeds", "python -m baselines.refresh --only expert-200-seeds", expert_200_seeds, cheap=False),
    Figure("expert-takeover", "python -m baselines.refresh --only expert-takeover", expert_takeover, cheap=False),
    Figure("expert-scan", "python -m baselines.refresh --only expert-scan", expert_scan, cheap=False),
    Figure("ppo-random-floor", "python -m baselines.refresh --only ppo-random-floor", ppo_random_floor, cheap=True),
)}


# -- the paper's table, from reproduce_table.py runs ---------------------------------------------
def vla_table(results: dict[str, Any]) -> Table:
    """The paper's Table 3 beside a ``reproduce_table.py`` run's ``results.json``."""
    # imported here: the baselines' modules import torch (seconds); --check and --show need none
    from baselines.reproduce_table import COLUMNS, EVAL_TASKS, PAPER_ROWS, PAPER_WHERE_IS_NOTE

    episodes = len(next(iter(next(iter(results["episodes"].values())).values())))
    rows: list[list[Any]] = [[f"{label} (paper)", *rates] for label, rates in PAPER_ROWS]
    errors: list[list[float | None]] = [[None] * (len(COLUMNS) + 1) for _ in PAPER_ROWS]
    for label, rates in results["success_rates"].items():
        values = [float(rates[task]) for task in EVAL_TASKS]
        rows.append([label, *values])
        errors.append([None, *(_rate_stderr(v, episodes) for v in values)])
    first, last = results["eval_seeds"]
    note = (f"Success rates; ours over {episodes} seeded episodes per task (reset seeds {first}-{last}), the "
            "paper's over 100. \\* never trained on (generalisation).")
    if results.get("paper_where_is"):
        note += " " + PAPER_WHERE_IS_NOTE
    return Table(["Model", *COLUMNS], rows, errors, seeds=f"{first}-{last} (evaluation)", note=note,
                 formats=["", ".2f", ".2f", ".2f", ".2f"])


def run_folder(folder: str) -> Path:
    """Where a table run's ``results.json``, ``table.md`` and ``table.csv`` are kept."""
    return ROOT / "docs" / "data" / folder


def rerun_table(folder: str, args: Sequence[str], out_folder: str | None = None) -> Table:
    """Run ``reproduce_table.py`` with ``args`` into ``runs/<out_folder>`` (default: ``folder``;
    the run resumes what is there), keep its outputs in ``docs/data/<folder>/`` (its chart as
    ``docs/images/<folder>.png``) and give its table."""

    out = ROOT / "runs" / (out_folder or folder)
    subprocess.run([sys.executable, str(ROOT / "baselines" / "reproduce_table.py"), *args, "--out", str(out)],
                   check=True, cwd=ROOT)
    keep = run_folder(folder)
    keep.mkdir(parents=True, exist_ok=True)
    for name in ("results.json", "table.md", "table.csv"):
        if (out / name).is_file():
            shutil.copyfile(out / name, keep / name)
    if (out / "table.png").is_file():  # the chart the doc shows beside the table
        shutil.copyfile(out / "table.png", ROOT / "docs" / "images" / f"{folder}.png")
    return vla_table(json.loads((keep / "results.json").read_text()))


def adopt(name: str, commit: str, note: str = "") -> dict[str, Any]:
    """The data of a figure measured before it was one (nothing is run): from the
    ``results.json`` its run kept in ``docs/data/<folder>/`` (the run's commit as given, the
    date of that commit, the run's own wall time), else from its table as typed in the doc at
    ``commit`` (``Figure.typed``). ``note`` says how the commit is known."""
    fig = figure(name)
    full = git("rev-parse", "--verify", "--quiet", f"{commit}^{{commit}}")
    if not full:
        raise FigureError(f"no commit {commit!r} in this repository")
    path = run_folder(fig.folder) / "results.json" if fig.folder else None
    if fig.typed is not None and (path is None or not path.is_file()):
        return adopt_typed(fig, full, note)
    if path is None:
        raise FigureError(f"figure {name!r} is neither a run that kept a results.json nor a typed table")
    try:
        results = json.loads(path.read_text())
    except (OSError, ValueError) as err:
        raise FigureError(f"{shown(path)}: {err}") from None
    table = vla_table(results)
    return {"format": FORMAT_VERSION, "name": name, "command": fig.command, "cheap": False,
            "number_format": fig.number_format, "formats": table.formats, "columns": table.columns,
            "rows": table.rows, "stderr": table.stderr, "seeds": table.seeds, "note": table.note,
            "wall_seconds": round(float(results.get("wall_seconds", {}).get("total", 0.0)), 1),
            "commit": full, "dirty": False, "commit_note": note,
            "argv": str(results.get("command", "")).split(), "machine": machine(),
            "date": git("show", "-s", "--format=%cd", "--date=format:%Y-%m-%d %H:%M UTC", full)}


def _table_figure(name: str, folder: str, args: str, continues: str | None = None) -> Figure:
    """A ``reproduce_table.py`` run kept in ``docs/data/<folder>/``. ``continues``: the output
    folder of the run it adds to (``--dagger`` adds DAgger rows to a run, ``--paper-where-is``
    retrains the Where Is models of one), whose data and models it resumes from."""
    out = continues or folder
    return Figure(name, f"python baselines/reproduce_table.py {args} --out runs/{out}",
                  lambda: rerun_table(folder, args.split(), out), cheap=False, folder=folder)


FIGURES.update({f.name: f for f in (
    _table_figure("table-full-wide", "table_full_wide",
                  "--scale full --perturb 0.25 --scan --channels 32,64,128,256 --epochs-large 8"),
    _table_figure("table-full-wide-paper", "table_full_wide_paper",
                  "--scale full --perturb 0.25 --scan --channels 32,64,128,256 --epochs-large 8 --paper-where-is",
                  continues="table_full_wide"),
    _table_figure("table-full-p25-scan", "table_full_p25_scan", "--scale full --perturb 0.25 --scan"),
    _table_figure("table-full", "table_full", "--scale full"),
    _table_figure("table-full-p25-scan-dagger", "table_full_p25_scan_dagger",
                  "--scale full --perturb 0.25 --scan --dagger", continues="table_full_p25_scan"),
    _table_figure("table-large", "table_large", "--scale large"),
    _table_figure("table-medium", "table_medium", "--scale medium"),
)})


SMALL_TABLE_ARGS = ("--scale", "small")


def small_table() -> Table:
    """docs/results.md, scale ``small``: ``reproduce_table.py --scale small`` end to end (data,
    seven trainings, evaluation) in a scratch folder; deterministic, so the default tests rerun it."""

    with tempfile.TemporaryDirectory() as scratch:
        subprocess.run([sys.executable, str(ROOT / "baselines" / "reproduce_table.py"), *SMALL_TABLE_ARGS,
                        "--out", scratch], check=True, cwd=ROOT, capture_output=True)
        return vla_table(json.loads((Path(scratch) / "results.json").read_text()))


FIGURES["table-small"] = Figure("table-small", "python baselines/reproduce_table.py --scale small --out "
                                "runs/table_small", small_table, cheap=True)


#: The phases of a ``reproduce_table.py`` run, in the order it runs them, as ``results.json``
#: names them in ``wall_seconds``.
PHASES = ("data", "training", "dagger_data", "dagger_training", "evaluation")


def run_table(results: dict[str, Any]) -> Table:
    """What a ``reproduce_table.py`` run's ``results.json`` says of its models (size, data,
    training time, validation) and, under the table, of its phases' wall time."""
    rows: list[list[Any]] = []
    for name, run in results["training"].items():
        m = run["metrics"]
        rows.append([name, m["trajectories"], m["steps"], m["epoch"], m["parameters"], round(float(m["seconds"])),
                     m.get("val_template_accuracy"), m.get("val_bin_accuracy")])  # none: too few to hold out
    wall = results["wall_seconds"]
    phases = ", ".join(f"{phase.replace('_', ' ')} {float(wall[phase]):,.0f} s" for phase in PHASES if phase in wall)
    total = float(wall["total"])
    note = (f"Validation: the share of held-out steps ({results['training'][rows[0][0]]['config']['validation_fraction']:.0%} "
            "of each data set's trajectories) whose action template (which call) and number bin (its argument, "
            f"{results['training'][rows[0][0]]['config']['bins']} bins) the model predicts. Wall time "
            f"{total:,.0f} s ({total / 60:.1f} minutes, {results['workers']} worker processes): {phases}; a model "
            "that a resumed run found trained keeps the training time of the run that trained it. "
            f"Evaluation houses found in the training data: {results['house_overlap_eval_vs_data']}.")
    if results.get("collections"):  # kept by runs since the field was added
        note += " Collections (trajectories kept, failed expert attempts skipped, steps): " + "; ".join(
            f"{task} {c['trajectories']:,}, {c['failed_attempts']}, "
            f"{c['steps']:,}" for task, c in results["collections"].items()) + "."
    if results.get("dagger_rounds"):
        note += " DAgger rounds (rollouts, the learner's success, labelled steps, seconds): " + "; ".join(
            f"{task} {d['episodes']:,}, {d['learner_success']:.0%}, {d['steps']:,}, {d['seconds']:,.0f}"
            for task, d in results["dagger_rounds"].items()) + "."
    return Table(["model", "trajectories", "steps", "epochs", "parameters", "training s",
                  "validation: template", "validation: number bin"], rows, note=note,
                 formats=["", ",d", ",d", "d", ",d", ",d", ".0%", ".0%"])


def run_details(name: str) -> Callable[[], Table]:
    """The producer of ``<name>-run``: :func:`run_table` of the results.json that the table
    run ``name`` kept (nothing measured; the table run's commit named)."""
    def produce() -> Table:
        fig = figure(name)
        path = run_folder(fig.folder or "") / "results.json"
        try:
            results = json.loads(path.read_text())
        except (OSError, ValueError) as err:
            raise FigureError(f"{shown(path)}: {err}") from None
        table = run_table(results)
        made_from = f"`{shown(path)}`, kept by the `{name}` run at {load(name)['commit'][:7]}"
        return Table(table.columns, table.rows, note=table.note, formats=table.formats, made_from=made_from)
    return produce


#: The PPO run of docs/results.md; its two figures (the curve, the final evaluation) read its outputs.
PPO_COMMAND = ("baselines/ppo_comehere.py", "--timesteps", "250000", "--out", "out/ppo_comehere")
#: Rollouts per stretch of the curve's table, and how many stretches it shows.
PPO_STRETCH, PPO_STRETCHES = 10, 6


@functools.cache
def ppo_run() -> Path:
    """Run the PPO baseline once per process (both PPO figures read it); its output folder."""
    subprocess.run([sys.executable, *PPO_COMMAND], check=True, cwd=ROOT)
    return ROOT / PPO_COMMAND[PPO_COMMAND.index("--out") + 1]


def ppo_curve_table(rows: list[dict[str, str]]) -> Table:
    """The PPO curve (``ppo_curve.csv``) as a table: the random row, then stretches of
    ``PPO_STRETCH`` rollouts spread evenly over the run (episodes summed, rates weighted by them)."""
    random = [r for r in rows if r["policy"] == "random"]
    ppo = [r for r in rows if r["policy"] != "random"]
    out: list[list[Any]] = [["random policy, same envs and seeds", int(r["episodes"]), float(r["success_rate"]),
                             float(r["mean_return"])] for r in random]
    count = max(1, len(ppo) - PPO_STRETCH + 1)
    starts = sorted({round(i * (count - 1) / max(1, PPO_STRETCHES - 1)) for i in range(PPO_STRETCHES)})
    for start in starts:
        part = ppo[start:start + PPO_STRETCH]
        episodes = sum(int(r["episodes"]) for r in part)
        if not episodes:
            continue

        def mean(key: str, part: list[dict[str, str]] = part, episodes: int = episodes) -> float:
            return sum(float(r[key]) * int(r["episodes"]) for r in part) / episodes

        label = f"{round(int(part[0]['timesteps']) / 1000)}k-{round(int(part[-1]['timesteps']) / 1000)}k"
        out.append([label, episodes, mean("success_rate"), mean("mean_return")])
    return Table(["timesteps", "episodes", "success rate", "mean return"], out,
                 note=f"Training episodes (the policy samples its actions) that ended in each stretch of "
                 f"{PPO_STRETCH} rollouts.", formats=["", "d", ".2f", ".2f"])


def ppo_curve() -> Table:
    """docs/results.md, PPO's learning curve: ``baselines/ppo_comehere.py`` (250k steps)."""

    with (ppo_run() / "ppo_curve.csv").open() as fh:
        table = ppo_curve_table(list(csv.DictReader(fh)))
    summary = json.loads((ppo_run() / "ppo_summary.json").read_text())
    return replace(table, wall_seconds=summary["total_wall_s"])


def ppo_evaluation() -> Table:
    """docs/results.md, PPO's final evaluation: the same run's ``ppo_summary.json``."""
    return ppo_evaluation_table(json.loads((ppo_run() / "ppo_summary.json").read_text()))


def ppo_evaluation_table(summary: dict[str, Any]) -> Table:
    """The final evaluation of a PPO run's summary as a table."""
    evaluation = summary["evaluation"]
    names = {"ppo_greedy": "PPO, greedy (mean action)", "ppo_sampled": "PPO, sampled", "random": "random"}
    first, last = evaluation["seeds"]
    rows = [[label, evaluation[key]["success_rate"], evaluation[key]["mean_return"], evaluation[key]["mean_steps"]]
            for key, label in names.items()]
    errors = [[None, _rate_stderr(r[1], last - first + 1), None, None] for r in rows]
    return Table(["policy", "success", "mean return", "mean steps"], rows, errors, seeds=f"{first}-{last}",
                 note=f"The run took {summary['total_wall_s']:,.0f} s of wall time, {summary['train_wall_s']:,.0f} s "
                 "of it training.", formats=["", ".3f", ".2f", ".1f"], wall_seconds=summary["total_wall_s"])


def _typed(name: str, doc: str, line: str, command: str = "") -> Figure:
    """A table typed in ``doc`` whose run kept no file and that no one command measures
    again: adopted from the doc at the commit that added it. ``command``: the command the doc
    gives for it ("" where the doc does not keep one)."""
    return Figure(name, command, None, cheap=False, typed=(doc, line))


FIGURES.update({f"{name}-run": Figure(f"{name}-run", f"python -m baselines.refresh --only {name}-run",
                                        run_details(name), cheap=True)
                for name, fig in list(FIGURES.items()) if fig.folder and fig.typed is None})
def side_by_side(sources: Sequence[tuple[str, str]], labels: Sequence[str]) -> Callable[[], Table]:
    """The producer of a table of rows taken from table figures: for each row label, that row
    of each ``(figure, what it is)`` source in turn (nothing measured; each source's commit
    named)."""
    def produce() -> Table:
        loaded = [(name, what, load(name)) for name, what in sources]
        columns = loaded[0][2]["columns"]
        rows: list[list[Any]] = []
        errors: list[list[float | None]] = []
        for label in labels:
            for name, what, data in loaded:
                if data["columns"] != columns:
                    raise FigureError(f"figure {name!r} has other columns than {loaded[0][0]!r}")
                hits = [i for i, r in enumerate(data["rows"]) if r[0] == label]
                if len(hits) != 1:
                    raise FigureError(f"figure {name!r} has {len(hits)} rows named {label!r}")
                rows.append([f"{label}, {what}", *data["rows"][hits[0]][1:]])
                errors.append(list((data.get("stderr") or [[None] * len(columns)] * len(data["rows"]))[hits[0]]))
        made_from = ", ".join(f"`{shown(data_path(name))}` (at {data['commit'][:7]})" for name, _, data in loaded)
        return Table(["Model", *columns[1:]], rows, errors, formats=loaded[0][2].get("formats"), made_from=made_from,
                     note="Success rates over reset seeds 0-99; a standard error is about 0.05 at 100 episodes.")
    return produce


FIGURES["wide-against-narrow"] = Figure(
    "wide-against-narrow", "python -m baselines.refresh --only wide-against-narrow",
    side_by_side([("table-full-wide", "wide encoder"), ("table-full-p25-scan", "0.8 M")],
                 ["VLA-Sep 1K (ours)", "VLA-Sep 10K (ours)", "VLA-Joint 10K (ours)"]), cheap=True)
FIGURES["recovery-against-clean"] = Figure(
    "recovery-against-clean", "python -m baselines.refresh --only recovery-against-clean",
    side_by_side([("table-full-p25-scan", "recovery and scan data"), ("table-full", "clean data, direct expert")],
                 ["VLA-Sep 1K (ours)", "VLA-Sep 10K (ours)", "VLA-Joint 10K (ours)"]), cheap=True)
_WIDE_TRAIN = "python -m baselines.vla.train --data runs/table-full-p25/data/<task folder> --out M --epochs 8 " \
    "--threads 1 --channels 32,64,128,256"
FIGURES.update({f.name: f for f in (
    _typed("where-is-paper-seeds", "docs/results.md", "| VLA-Sep 10K of the default task (ours), asked these |"),
    Figure("ppo-curve", "python " + " ".join(PPO_COMMAND), ppo_curve, cheap=False,
           typed=("docs/results.md", "| 196k-205k |")),
    Figure("ppo-evaluation", "python " + " ".join(PPO_COMMAND), ppo_evaluation, cheap=False,
           typed=("docs/results.md", "| PPO, greedy (mean action) |")),
    _typed("ablation-wide-encoder", "docs/results.md", "| Come Here, one room | 0.72 | 0.78 |",
           _WIDE_TRAIN + ", evaluated on reset seeds 0-299"),
    _typed("ablation-epochs16", "docs/results.md", "| 16 epochs, seeds 0-99 / 0-299 |",
           "python -m baselines.vla.train --data <table-full-wide data>/<Task> --trajectories 10000 --epochs 16 "
           "--channels 32,64,128,256 --threads 1, evaluated on reset seeds 0-299"),
    _typed("ablation-shift", "docs/results.md", "| `--shift 4`, seeds 0-99 / 0-299 |",
           "python -m baselines.vla.train --data <table-full-wide data>/<Task> --trajectories 10000 --epochs 8 "
           "--channels 32,64,128,256 --shift 4 --threads 1, evaluated on reset seeds 0-299"),
    _typed("ablation-recovery", "docs/results.md", "| clean | 8,810 | 92 s |"),
    _typed("ablation-scan", "docs/results.md", "| **scan**, clean |"),
    _typed("ablation-aux", "docs/results.md", "| the same | W = 0.5 | 0.56 |"),
    _typed("variants-medium", "docs/results.md", "| plain behaviour cloning (no mirroring) |"),
    # docs/performance.md: each fast path measured against the code before it, at the commits the doc names
    _typed("render-fast-vs-stock", "docs/performance.md", "| 64 | 2528 |", "python benchmarks/render.py"),
    _typed("render-without-culling", "docs/performance.md", "| 96 | 1218-1318 |"),
    _typed("step-view-culling", "docs/performance.md", "| ComeHere-TwoRoom | 1490 |",
           "python benchmarks/step.py --steps 3000"),
    _typed("step-episode-engine", "docs/performance.md", "| ComeHere-OneRoom | 0.80 / 0.80 |",
           "python benchmarks/step.py --steps 1000 --resets 10"),
    _typed("step-frame-savings", "docs/performance.md", "| commit 5586812, its reference |",
           "python benchmarks/step.py --steps 3000"),
    _typed("step-own-cost", "docs/performance.md", "| before | 1793 |", "python benchmarks/step.py"),
    _typed("generation-fast-paths", "docs/performance.md", "| 1 | before | 21.6 |",
           "python benchmarks/generation.py"),
    _typed("soak", "docs/performance.md", "| steps, resets, make/close cycles |", "python benchmarks/soak.py"),
    # the other docs' measured tables
    _typed("collect-speed", "docs/datasets.md", "| expert loop, 1 worker |",
           "python benchmarks/experts.py --ids Legent/ComeHere-OneRoom-v0 --attempts 40"),
    _typed("collect-speed-all-ids", "docs/datasets.md", "| ComeHere-OneRoom | 3.0 |",
           "python benchmarks/experts.py --attempts 20 --collect-ids ''"),
    _typed("multiagent-speed", "docs/multiagent.md", "| Legent/ComeHere-OneRoom-v0 | random |",
           "python benchmarks/multiagent.py (--user still, --distance-info for those rows)"),
    _typed("scale-backends", "docs/scale.md", "| process backend, 2 workers |",
           "python benchmarks/scale.py --episodes 100 --rounds 3"),
    _typed("vlm-tiny-speed", "docs/vlm.md", "| full fine-tuning |"),
)})


# -- the paper beside us --------------------------------------------------------------------------
#: The run of ours that the comparison shows (the best table here) and the paper's quoted table.
OURS_FIGURE, PAPER_FIGURE = "table-full-wide", "paper-table-3"


def load_quoted(name: str) -> dict[str, Any]:
    """A data file of numbers quoted from a publication (``source``: "paper"), not measured."""
    path = data_path(name)
    try:
        data = json.loads(path.read_text())
    except (OSError, ValueError) as err:
        raise FigureError(f"{shown(path)}: {err}") from None
    if data.get("source") != "paper" or data.get("name") != name:
        raise FigureError(f"{shown(path)}: not quoted data named {name!r}")
    return data


def paper_beside_ours() -> Table:
    """The paper's Table 3 and ours side by side, each row with its conditions: the paper's
    rows from ``paper-table-3.json`` (quoted), ours from the ``table-full-wide`` figure and
    the ``results.json`` its run kept (model sizes, data, evaluation seeds), and the baselines
    that need what no CPU machine has (an LLM endpoint, a GPU), not measured."""
    paper, ours = load_quoted(PAPER_FIGURE), load(OURS_FIGURE)
    results = json.loads((run_folder(figure(OURS_FIGURE).folder or "") / "results.json").read_text())
    first, last = results["eval_seeds"]
    hardware = f"CPU, {ours['machine']['cores']} cores"
    evaluation = f"{results['config']['episodes']} per task, reset seeds {first}-{last}"
    view = results["config"]["image_size"]
    columns = ["Model", *ours["columns"][1:], "parameters", "training data", "hardware", "evaluation",
               "needs a GPU", "from"]
    rows: list[list[Any]] = []
    for label, *rates in paper["rows"]:
        c = paper["conditions"][label]
        rows.append([f"{label} (paper)", *rates, c["parameters"], c["training data"], c["hardware"],
                     paper["evaluation"], c["needs a GPU"], "the paper's Table 3"])

    def parameters(prefix: str) -> str:
        counts = sorted({m["metrics"]["parameters"] for k, m in results["training"].items() if k.startswith(prefix)})
        low, high = counts[0] / 1e6, counts[-1] / 1e6
        return f"{low:.2f} M" if f"{low:.2f}" == f"{high:.2f}" else f"{low:.2f}-{high:.2f} M"

    def amount(n: int) -> str:
        return f"{n // 1000}K" if n % 1000 == 0 else str(n)

    small, large = results["config"]["small"], results["config"]["large"]
    made = {"Random": ("-", "none", "CPU"),
            f"VLA-Sep {amount(small)} (ours)": (parameters(f"sep{small}-"),
                                                f"{amount(small)} trajectories per task, a model per task, "
                                                f"{view} x {view} views", hardware),
            f"VLA-Sep {amount(large)} (ours)": (parameters(f"sep{large}-"),
                                                f"{amount(large)} trajectories per task, a model per task, "
                                                f"{view} x {view} views", hardware),
            f"VLA-Joint {amount(large)} (ours)": (parameters("joint"),
                                                  f"the three tasks' {amount(large)} sets, one model, "
                                                  f"{view} x {view} views", hardware)}
    for label, *rates in ours["rows"]:
        if label in made:
            size, data, where = made[label]
            rows.append([label if label.endswith("(ours)") else f"{label} (ours)", *rates, size, data, where,
                         evaluation, "no", f"`{OURS_FIGURE}` at {ours['commit'][:7]}"])
    rows.append(["LLM agent (ours, `baselines/llm_agent.py`)", "-", "-", "-", "-", "the endpoint's model",
                 "none (zero-shot)", "an OpenAI-compatible multimodal endpoint", "-", "the endpoint's",
                 "not measured: needs a model endpoint"])
    rows.append(["VLM fine-tuned (ours, `baselines/vlm/`, the paper's recipe)", "-", "-", "-", "-",
                 "the chosen Hugging Face model", "`legent-gym collect` data", "GPU", "-", "yes",
                 "not measured: needs a GPU (`docs/vlm.md`)"])
    note = ("Success rates. The paper's rows are quoted (views 448 x 448); ours are measured with the same "
            "protocol (the same training tasks, Where Is in two rooms never trained on, 100 episodes per task). "
            "\\* never trained on (generalisation).")
    made_from = (f"`{shown(data_path(PAPER_FIGURE))}` (quoted from {paper['quoted']}), "
                 f"`{shown(data_path(OURS_FIGURE))}` and `docs/data/{figure(OURS_FIGURE).folder}/results.json`")
    return Table(columns, rows, seeds=f"{first}-{last} (evaluation, ours)", note=note, made_from=made_from,
                 formats=["", ".2f", ".2f", ".2f", ".2f", "", "", "", "", "", ""])


FIGURES["paper-beside-ours"] = Figure("paper-beside-ours", "python -m baselines.refresh --only paper-beside-ours",
                                      paper_beside_ours, cheap=True)


# -- speed ----------------------------------------------------------------------------------------
THROUGHPUT_ARGS = ("--rounds", "5")


def throughput_table(report: dict[str, Any]) -> Table:
    """The rows of a ``benchmarks/throughput.py --json`` report."""
    rows: list[list[Any]] = []
    for name, row in report["rows"].items():
        label = row["label"].replace("Legent/", "")
        collect = name.startswith("collect")
        if "rate" not in row:
            rows.append([label, row.get("reason") or row.get("status", ""), "", None, None, None, None, None])
            continue
        ratio = None if collect else row.get("x_fourrooms", 1.0 if name == "mw-fourrooms" else None)
        rows.append([label, round(float(row["rate"]), 2 if collect else 0),
                     "trajectories/s" if collect else "steps/s", ratio,
                     None if collect else row.get("cpu_x_fourrooms"), row.get("reset_ms"), row.get("reset_ms_mean"),
                     row.get("x_vec1")])
    machine = report.get("machine", {})
    load = machine.get("load_before", [None])[0], machine.get("load_after", [None])[0]
    args = report.get("args", {})
    note = (f"{args.get('rounds')} rounds x {args.get('steps')} steps per row at {args.get('size')}x{args.get('size')}, "
            f"one core (the N=2 vector rows: all cores), rows alternating; GL {machine.get('gl_renderer')}; "
            f"load {load[0]:.1f} before, {load[1]:.1f} after. Ratios are medians of per-round ratios to "
            "Miniworld's FourRooms measured in the same run.")
    return Table(["row", "rate", "unit", "x MW FourRooms", "cpu x MW FourRooms", "reset ms (median)",
                  "reset ms (mean)", "N=2 / N=1"], rows, note=note,
                 formats=["", "g", "", ".2f", ".2f", ".1f", ".1f", ".2f"])


def throughput() -> Table:
    """docs/performance.md, "Training-loop throughput": ``benchmarks/throughput.py``."""
    return throughput_table(benchmark("throughput.py", THROUGHPUT_ARGS))


FIGURES["throughput"] = Figure("throughput", "python benchmarks/throughput.py " + " ".join(THROUGHPUT_ARGS),
                               throughput, cheap=False)


def benchmark(script: str, args: Sequence[str]) -> dict[str, Any]:
    """Run ``benchmarks/<script>`` with ``args`` and ``--json``; its report."""

    with tempfile.TemporaryDirectory() as scratch:
        out = Path(scratch) / "report.json"
        subprocess.run([sys.executable, str(ROOT / "benchmarks" / script), *args, "--json", str(out)], check=True,
                       cwd=ROOT)
        return json.loads(out.read_text())


def _load_note(report: dict[str, Any]) -> str:
    machine = report["machine"]
    return f"Load average {machine['load_before']:.1f} before the run, {machine['load_after']:.1f} after."


RENDER_ARGS = ("--frames", "600")


def render_speed(args: Sequence[str] = RENDER_ARGS) -> Table:
    """docs/performance.md, "Rendering": ``benchmarks/render.py``: frames/s of our renderer,
    MuJoCo's own renderer drawing the same image, and the naive build, in one run."""
    report = benchmark("render.py", args)
    rows: list[list[Any]] = []
    for size, r in report["rows"].items():
        if size.isdigit():
            rows.append([int(size), round(r["ours_fps"]), round(r["stock_fps"]), r["ours_fps"] / r["stock_fps"],
                         round(r["naive_fps"], 1), r["ours_fps"] / r["naive_fps"]])
    note = (f"Egocentric RGB of `examples/scenes/two_room_furnished.json`, the agent turning, one core. Building the "
            f"scene: {report['rows']['build']['ms']:.1f} ms (median); a renderer for a new scene once the process's "
            f"GL context exists: {report['rows']['renderer']['ms']:.1f} ms. " + _load_note(report))
    return Table(["size", "ours (`fast`) fps", "stock fps", "ours/stock", "naive build fps", "ours/naive"], rows,
                 note=note, formats=["d", "d", "d", ".2f", ".1f", ".0f"])


STEP_ARGS = ("--ids", "Legent/ComeHere-OneRoom-v0,Legent/ComeHere-TwoRoom-v0,Legent/WhereIs-TwoRoom-v0",
             "--steps", "3000", "--resets", "20")


def step_speed(args: Sequence[str] = STEP_ARGS) -> Table:
    """docs/performance.md, "Environment steps": ``benchmarks/step.py``: steps/s beside the raw
    render of the same poses, and the median reset with a new house."""
    report = benchmark("step.py", args)
    rows = [[env_id.replace("Legent/", ""), round(r["steps_per_s"]), round(r["render_per_s"]), r["ratio"],
             r["cpu_ratio"], r["reset_ms"]] for env_id, r in report["rows"].items()]
    note = (f"{report['args']['steps']:,} steps at {report['args']['size']} px, one core, random text actions; "
            "steps and raw renders alternate in blocks of "
            f"{report['args']['block']}. " + _load_note(report))
    return Table(["env id", "steps/s", "raw render/s", "ratio", "cpu ratio", "reset ms (median)"], rows, note=note,
                 formats=["", "d", "d", ".2f", ".2f", ".1f"])


GENERATION_ARGS = ("--houses", "30")


def generation_speed(args: Sequence[str] = GENERATION_ARGS) -> Table:
    """docs/performance.md, "House generation": ``benchmarks/generation.py``: ms per house
    by stage, and the MuJoCo compile of the same scenes (the reference, the same run)."""
    report = benchmark("generation.py", args)
    rows = [[int(n), r["gen"], r["build"], r["compile"], r["nav"], r["total"], r["houses_per_s"], r["path"],
             r["path_p95"]] for n, r in report["rows"].items()]
    note = (f"Medians over {report['args']['houses']} houses per size, one core; each stage's median of its own, so "
            "they need not add up to the total. " + _load_note(report))
    return Table(["rooms", "generation ms", "build ms", "of it compile ms", "nav grid ms", "total ms", "houses/s",
                  "path query ms (median)", "p95"], rows, note=note,
                 formats=["d", ".1f", ".1f", ".1f", ".1f", ".1f", ".1f", ".2f", ".2f"])


EXPERT_SPEED_ARGS = ("--ids", "Legent/ComeHere-OneRoom-v0,Legent/PickUp-OneRoom-v0,Legent/PutOn-FourRoom-v0",
                     "--attempts", "40", "--workers", "1", "--collect-ids", "Legent/ComeHere-OneRoom-v0")


def expert_speed(args: Sequence[str] = EXPERT_SPEED_ARGS) -> Table:
    """docs/experts.md, "Measured": ``benchmarks/experts.py``: the expert's planning time per
    action and what collection gets, resets included, one worker on one core."""
    report = benchmark("experts.py", args)
    rows: list[list[Any]] = []
    for key, r in report["rows"].items():
        env_id = key.rsplit(" ", 1)[0].replace("Legent/", "")
        if key.endswith("collect x1"):
            rows.append([env_id.removesuffix(" collect") + ", `legent-gym collect`", None, None,
                         r["trajectories_per_s"], r["trajectories_per_cpu_s"], None, r["success_rate"]])
        else:
            rows.append([env_id, r["expert_ms"], r["actions_per_s"], r["trajectories_per_s"],
                         r["trajectories_per_cpu_s"], r["reset_ms"], r["success_rate"]])
    note = (f"{report['args']['size']} x {report['args']['size']} images, {report['args']['attempts']} attempts each (a reset with a new house, then the expert's action until the episode "
            "ends), one worker pinned to one core. `traj/cpu-s` is the rate per second of CPU time used: what an "
            "idle core would give. " + _load_note(report))
    return Table(["env", "expert ms per action (median)", "actions/s", "trajectories/s", "traj/cpu-s",
                  "reset ms (median)", "expert success"], rows, note=note,
                 formats=["", ".2f", ".0f", ".1f", ".1f", ".1f", ".0%"])


FIGURES.update({f.name: f for f in (
    Figure("render", "python benchmarks/render.py " + " ".join(RENDER_ARGS), render_speed, cheap=False),
    Figure("step", "python benchmarks/step.py " + " ".join(STEP_ARGS), step_speed, cheap=False),
    Figure("generation", "python benchmarks/generation.py " + " ".join(GENERATION_ARGS), generation_speed,
           cheap=False),
    Figure("expert-speed", "python benchmarks/experts.py " + " ".join(EXPERT_SPEED_ARGS), expert_speed,
           cheap=False),
)})


# -- the DAgger round over more seeds -------------------------------------------------------------
DAGGER_FIGURE = "table-full-p25-scan-dagger"
DAGGER_EPISODES = 300


def dagger_more_seeds() -> Table:
    """docs/results.md, "One DAgger round": the Sep 10K models of the DAgger run and the
    DAgger models trained from them, each on the task it was trained for, over reset seeds
    0-299 (greedy decoding). Reads the models that ``table-full-p25-scan-dagger`` left in its
    run folder, so it is measured after that figure."""
    # imported here: the baselines' modules import torch (seconds); --check and --show need none
    from baselines.reproduce_table import (
        COLUMNS,
        EVAL_TASKS,
        SCALES,
        TRAIN_TASKS,
        evaluate_rows,
        table_rows,
    )
    from baselines.vla.evaluate import success_rate

    out = figure(DAGGER_FIGURE).command.split("--out ")[1].split()[0]
    root, scale = ROOT / out, SCALES["full"]
    large = f"VLA-Sep {scale.large // 1000}K (ours)"
    wanted = (large, f"VLA-Sep {scale.large // 1000}K + DAgger (ours)")
    rows = [(label, {t: spec for t, spec in specs.items() if t in TRAIN_TASKS})
            for label, specs in table_rows(root, scale, dagger=True) if label in wanted]
    missing = sorted({spec for _, specs in rows for spec in specs.values() if not Path(spec).is_file()})
    if missing:
        raise FigureError(f"no model {shown(Path(missing[0]))}: run `python -m baselines.refresh --only "
                          f"{DAGGER_FIGURE}` first (its models are what this figure evaluates)")
    results = evaluate_rows(rows, scale, DAGGER_EPISODES, 0, workers=os.cpu_count() or 1)
    table_rows_, errors = [], []
    for label, by_task in results.items():
        rates = [success_rate(by_task[t]) for t in TRAIN_TASKS]
        table_rows_.append([label, *rates])
        errors.append([None, *(_rate_stderr(r, DAGGER_EPISODES) for r in rates)])
    columns = ["Model", *(COLUMNS[EVAL_TASKS.index(t)] for t in TRAIN_TASKS)]
    return Table(columns, table_rows_, errors, seeds=f"0-{DAGGER_EPISODES - 1} (evaluation)",
                 note=f"Success rates over {DAGGER_EPISODES} seeded episodes per task, greedy decoding; a standard "
                      f"error is about 0.03. Each model on the task it was trained for.",
                 formats=["", ".3f", ".3f", ".3f"])


FIGURES["dagger-more-seeds"] = Figure(
    "dagger-more-seeds", "python -m baselines.refresh --only dagger-more-seeds", dagger_more_seeds, cheap=False)


# -- what --scale full measures -------------------------------------------------------------------
FULL_SCALE_FIGURE = "full-scale-cost"


def full_scale_cost() -> Table:
    """Every figure that ``python -m baselines.refresh --scale full`` measures (not those made
    from other data files; a table still adopted from a doc is listed with no time): the commit
    it was last measured at,
    when, and its run's wall time; the last row sums them, a run that measured two figures
    (the same command) counted once (nothing measured)."""
    rows: list[list[Any]] = []
    commands: set[str] = set()
    total, unknown = 0.0, 0
    for name, fig in FIGURES.items():
        if fig.produce is None or name == FULL_SCALE_FIGURE:
            continue
        data = load(name)
        if data.get("made_from"):
            continue
        commit = data["commit"][:7] + (" with uncommitted changes" if data.get("dirty") else "")
        if data.get("typed"):  # adopted from a doc: its run's time was not kept
            rows.append([f"`{name}`", "no", f"{commit} (typed)", data["date"], None, None])
            unknown += 1
            continue
        wall = float(data["wall_seconds"])
        if data["command"] not in commands:
            commands.add(data["command"])
            total += wall
        rows.append([f"`{name}`", "yes" if fig.cheap else "no", commit, data["date"], wall, wall / 3600])
    label = f"all {len(rows)} ({len(commands)} runs" + (f"; without the {unknown} typed)" if unknown else ")")
    rows.append([label, "", "", "", total, total / 3600])
    note = ("Each wall time is its figure's own run as it was measured, on the machine its figure names; a run "
            "that started from another run's data or models (its phases are in its `-run` table) takes longer "
            "from nothing. `--scale full` runs them one after another in this order, the table runs that "
            "continue another run after it.")
    if unknown:
        note += " A table still typed in a doc (adopted, see its block) kept no wall time; `--scale full` measures it too."
    return Table(["figure", "cheap", "measured at", "date", "wall time (s)", "hours"], rows, note=note,
                 formats=["", "", "", "", ".0f", ".2f"],
                 made_from="the data files of the figures it lists (`docs/data/figures/<figure>.json`)")


FIGURES[FULL_SCALE_FIGURE] = Figure(FULL_SCALE_FIGURE, f"python -m baselines.refresh --only {FULL_SCALE_FIGURE}",
                                    full_scale_cost, cheap=True)


def figure(name: str) -> Figure:
    try:
        return FIGURES[name]
    except KeyError:
        raise FigureError(f"no figure named {name!r}; known: {', '.join(FIGURES)}") from None

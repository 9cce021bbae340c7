"""`baselines/reproduce_table.py --scale small --dagger` end to end, as CI runs it:
`legent-gym collect`, seven trainings, a DAgger round and three more trainings, six rows x
four tasks of evaluation, and the table in Markdown, CSV and PNG (the outputs are checked,
not the success rates)."""

from __future__ import annotations

import csv
import dataclasses
import json
import subprocess
import sys
from pathlib import Path

import pytest

pytest.importorskip("torch", reason="install the 'baselines' extra: pip install -e '.[baselines]'")
pytest.importorskip("matplotlib", reason="install the 'baselines' extra: pip install -e '.[baselines]'")

from PIL import Image  # noqa: E402

from baselines.reproduce_table import (  # noqa: E402
    EVAL_TASKS,
    PAPER_ROWS,
    PAPER_WHERE_IS_NOTE,
    SCALES,
    TRAIN_TASKS,
    _trained,
    collect_command,
    dagger_folder,
    dagger_runs,
    data_folder,
    main,
    markdown_table,
    run,
    task_options,
    training_runs,
)
from baselines.vla.checkpoint import load_model  # noqa: E402

SCRIPT = Path(__file__).resolve().parents[2] / "baselines" / "reproduce_table.py"
OUR_ROWS = 6  # random, Sep small, Sep large, Joint, Sep large + DAgger, expert


def check_outputs(out: Path, scale: str, paper_where_is: bool = False) -> dict:
    """The table in its three forms, the checkpoints and the record of the run."""
    config = SCALES[scale]
    md = (out / "table.md").read_text().splitlines()
    assert md[0].startswith("| Model | Come Here, one room |") and len(md[0].split("|")) == 7
    body = [line for line in md[2:] if line.startswith("|")]
    assert len(body) == len(PAPER_ROWS) + OUR_ROWS
    assert body[len(PAPER_ROWS)].startswith("| Random |") and body[-1].startswith("| Expert (privileged) |")
    rows = list(csv.reader((out / "table.csv").open()))
    assert rows[0] == ["model", "source", *EVAL_TASKS] and len(rows) == 1 + len(PAPER_ROWS) + OUR_ROWS
    for row in rows[1:]:
        assert all(0.0 <= float(x) <= 1.0 for x in row[2:])
    with Image.open(out / "table.png") as image:
        assert image.format == "PNG" and image.size[0] >= 800 and image.size[1] >= 300
    results = json.loads((out / "results.json").read_text())
    assert results["scale"] == scale and results["house_overlap_eval_vs_data"] == 0
    assert set(results["wall_seconds"]) == {"data", "training", "dagger_data", "dagger_training", "evaluation",
                                            "total"}
    assert results["dagger"] == config.dagger_rollouts
    for label, per_task in results["episodes"].items():
        for task in EVAL_TASKS:
            assert [e["seed"] for e in per_task[task]] == list(range(config.episodes)), (label, task)
    models = sorted(p.parent.name for p in (out / "models").glob("*/model.pt"))
    assert len(models) == 10  # 3 tasks x 2 amounts, the joint model and 3 DAgger models
    model, _ = load_model(out / "models" / f"joint{config.large}" / "model.pt")
    assert model.config.image_size == config.image_size
    for task in TRAIN_TASKS:
        progress = json.loads((data_folder(out, task, paper_where_is=paper_where_is) / "progress.json").read_text())
        assert progress["progress"]["committed"] == config.large
        # results.json keeps what each collection and DAgger round made (the run's figures read it).
        assert results["collections"][task] == {"trajectories": config.large,
                                                "failed_attempts": progress["progress"]["failures"],
                                                "steps": progress["progress"]["total_steps"]}
        dagger = json.loads((dagger_folder(out, task, config, paper_where_is) / "dagger.json").read_text())
        assert dagger["episodes"] == config.dagger_rollouts and dagger["config"]["policy"].endswith(
            f"sep{config.large}-{task}/model.pt")
        assert results["dagger_rounds"][task] == {k: dagger[k] for k in ("episodes", "learner_success", "steps",
                                                                         "seconds")}
        # The DAgger model learned from the demonstrations and every rollout.
        metrics = results["training"][f"sep{config.large}-{task}-dagger"]["metrics"]
        assert metrics["trajectories"] == config.large + config.dagger_rollouts
    # Its folders are kept relative to the run's folder: the file names no folder of this machine.
    for name, entry in results["training"].items():
        assert entry["config"]["out"] == f"models/{name}"
        assert all(d.startswith("data/") and (out / d).is_dir() for d in entry["config"]["data"]), name
    return results


def test_small_scale_from_the_command_line(tmp_path):
    done = subprocess.run([sys.executable, str(SCRIPT), "--scale", "small", "--dagger", "--out", str(tmp_path)],
                          capture_output=True, text=True, timeout=900)
    assert done.returncode == 0, done.stderr[-3000:]
    assert "| VLA-Joint 20 (ours) |" in done.stdout and "house seeds shared" in done.stdout
    assert "| VLA-Sep 20 + DAgger (ours) |" in done.stdout
    results = check_outputs(tmp_path, "small")
    # The models learned: together, the trained models answer Where Is questions, which the
    # random policy never does (it names no object). Come Here is no test of learning at this
    # scale: a random walk reaches the user in about half the one-room episodes, and 10
    # episodes a task put any model within the noise of that.
    rates = results["success_rates"]
    where_is = [task for task in rates["Random"] if task.startswith("WhereIs")]
    assert sum(rates["Random"][task] for task in where_is) == 0, rates
    trained = [model for model in rates if "(ours)" in model]
    assert sum(rates[model][task] for model in trained for task in where_is) > 0, rates
    # The run's figure (models, validation, phases, collections, DAgger rounds) reads that record.
    from baselines.figures import run_table

    run = run_table(results)
    assert [row[0] for row in run.rows] == list(results["training"])
    assert "DAgger rounds" in run.note and "Collections" in run.note and "dagger training" in run.note
    # A second run would resume: every model is recognised as trained by this configuration.
    folders = {task: tmp_path / "data" / task for task in TRAIN_TASKS}
    dagger = {task: dagger_folder(tmp_path, task, SCALES["small"]) for task in TRAIN_TASKS}
    runs = {**training_runs(tmp_path, folders, SCALES["small"]),
            **dagger_runs(tmp_path, folders, dagger, SCALES["small"])}
    assert all(_trained(config) for config in runs.values())
    # The tables can be redrawn from results.json alone.
    markdown, table = (tmp_path / "table.md").read_text(), (tmp_path / "table.csv").read_text()
    for name in ("table.md", "table.csv", "table.png"):
        (tmp_path / name).unlink()
    assert main(["--scale", "small", "--out", str(tmp_path), "--redraw"]) == 0
    assert (tmp_path / "table.md").read_text() == markdown and (tmp_path / "table.csv").read_text() == table
    assert (tmp_path / "table.png").stat().st_size > 10_000


def test_paper_questions_with_dagger_and_film_from_the_command_line(tmp_path):
    """The options that change what is trained, together: LEGENT's Where Is questions reach
    the DAgger rollouts too, and every model has the FiLM encoder."""
    done = subprocess.run([sys.executable, str(SCRIPT), "--scale", "small", "--dagger", "--paper-where-is",
                           "--film", "--out", str(tmp_path)], capture_output=True, text=True, timeout=900)
    assert done.returncode == 0, done.stderr[-3000:]
    assert PAPER_WHERE_IS_NOTE in done.stdout
    results = check_outputs(tmp_path, "small", paper_where_is=True)
    assert results["paper_where_is"] is True
    assert {entry["config"]["model"]["film"] for entry in results["training"].values()} == {True}
    where = json.loads((dagger_folder(tmp_path, "WhereIs-OneRoom", SCALES["small"], True) / "dagger.json").read_text())
    assert where["config"]["env_kwargs"] == {"task_options": task_options("WhereIs-OneRoom", True)}
    assert dagger_folder(tmp_path, "WhereIs-OneRoom", SCALES["small"], True).name.startswith("WhereIs-OneRoom-paper-")
    come = json.loads((dagger_folder(tmp_path, "ComeHere-OneRoom", SCALES["small"], True) / "dagger.json").read_text())
    assert come["config"]["env_kwargs"] == {}
    # Every Where Is episode, trained on or evaluated, asked about one of LEGENT's objects.
    objects = ("orange", "apple", "banana", "cola")  # as the instructions name them
    for per_task in results["episodes"].values():
        for task in ("WhereIs-OneRoom", "WhereIs-TwoRoom"):
            assert all(any(o in e["instruction"] for o in objects) for e in per_task[task]), task


def test_bad_arguments_are_named(tmp_path):
    with pytest.raises(ValueError, match="unknown scale 'huge'"):
        run("huge", tmp_path, workers=1)
    with pytest.raises(ValueError, match="workers must be >= 1"):
        run("small", tmp_path, workers=0)
    with pytest.raises(ValueError, match="perturb must be in"):
        run("small", tmp_path, workers=1, perturb=1.0)
    assert main(["--out", str(tmp_path / "none"), "--redraw"]) == 2  # no results.json to redraw
    assert main(["--out", str(tmp_path / "c"), "--channels", "8,x"]) == 2
    with pytest.raises(ValueError, match="multiple of 32"):  # five halvings of a 48 px view
        run("small", tmp_path / "c", workers=1, channels=(8, 8, 8, 8, 8))
    with pytest.raises(ValueError, match="epochs_large must be >= 1"):
        run("small", tmp_path / "c", workers=1, epochs_large=0)
    with pytest.raises(ValueError, match="shift must be in"):
        run("small", tmp_path / "c", workers=1, shift=-1)
    assert not (tmp_path / "c").exists()  # refused before anything was written


def test_encoder_options_and_epochs_reach_every_large_model(tmp_path):
    scale = dataclasses.replace(SCALES["small"], channels=(8, 16, 32, 64), epochs_large=5, film=True, shift=3)
    folders = {task: tmp_path / task for task in TRAIN_TASKS}
    runs = training_runs(tmp_path, folders, scale)
    assert {r.model.channels for r in runs.values()} == {(8, 16, 32, 64)}
    assert {r.model.film for r in runs.values()} == {True}
    assert {r.shift for r in runs.values()} == {3}
    assert {r.epochs for name, r in runs.items() if str(scale.large) in name} == {5}


def test_recovery_data_has_its_own_folders_and_collect_flag(tmp_path):
    scale = SCALES["small"]
    clean = collect_command("ComeHere-OneRoom", 0, 5, data_folder(tmp_path, "ComeHere-OneRoom"), scale, 1)
    assert "--perturb" not in clean and clean[clean.index("--out") + 1] == str(tmp_path / "data" / "ComeHere-OneRoom")
    folder = data_folder(tmp_path, "ComeHere-OneRoom", 0.25)
    assert folder == tmp_path / "data" / "ComeHere-OneRoom-perturb0.25"
    perturbed = collect_command("ComeHere-OneRoom", 0, 5, folder, scale, 1, perturb=0.25)
    assert perturbed[-2:] == ["--perturb", "0.25"] and perturbed[:-2] == clean[:clean.index("--out") + 1] + [
        str(folder)] + clean[clean.index("--out") + 2:]


def test_scan_changes_only_the_where_is_data(tmp_path):
    scale = SCALES["small"]
    come = data_folder(tmp_path, "ComeHere-OneRoom", scan=True)
    assert come == tmp_path / "data" / "ComeHere-OneRoom"  # Come Here calls no find(): the same data
    assert "--find-strategy" not in collect_command("ComeHere-OneRoom", 0, 5, come, scale, 1, scan=True)
    where = data_folder(tmp_path, "WhereIs-OneRoom", 0.25, scan=True)
    assert where == tmp_path / "data" / "WhereIs-OneRoom-scan-perturb0.25"
    command = collect_command("WhereIs-OneRoom", 2, 5, where, scale, 1, perturb=0.25, scan=True)
    assert command[-4:] == ["--perturb", "0.25", "--find-strategy", "scan"]


def test_paper_where_is_changes_only_the_where_is_data_and_envs(tmp_path):
    scale = SCALES["small"]
    assert data_folder(tmp_path, "ComeHere-OneRoom", 0.25, True, True) == tmp_path / "data" / "ComeHere-OneRoom-perturb0.25"
    assert "--env-kwargs" not in collect_command("ComeHere-TwoRoom", 1, 5, tmp_path, scale, 1, paper_where_is=True)
    where = data_folder(tmp_path, "WhereIs-OneRoom", 0.25, True, True)
    assert where == tmp_path / "data" / "WhereIs-OneRoom-paper-scan-perturb0.25"
    command = collect_command("WhereIs-OneRoom", 2, 5, where, scale, 1, 0.25, True, True)
    options = json.loads(command[command.index("--env-kwargs") + 1])["task_options"]
    assert options == {"objects": ["orange", "apple", "banana", "cola_can"],
                       "receptacles": ["sofa", "chair", "dining_table", "coffee_table", "side_table",
                                       "kitchen_counter", "dresser"]}
    assert task_options("WhereIs-TwoRoom", True) == options and task_options("WhereIs-TwoRoom", False) == {}
    assert PAPER_WHERE_IS_NOTE in markdown_table([("Random", [0.0] * 4)], 10, paper_where_is=True)

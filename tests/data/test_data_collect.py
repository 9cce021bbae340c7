"""`legent-gym collect`: kill -9 in the middle, resume, failures, workers."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from dataclasses import replace

import numpy as np
import pytest

from legent_gym.cli import main
from legent_gym.data import CollectConfig, CollectError, collect
from legent_gym.data.legent_format import load_interleaved, load_trajectories, read_png
from legent_gym.data.minari_store import load_minari_dataset
from tests.conftest import REPO

ENV_ID = "Legent/ComeHere-OneRoom-v0"
DATASET_ID = "legent/ComeHere-OneRoom/expert-v0"
SIZE = ["--width", "32", "--height", "32"]


def expert_on_even_houses(obs, info):
    """The expert, except that it gives up at once in houses with an odd seed."""
    return "finish()" if info["house_seed"] % 2 else info["expert_action"]


def give_up(obs, info):
    return "finish()"


def _committed(out) -> int:
    try:
        return json.loads((out / "progress.json").read_text())["progress"]["committed"]
    except (FileNotFoundError, json.JSONDecodeError):
        return 0


def _group_gone(pgid: int, timeout: float = 0.0) -> bool:
    deadline = time.monotonic() + timeout
    while True:
        try:
            os.killpg(pgid, 0)
        except ProcessLookupError:
            return True
        if time.monotonic() >= deadline:
            return False
        time.sleep(0.2)


def _check_whole(out, expected: int | None = None) -> int:
    """The dataset loads and its formats agree; returns the number of episodes."""
    dataset = load_minari_dataset(out / "minari", DATASET_ID)
    episodes = list(dataset.iterate_episodes())
    trajectories = load_trajectories(out / "legent")
    assert len(trajectories) <= len(episodes)  # the aggregates may lag, never lead
    for trajectory, episode in zip(trajectories, episodes):
        steps = trajectory["interactions"][1]["trajectory"]  # and LEGENT's closing finish() on the last view
        assert len(steps) == len(episode.actions) + 1 and episode.infos["success"][-1]
        for n, step in enumerate(steps):
            assert np.array_equal(read_png(out / "legent" / step["image"]), episode.observations["rgb"][n])
    seeds = [m["seed"] for m in dataset.storage.get_episode_metadata(range(dataset.total_episodes))]
    assert len(seeds) == len(set(seeds)), "an episode was recorded twice"
    if expected is not None:
        assert dataset.total_episodes == expected == len(trajectories)
        assert len(load_interleaved(out / "legent")) == dataset.total_steps
    return dataset.total_episodes


def test_kill_9_mid_collect_then_resume_completes_exactly_n(tmp_path):
    out, n = tmp_path / "run", 10
    command = [sys.executable, "-m", "legent_gym.cli", "collect", ENV_ID, "--episodes", str(n), "--out", str(out),
               "--format", "minari,legent", "--workers", "2", "--quiet", *SIZE]
    proc = subprocess.Popen(command, cwd=REPO, start_new_session=True, stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT)
    try:
        deadline = time.monotonic() + 120
        while _committed(out) < 2 and proc.poll() is None and time.monotonic() < deadline:
            time.sleep(0.02)
        assert proc.poll() is None, proc.stdout.read().decode()[-2000:]
        os.kill(proc.pid, signal.SIGKILL)
        proc.wait()
        # Its workers notice and leave (nothing keeps running after a kill -9).
        assert _group_gone(proc.pid, timeout=15)
    finally:
        if not _group_gone(proc.pid):  # only the processes this test started
            os.killpg(proc.pid, signal.SIGKILL)
        proc.stdout.close()

    survived = _check_whole(out)
    assert 2 <= survived < n

    # Resume with one worker: the same episodes as an uninterrupted run of either kind.
    assert main(["collect", ENV_ID, "--episodes", str(n), "--out", str(out), "--format", "minari,legent",
                 "--quiet", *SIZE]) == 0
    assert _check_whole(out, expected=n) == n
    reference = tmp_path / "reference"
    collect(CollectConfig(ENV_ID, n, str(reference), formats=("minari", "legent"),
                          env_kwargs={"width": 32, "height": 32}), show_progress=False)
    assert load_trajectories(out / "legent") == load_trajectories(reference / "legent")
    assert (out / "legent" / "interleaved.jsonl").read_bytes() == (reference / "legent" / "interleaved.jsonl").read_bytes()

    # A finished collection asked again is left as it is.
    assert main(["collect", ENV_ID, "--episodes", str(n), "--out", str(out), "--format", "minari,legent",
                 "--quiet", *SIZE]) == 0
    assert _check_whole(out, expected=n) == n


def test_only_successes_are_kept_and_failures_are_counted(tmp_path):
    config = CollectConfig(ENV_ID, 3, str(tmp_path), formats=("minari", "legent"),
                           env_kwargs={"width": 32, "height": 32}, policy="tests.data.test_data_collect:expert_on_even_houses")
    summary = collect(config, show_progress=False)
    assert summary.episodes == 3 and summary.failures > 0
    assert summary.attempts == summary.episodes + summary.failures
    trajectories = load_trajectories(tmp_path / "legent")
    assert all(t["success"] and t["house_seed"] % 2 == 0 for t in trajectories)
    progress = json.loads((tmp_path / "progress.json").read_text())["progress"]
    assert progress["failures"] == summary.failures and progress["next_attempt"] == summary.attempts
    # Growing the collection continues from the next attempt, never repeating one.
    summary = collect(replace(config, episodes=5), show_progress=False)
    attempts = [t["attempt"] for t in load_trajectories(tmp_path / "legent")]
    assert summary.new_episodes == 2 and attempts == sorted(set(attempts)) and len(attempts) == 5


def test_a_policy_that_never_succeeds_stops_at_the_attempt_limit(tmp_path):
    config = CollectConfig(ENV_ID, 2, str(tmp_path), formats=("legent",), env_kwargs={"width": 32, "height": 32},
                           policy="tests.data.test_data_collect:give_up", max_attempts=4)
    with pytest.raises(CollectError, match="only 0 of 2 episodes succeeded in 4 attempts"):
        collect(config, show_progress=False)
    assert load_trajectories(tmp_path / "legent") == []


def test_perturbed_collection_depends_on_the_seed_alone_and_keeps_the_labels(tmp_path):
    """``--perturb``: random steps in place of the expert's, each labelled with the expert's
    action; two workers give the same trajectories as one, and the option is part of what a
    resumed run must share."""
    kwargs = {"width": 32, "height": 32}
    one = CollectConfig(ENV_ID, 4, str(tmp_path / "one"), formats=("legent",), env_kwargs=kwargs, perturb=0.4)
    collect(one, show_progress=False)
    collect(replace(one, out=str(tmp_path / "two"), workers=2), show_progress=False)
    first, second = (load_trajectories(tmp_path / name / "legent") for name in ("one", "two"))
    assert [t["interactions"] for t in first] == [t["interactions"] for t in second]
    steps = [s for t in first for s in t["interactions"][1]["trajectory"]]
    assert any("expert_action" in s for s in steps) and not all("expert_action" in s for s in steps)
    assert all(t["success"] for t in first)
    with pytest.raises(CollectError, match="perturb"):
        collect(replace(one, perturb=0.0), show_progress=False)
    with pytest.raises(CollectError, match="--perturb"):
        collect(replace(one, out=str(tmp_path / "bad"), perturb=1.0), show_progress=False)


def test_scan_collection_records_the_looking_expert(tmp_path):
    """``--find-strategy scan``: Where Is demonstrations in which an object out of view is
    found by the scan's fixed looks, where the direct expert turns straight to it (an object
    in view at the start is approached the same way by both); the strategy is part of what a
    resumed run must share."""

    def actions(strategy: list[str], folder: str) -> list[list[str]]:
        out = tmp_path / folder
        assert main(["collect", "Legent/WhereIs-OneRoom-v0", "--episodes", "3", "--out", str(out), "--format",
                     "legent", "--width", "32", "--height", "32", "--quiet", *strategy]) == 0
        trajectories = load_trajectories(out / "legent")
        assert len(trajectories) == 3 and all(t["success"] for t in trajectories)
        return [[s["action"] for s in t["interactions"][1]["trajectory"]] for t in trajectories]

    scanned, direct = actions(["--find-strategy", "scan"], "scan"), actions([], "direct")
    assert all(a[-1].startswith("speak(") for a in scanned)
    differing = [(s, d) for s, d in zip(scanned, direct) if s != d]
    assert differing, "no episode's object started out of view: the strategies were not compared"
    for s, d in differing:
        assert s[0].startswith("rotate_right(60)") and not d[0].startswith("rotate_right(60)"), (s, d)
    out = tmp_path / "scan"
    config = CollectConfig("Legent/WhereIs-OneRoom-v0", 3, str(out), formats=("legent",),
                           env_kwargs={"width": 32, "height": 32})
    with pytest.raises(CollectError, match="find_strategy"):
        collect(config, show_progress=False)  # the same folder, the direct expert: refused
    assert main(["collect", "Legent/WhereIs-OneRoom-v0", "--episodes", "1", "--out", str(tmp_path / "bad"),
                 "--find-strategy", "wander", "--quiet"]) != 0


def test_a_relative_out_folder(tmp_path, monkeypatch):
    # The command as a user types it in their project folder: `--out data/`.
    monkeypatch.chdir(tmp_path)
    assert main(["collect", "Legent/ComeHere-OneRoom-v0", "--episodes", "2", "--out", "data",
                 "--format", "minari,legent", "--width", "32", "--height", "32", "--quiet"]) == 0
    dataset = load_minari_dataset(tmp_path / "data" / "minari", DATASET_ID)
    assert dataset.total_episodes == 2 and len(load_trajectories(tmp_path / "data" / "legent")) == 2

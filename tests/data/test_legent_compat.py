"""Our LEGENT-format export, read as LEGENT's own scripts read LEGENT's data.

LEGENT's Python toolkit (github thunlp/LEGENT) drives a closed Unity client, so its scripts
cannot run here; this test opens our files by the names, layout and fields those scripts
use, and applies their rules (stated beside each check, with the file they are in):

* ``legent/dataset/trajectory.py`` (``TrajectorySaver``): per trajectory a folder of
  ``NNNN.png``, ``trajectory.json`` and ``task_setting.json``; ``trajectories.json`` is the
  list of the folders' ``trajectory.json``;
* ``scripts/llava/prepare_dataset.py``: reads ``trajectories.json``: ``id``,
  ``interactions[0]["text"]``, and per step of ``interactions[1]["trajectory"]`` its
  ``image`` (relative to the data folder) and ``action``;
* ``legent/dataset/controller.py`` and ``scripts/eval_model.py``: the task type is
  ``task_setting["task"].split(" ")[0].lower()``; ``legent/dataset/eval.py``
  (``task_done``): ``come`` succeeds within 2 m of the user, ``where`` when
  ``task_setting["answer"]`` is in the lower-cased text of the agent's ``speak("...")``
  (``legent/action/action.py``'s ``parse_action``: primitives split on ", ", the text
  matched by ``\\("(.*?)"\\)``);
* ``controller.collect_trajectory``: a Come Here trajectory ends with a ``finish()`` step on
  the final view (``add_finish_action=True``); a Where Is one ends with the answer.
"""

from __future__ import annotations

import json
import math
import re

import numpy as np
import pytest

from legent_gym.data import CollectConfig, collect
from legent_gym.data.legent_format import load_interleaved, read_png
from legent_gym.data.minari_store import load_minari_dataset

SIZE = 32
LEGENT_PRIMITIVES = ("move_forward", "rotate_right", "rotate_down", "speak", "grab", "finish")


def _legent_speech(action: str) -> str:
    """The ``text`` LEGENT's ``parse_action`` reads from an action string."""
    text = ""
    for elem in action.split(", "):
        if elem.startswith("speak"):
            match = re.search(r"\(\"(.*?)\"\)", elem)
            text = match.group(1) if match else text
    return text


@pytest.fixture(scope="module", params=["Legent/ComeHere-OneRoom-v0", "Legent/WhereIs-OneRoom-v0"])
def export(request, tmp_path_factory):
    out = tmp_path_factory.mktemp("legent")
    collect(CollectConfig(request.param, 2, str(out), formats=("minari", "legent"),
                          env_kwargs={"width": SIZE, "height": SIZE}), show_progress=False)
    return request.param, out


def test_legent_scripts_read_our_export(export):
    env_id, out = export
    data = out / "legent"
    folders = sorted(p for p in data.iterdir() if p.is_dir())
    assert len(folders) == 2
    # TrajectorySaver.save: trajectories.json is the folders' trajectory.json files
    aggregated = json.loads((data / "trajectories.json").read_text())
    assert sorted(aggregated, key=lambda t: t["id"]) == [json.loads((f / "trajectory.json").read_text())
                                                         for f in folders]
    minari = load_minari_dataset(out / "minari", f"legent/{env_id.split('/')[1][:-3]}/expert-v0")
    for folder, episode in zip(folders, minari.iterate_episodes(), strict=True):
        trajectory = json.loads((folder / "trajectory.json").read_text())
        setting = json.loads((folder / "task_setting.json").read_text())
        # prepare_dataset.py
        task = trajectory["interactions"][0]["text"]
        steps = trajectory["interactions"][1]["trajectory"]
        assert trajectory["id"] == folder.name and task == setting["instruction"]
        for n, step in enumerate(steps):
            assert step["image"] == f"{folder.name}/{n:04d}.png"
            assert np.array_equal(read_png(data / step["image"]), episode.observations["rgb"][n])
            assert all(p.startswith(LEGENT_PRIMITIVES) for p in step["action"].split(", ")), step["action"]
        # controller.py / eval_model.py / eval.py
        task_type = setting["task"].split(" ")[0].lower()
        last = steps[-1]["action"]
        if env_id.startswith("Legent/ComeHere"):
            assert task_type == "come"
            assert last == "finish()" and steps[-1]["after_end"] and len(steps) == len(episode.actions) + 1
            x, y = episode.infos["agent_pose"][-1][:2]
            ux, uy = episode.infos["user_pose"][-1][:2]
            assert math.hypot(ux - x, uy - y) < 2.0  # LEGENT's COME_DONE_DISTANCE
        else:
            assert task_type == "where"
            assert setting["answer"] in _legent_speech(last).lower()
            assert setting["answer"] == setting["answers"][0] == trajectory["task"]["answer"]
            assert len(steps) == len(episode.actions)
    # our interleaved samples are the steps the env ran (no sample for the closing finish())
    assert len(load_interleaved(data)) == minari.total_steps

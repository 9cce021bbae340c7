"""LEGENT's trajectory format and the image-text interleaved JSONL for VLA training.

Under the export root (``OUT/legent``):

* ``<id>/NNNN.png``: the agent's view before action N (lossless RGB);
* ``<id>/trajectory.json``: ``{"id", "interactions": [{"from": "human", "text": task},
  {"from": "agent", "trajectory": [{"image": "<id>/0000.png", "action": "..."}, ...]}]}``
  plus our own fields (``env_id``, ``seed``, ``attempt``, ``task``, ...); a step may also
  hold ``expert_action`` (the label of a perturbed or DAgger step) and ``goal_view`` (the
  privileged visibility, bearing and distance of the task's goal from that view). As in
  LEGENT, a successful trajectory of every task but Where Is ends with ``finish()`` on the
  final view, a step marked ``"after_end": true`` (the env ended the episode on success
  before it; :func:`closes_with_finish`);
* ``<id>/task_setting.json``: the task as LEGENT's scripts read it (:func:`task_setting_record`);
* ``trajectories.json``: the list of all trajectories (LEGENT's aggregated file);
* ``interleaved.jsonl``: one line per step the env ran (see :func:`interleaved_records`).

A trajectory folder is written under a temporary name and renamed into place, so it is
whole or absent. The two aggregate files are derived from the folders and rewritten
atomically at checkpoints; after a crash they may lag behind the folders, never disagree
with them, and the next run rebuilds them.
"""

from __future__ import annotations

import json
import os
import shutil
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from legent_gym.data.rollout import Episode
from legent_gym.utils.atomic import atomic_write_bytes

TRAJECTORY_FILE = "trajectory.json"
TASK_SETTING_FILE = "task_setting.json"
AGGREGATE_FILE = "trajectories.json"
INTERLEAVED_FILE = "interleaved.jsonl"
#: The paper's model reads the last 6 observations.
DEFAULT_WINDOW = 6
IMAGE_TOKEN = "<image>"


def encode_png(rgb: np.ndarray) -> bytes:
    # start-up time: cv2 only when images are encoded
    import cv2

    ok, data = cv2.imencode(".png", np.ascontiguousarray(rgb[..., ::-1]))
    if not ok:
        raise ValueError(f"could not encode an image of shape {rgb.shape} as PNG")
    return data.tobytes()


def read_png(path: str | os.PathLike) -> np.ndarray:
    """An RGB uint8 image from a PNG written by :func:`encode_png`."""
    # start-up time: cv2 only when images are encoded
    import cv2

    bgr = cv2.imread(str(path), cv2.IMREAD_COLOR)
    if bgr is None:
        raise FileNotFoundError(f"cannot read image {path}")
    return np.ascontiguousarray(bgr[..., ::-1])


def legent_task_type(instruction: str) -> str:
    """The task type as LEGENT's scripts read it: the instruction's first word, lower-cased
    (``come``, ``where``; ``task_setting["task"].split(" ")[0].lower()``)."""
    return instruction.split(" ")[0].lower()


def closes_with_finish(episode: Episode) -> bool:
    """Whether the trajectory ends with LEGENT's closing ``finish()``: LEGENT's trajectory
    collection appends it to a successful trajectory of every task but Where Is (whose last
    action is the answer), where the last action is not a ``finish()`` already."""
    last = episode.action_texts[-1] if episode.action_texts else ""
    return (episode.success and legent_task_type(episode.paper_instruction) != "where"
            and not last.endswith("finish()"))


def _task(episode: Episode) -> dict[str, Any]:
    task = dict(episode.task)
    if task.get("answers"):  # WhereIs: LEGENT's ``answer`` (what its success test looks for)
        task["answer"] = task["answers"][0]
    return task


def trajectory_record(episode: Episode, traj_id: str) -> dict[str, Any]:
    """The ``trajectory.json`` of an episode."""
    steps: list[dict[str, Any]] = [{"image": f"{traj_id}/{n:04d}.png", "action": text}
                                   for n, text in enumerate(episode.action_texts)]
    for step, label in zip(steps, episode.labels):
        if label is not None:  # a perturbed or DAgger step (record_episode): the expert's action
            step["expert_action"] = label
    for step, view in zip(steps, episode.goal_views):
        if view is not None:  # privileged labels of the view (ExpertInfo's info["goal_view"])
            step["goal_view"] = view
    if closes_with_finish(episode):
        n = episode.steps
        steps.append({"image": f"{traj_id}/{n:04d}.png", "action": "finish()", "after_end": True})
        if episode.goal_views[n] is not None:
            steps[-1]["goal_view"] = episode.goal_views[n]
    return {
        "id": traj_id,
        "interactions": [
            {"from": "human", "text": episode.instruction},
            {"from": "agent", "trajectory": steps},
        ],
        "env_id": episode.env_id,
        "seed": episode.seed,
        "attempt": episode.attempt,
        "task": _task(episode),
        "house_seed": episode.house_seed,
        "scene_name": episode.scene_name,
        "success": episode.success,
        "steps": episode.steps,
        "return": float(sum(episode.rewards)),
    }


def task_setting_record(episode: Episode) -> dict[str, Any]:
    """The ``task_setting.json`` of an episode: LEGENT's fields where it has them, ``task``
    (the goal in the paper's words, whose first word LEGENT's scripts read as the task
    type) and, for Where Is, ``answer`` (the word LEGENT's success test looks for in the
    answer); then ours: ``instruction`` (what the user said: the trajectory's ``text``),
    the task (``task_name``, goal ids, ``answers``), and how to play it again."""
    task = _task(episode)
    record: dict[str, Any] = {"task": episode.paper_instruction}
    if "answer" in task:
        record["answer"] = task["answer"]
    record.update(instruction=episode.instruction, task_name=task.pop("name", None), **task,
                  env_id=episode.env_id, seed=episode.seed, house_seed=episode.house_seed,
                  scene_name=episode.scene_name)
    return record


def build_prompt(instruction: str, history: Sequence[str]) -> str:
    """``Instruction: <i> Observation: <image> Action: <a> ... Observation: <image> Action:``
    with one ``<image>`` per image (``len(history) + 1``)."""
    parts = [f"Instruction: {instruction}"]
    parts += [f"Observation: {IMAGE_TOKEN} Action: {action}" for action in history]
    parts.append(f"Observation: {IMAGE_TOKEN} Action:")
    return " ".join(parts)


def interleaved_records(trajectory: dict[str, Any], window: int = DEFAULT_WINDOW) -> list[dict[str, Any]]:
    """One training sample per step of a trajectory record: the last ``window`` views up
    to and including the step, the actions between them, the prompt and the target action.
    Image paths are relative to the export root.

    A labelled step (recovery data, ``collect --perturb``; DAgger rollouts,
    ``baselines.vla.dagger``) has the expert's action as its target (``action``) and what
    was executed in ``executed``; the histories always hold the executed actions. LEGENT's
    closing ``finish()`` (``after_end``) is no sample: the env had ended the episode."""
    if window < 1:
        raise ValueError(f"the interleaved window must be >= 1 image, got {window}")
    instruction = trajectory["interactions"][0]["text"]
    steps = [s for s in trajectory["interactions"][1]["trajectory"] if not s.get("after_end")]
    task = trajectory.get("task", {})
    task_name = task.get("name") if isinstance(task, dict) else task
    records = []
    for n, step in enumerate(steps):
        first = max(0, n - window + 1)
        images = [s["image"] for s in steps[first:n + 1]]
        history = [s["action"] for s in steps[first:n]]  # what was executed
        records.append({
            "trajectory": trajectory["id"],
            "step": n,
            "instruction": instruction,
            "images": images,
            "history": history,
            "prompt": build_prompt(instruction, history),
            # The target: the expert's action, also where a perturbation was executed instead.
            "action": step.get("expert_action", step["action"]),
            "task": task_name,
            "env_id": trajectory.get("env_id"),
            "seed": trajectory.get("seed"),
        })
        if "expert_action" in step:
            records[-1]["executed"] = step["action"]
        if "goal_view" in step:
            records[-1]["goal_view"] = step["goal_view"]
    return records


def episode_pngs(episode: Episode) -> list[bytes]:
    """The views of the trajectory's steps, PNG-encoded: before each action, and the final
    view where LEGENT's closing ``finish()`` follows (:func:`closes_with_finish`; else, as
    in LEGENT, no image after the last action)."""
    views = episode.steps + (1 if closes_with_finish(episode) else 0)
    return [encode_png(obs["rgb"]) for obs in episode.observations[:views]]


class LegentWriter:
    """Writes trajectory folders and keeps the aggregate files (see the module docstring)."""

    def __init__(self, root: str | os.PathLike, window: int = DEFAULT_WINDOW):
        if window < 1:
            raise ValueError(f"the interleaved window must be >= 1 image, got {window}")
        self.root = Path(root)
        self.window = window
        self._trajectories: list[bytes] = []  # serialised, so a checkpoint is a join and a write
        self._interleaved: list[bytes] = []

    @staticmethod
    def trajectory_id(index: int) -> str:
        return f"{index:06d}"

    def resume(self, committed: int) -> None:
        """Load the first ``committed`` trajectories and drop anything written after them."""
        self.root.mkdir(parents=True, exist_ok=True)
        self._trajectories, self._interleaved = [], []
        for index in range(committed):
            folder = self.root / self.trajectory_id(index)
            try:
                record = json.loads((folder / TRAJECTORY_FILE).read_text())
            except FileNotFoundError:
                raise ValueError(f"{folder} is missing although the progress file counts it as written: "
                                 "the output directory was changed by hand; use a new --out") from None
            self._add(record)
        for child in self.root.iterdir():
            stale_temp = child.name.startswith(".") and child.name.endswith(".tmp")
            uncounted = child.is_dir() and child.name.isdigit() and int(child.name) >= committed
            if stale_temp or uncounted:
                shutil.rmtree(child) if child.is_dir() else child.unlink()

    def _add(self, record: dict[str, Any]) -> None:
        self._trajectories.append(json.dumps(record).encode())
        lines = (json.dumps(r) + "\n" for r in interleaved_records(record, self.window))
        self._interleaved.append("".join(lines).encode())

    def write(self, episode: Episode, index: int, pngs: Sequence[bytes]) -> dict[str, Any]:
        """Write trajectory ``index`` (whole or not at all); returns its record."""
        if index != len(self._trajectories):
            raise ValueError(f"trajectory {index} is not the next one ({len(self._trajectories)} written)")
        traj_id = self.trajectory_id(index)
        record = trajectory_record(episode, traj_id)
        steps = len(record["interactions"][1]["trajectory"])
        if len(pngs) != steps:
            raise ValueError(f"{len(pngs)} images for {steps} steps ({episode.steps} actions)")
        temp = self.root / f".{traj_id}.tmp"
        shutil.rmtree(temp, ignore_errors=True)
        temp.mkdir(parents=True)
        for n, png in enumerate(pngs):
            (temp / f"{n:04d}.png").write_bytes(png)
        (temp / TRAJECTORY_FILE).write_text(json.dumps(record, indent=1))
        (temp / TASK_SETTING_FILE).write_text(json.dumps(task_setting_record(episode), indent=1))
        final = self.root / traj_id
        if final.exists():  # written before a crash but never counted
            shutil.rmtree(final)
        os.rename(temp, final)
        self._add(record)
        return record

    def checkpoint(self, durable: bool = True) -> None:
        """Rewrite ``trajectories.json`` and ``interleaved.jsonl`` atomically."""
        atomic_write_bytes(self.root / AGGREGATE_FILE, b"[" + b",\n".join(self._trajectories) + b"]\n",
                           durable=durable)
        atomic_write_bytes(self.root / INTERLEAVED_FILE, b"".join(self._interleaved), durable=durable)


def load_trajectories(root: str | os.PathLike) -> list[dict[str, Any]]:
    """The aggregated trajectory list of an export."""
    return json.loads((Path(root) / AGGREGATE_FILE).read_text())


def load_interleaved(root: str | os.PathLike) -> list[dict[str, Any]]:
    with open(Path(root) / INTERLEAVED_FILE, encoding="utf-8") as fh:
        return [json.loads(line) for line in fh if line.strip()]

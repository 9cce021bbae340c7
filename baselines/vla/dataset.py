"""Training data: the interleaved JSONL that ``legent-gym collect --format legent`` writes.

Each line of ``interleaved.jsonl`` is one step: the instruction, the last <= k views up to
and including the step (``images``), the actions between them (``history``) and the
target ``action``. The loader checks that the lines of each trajectory agree with one
another (the window of step n is the last images and actions of the same trajectory),
keeps every view once, and turns every line into the model's input exactly as written:
the same window, the same history. Batches are whole trajectories, so each view goes
through the image encoder once per batch however many windows it appears in.
"""

from __future__ import annotations

import json
import os
from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import torch

from baselines.vla.codec import ActionCodec
from baselines.vla.words import WordVocab
from legent_gym.data.legent_format import INTERLEAVED_FILE, read_png

IGNORE = -100  # the cross-entropy "no target" index


class DatasetError(ValueError):
    """The interleaved data is missing or does not follow its contract."""


@dataclass
class Trajectory:
    id: str
    instruction: str
    env_id: str | None
    image_paths: list[str]  # relative to the dataset root; one per step
    actions: list[str]      # the action text executed at each step (what the history shows)
    window: int             # the most images one line holds
    #: The target per step: the expert's action. It differs from ``actions`` only at the
    #: perturbed steps of recovery data (``legent-gym collect --perturb``) and where a DAgger
    #: learner did other than the expert (``baselines.vla.dagger``). None: ``actions``.
    labels: list[str] | None = None
    #: Per step, the privileged view of the goal (``goal_view`` lines: visible, bearing,
    #: distance) where the data holds it, else None: auxiliary targets (``aux_weight``).
    goal_views: list[dict | None] | None = None

    def __post_init__(self) -> None:
        if self.labels is None:
            self.labels = list(self.actions)
        if len(self.labels) != len(self.actions):
            raise ValueError(f"trajectory {self.id}: {len(self.labels)} labels for {len(self.actions)} actions")
        if self.goal_views is None:
            self.goal_views = [None] * len(self.actions)

    @property
    def perturbed(self) -> int:
        """How many steps executed something other than their label."""
        return sum(a != b for a, b in zip(self.actions, self.labels))


def resolve_root(path: str | os.PathLike) -> Path:
    """A dataset root: the folder holding ``interleaved.jsonl``, or a collect output whose
    ``legent/`` sub-folder holds it."""
    path = Path(path)
    for candidate in (path, path / "legent"):
        if (candidate / INTERLEAVED_FILE).is_file():
            return candidate
    raise DatasetError(f"no {INTERLEAVED_FILE} in {path} or {path / 'legent'}: "
                       "collect data with `legent-gym collect ENV --format legent --out DIR`")


def read_trajectories(root: str | os.PathLike, limit: int | None = None) -> list[Trajectory]:
    """The trajectories of one dataset, in collection order, the first ``limit`` of them.

    Raises :class:`DatasetError` naming the file and line when a line lacks a field or
    disagrees with the other lines of its trajectory.
    """
    root = resolve_root(root)
    path = root / INTERLEAVED_FILE
    lines: dict[str, list[tuple[int, dict]]] = {}
    with open(path, encoding="utf-8") as fh:
        for number, line in enumerate(fh, 1):
            if not line.strip():
                continue
            try:
                record = json.loads(line)
            except json.JSONDecodeError as err:
                raise DatasetError(f"{path}:{number}: not JSON ({err})") from None
            missing = [k for k in ("trajectory", "step", "instruction", "images", "history", "action")
                       if k not in record]
            if missing:
                raise DatasetError(f"{path}:{number}: missing field(s) {', '.join(missing)}")
            lines.setdefault(str(record["trajectory"]), []).append((number, record))
    if not lines:
        raise DatasetError(f"{path} holds no steps")
    trajectories = []
    for traj_id in sorted(lines)[:limit]:
        trajectories.append(_trajectory(path, traj_id, sorted(lines[traj_id], key=lambda x: x[1]["step"])))
    return trajectories


def _trajectory(path: Path, traj_id: str, numbered: list[tuple[int, dict]]) -> Trajectory:
    images: list[str] = []
    actions: list[str] = []
    labels: list[str] = []
    goal_views: list[dict | None] = []
    window = 1
    for n, (number, record) in enumerate(numbered):
        where = f"{path}:{number} (trajectory {traj_id})"
        if record["step"] != n:
            raise DatasetError(f"{where}: step {record['step']} where step {n} was expected")
        if record["instruction"] != numbered[0][1]["instruction"]:
            raise DatasetError(f"{where}: the instruction changes within the trajectory")
        shown, history = record["images"], record["history"]
        if not shown or len(history) != len(shown) - 1:
            raise DatasetError(f"{where}: {len(shown)} images need {max(len(shown) - 1, 0)} history actions, "
                               f"got {len(history)}")
        images.append(shown[-1])
        labels.append(record["action"])
        goal_views.append(_goal_view(where, record.get("goal_view")))
        actions.append(record.get("executed", record["action"]))  # a labelled step may have executed another
        first = n + 1 - len(shown)
        if first < 0 or shown != images[first:] or history != actions[first:n]:
            raise DatasetError(f"{where}: its window is not the trajectory's last {len(shown)} steps")
        window = max(window, len(shown))
    first = numbered[0][1]
    return Trajectory(traj_id, first["instruction"], first.get("env_id"), images, actions, window, labels,
                      goal_views)


def _goal_view(where: str, view) -> dict | None:
    if view is None:
        return None
    try:
        return {"visible": bool(view["visible"]), "bearing": float(view["bearing"]),
                "distance": float(view["distance"])}
    except (KeyError, TypeError, ValueError):
        raise DatasetError(f"{where}: goal_view must be {{visible, bearing, distance}}, got {view!r}") from None


#: Auxiliary targets: the goal's bearing in 30-degree sectors (sector 0 straight ahead,
#: 1 to the right of it, 6 behind, 11 to the left) and its distance in these bands (metres).
BEARING_SECTORS = 12
DISTANCE_EDGES = (1.0, 2.0, 3.0, 4.0, 6.0)


def aux_targets(view: dict | None) -> tuple[int, int, int]:
    """(visible, bearing sector, distance band) of a goal view; IGNORE for each without one."""
    if view is None:
        return IGNORE, IGNORE, IGNORE
    sector = int(round(view["bearing"] / (360.0 / BEARING_SECTORS))) % BEARING_SECTORS
    return int(view["visible"]), sector, int(np.searchsorted(DISTANCE_EDGES, view["distance"], side="right"))


@dataclass
class Encoded:
    """Every step of a dataset as model inputs and targets (numpy, one row per step)."""

    images: np.ndarray          # (N_img, H, W, 3) uint8, each view once
    traj_images: list[np.ndarray]  # per trajectory, its global image indices
    traj_samples: list[np.ndarray]  # per trajectory, its sample (step) indices
    instruction: np.ndarray     # (S, L) word ids, 0-padded
    window_images: np.ndarray   # (S, k) global image indices, left-padded with -1
    history_template: np.ndarray  # (S, k-1) template ids (0: none / unknown)
    history_numbers: np.ndarray   # (S, k-1, n_slots) normalised values, 0 where absent
    history_speech: np.ndarray    # (S, k-1)
    target_template: np.ndarray   # (S,)
    target_bins: np.ndarray       # (S, n_slots), IGNORE where the slot is absent
    target_offsets: np.ndarray    # (S, n_slots)
    target_speech: np.ndarray     # (S,), IGNORE without speech
    target_visible: np.ndarray    # (S,) the goal in view (0/1), IGNORE without a goal view
    target_bearing: np.ndarray    # (S,) its bearing sector (BEARING_SECTORS), or IGNORE
    target_distance: np.ndarray   # (S,) its distance band (DISTANCE_EDGES), or IGNORE
    n_bins: int

    @property
    def n_samples(self) -> int:
        return len(self.target_template)


def action_features(codec: ActionCodec, text: str) -> tuple[int, np.ndarray, int]:
    """A history action as (template id, normalised slot values, speech id); unparsable text
    (which the env treats as a no-op) is the unknown template."""
    numbers = np.zeros(len(codec.slots), np.float32)
    decomposed = codec.encode(text)
    if decomposed is None:
        return 0, numbers, 0
    for slot, value in decomposed.numbers.items():
        index = codec.slot_id(slot)
        if index is not None:
            numbers[index] = codec.normalise(slot, value)
    return codec.template_id(decomposed.template), numbers, codec.speech_id(decomposed.speech)


def window_inputs(codec: ActionCodec, vocab: WordVocab, window: int, instruction: str,
                  history: Sequence[str]) -> dict[str, np.ndarray]:
    """The model inputs of one window other than the images: word ids and the history
    actions, left-padded to ``window - 1`` entries."""
    if len(history) > window - 1:
        raise ValueError(f"{len(history)} history actions do not fit a window of {window} images")
    words = vocab.encode(instruction)
    template = np.zeros(window - 1, np.int64)
    numbers = np.zeros((window - 1, len(codec.slots)), np.float32)
    speech = np.zeros(window - 1, np.int64)
    start = window - 1 - len(history)
    for j, text in enumerate(history):
        template[start + j], numbers[start + j], speech[start + j] = action_features(codec, text)
    instr = np.zeros(vocab.max_words, np.int64)
    instr[: len(words)] = words
    return {"instruction": instr, "history_template": template, "history_numbers": numbers,
            "history_speech": speech}


def encode(trajectories: Sequence[tuple[Path, Trajectory]], codec: ActionCodec, vocab: WordVocab,
           window: int) -> Encoded:
    """Load the views and encode every step (a line of the JSONL) for ``window`` images."""
    images: list[np.ndarray] = []
    traj_images, traj_samples = [], []
    rows: dict[str, list] = {k: [] for k in ("instruction", "window_images", "history_template",
                                             "history_numbers", "history_speech", "target_template",
                                             "target_bins", "target_offsets", "target_speech",
                                             "target_visible", "target_bearing", "target_distance")}
    shape = None
    for root, traj in trajectories:
        base = len(images)
        for rel in traj.image_paths:
            image = read_png(root / rel)
            if shape is None:
                shape = image.shape
            elif image.shape != shape:
                raise DatasetError(f"{root / rel} is {image.shape[1]}x{image.shape[0]}, other views are "
                                   f"{shape[1]}x{shape[0]}: collect every dataset at one image size")
            images.append(image)
        traj_images.append(np.arange(base, len(images)))
        first_sample = len(rows["target_template"])
        for n, text in enumerate(traj.labels):  # targets: the labels; histories: what was executed
            lo = max(0, n + 1 - window)
            inputs = window_inputs(codec, vocab, window, traj.instruction, traj.actions[lo:n])
            for key, value in inputs.items():
                rows[key].append(value)
            shown = np.full(window, -1, np.int64)
            shown[window - (n + 1 - lo):] = np.arange(base + lo, base + n + 1)
            rows["window_images"].append(shown)
            target = codec.encode(text)
            if target is None:
                raise DatasetError(f"trajectory {traj.id} step {n}: the action {text!r} does not parse")
            bins = np.full(len(codec.slots), IGNORE, np.int64)
            offsets = np.zeros(len(codec.slots), np.float32)
            for slot, value in target.numbers.items():
                index = codec.slot_id(slot)
                bins[index], offsets[index] = codec.to_bin(slot, value)
            rows["target_template"].append(codec.template_id(target.template))
            rows["target_bins"].append(bins)
            rows["target_offsets"].append(offsets)
            rows["target_speech"].append(IGNORE if target.speech is None else codec.speech_id(target.speech))
            for key, value in zip(("target_visible", "target_bearing", "target_distance"),
                                  aux_targets(traj.goal_views[n])):
                rows[key].append(value)
        traj_samples.append(np.arange(first_sample, len(rows["target_template"])))
    if not images:
        raise DatasetError("no trajectories to encode")
    scalars = ("target_template", "target_speech", "target_visible", "target_bearing", "target_distance")
    stacked = {k: np.asarray(v, np.int64) if k in scalars else np.stack(v) for k, v in rows.items()}
    return Encoded(np.stack(images), traj_images, traj_samples, **stacked, n_bins=codec.bins)


def mirror_slots(codec: ActionCodec) -> np.ndarray:
    """Which numeric slots change sign in a left-right mirrored world (the turns)."""
    return np.array([slot.startswith("rotate_right:") for slot in codec.slots], bool)


def batches(data: Encoded, trajectory_ids: Sequence[int], trajectories_per_batch: int,
            rng: np.random.Generator | None, mirror: np.ndarray | None = None
            ) -> Iterator[dict[str, torch.Tensor]]:
    """Batches of whole trajectories (shuffled with ``rng``; in order without): every view
    of the batch once, and every step of those trajectories as a sample.

    With ``mirror`` (from :func:`mirror_slots`) and an ``rng``, half the trajectories are
    mirrored: their views flipped left-right and their turns negated, in the targets and
    in the history alike. A mirrored house is as plausible as the house, the instructions
    name no side, so this doubles what the data shows (and evens out the expert's
    left/right choices where it turns towards what it knows is behind)."""
    order = np.asarray(trajectory_ids)
    if rng is not None:
        order = rng.permutation(order)
    for start in range(0, len(order), trajectories_per_batch):
        chosen = order[start:start + trajectories_per_batch]
        image_ids = np.concatenate([data.traj_images[t] for t in chosen])
        samples = np.concatenate([data.traj_samples[t] for t in chosen])
        remap = np.full(len(data.images), -1, np.int64)
        remap[image_ids] = np.arange(len(image_ids))
        window = data.window_images[samples]
        local = np.where(window >= 0, remap[np.maximum(window, 0)], -1)
        images = data.images[image_ids]
        history_numbers = data.history_numbers[samples]
        target_bins = data.target_bins[samples]
        target_offsets = data.target_offsets[samples]
        target_bearing = data.target_bearing[samples]
        if mirror is not None and rng is not None and mirror.any():
            flip = rng.random(len(chosen)) < 0.5
            flip_images = np.repeat(flip, [len(data.traj_images[t]) for t in chosen])
            flip_samples = np.repeat(flip, [len(data.traj_samples[t]) for t in chosen])
            images = images.copy()
            images[flip_images] = images[flip_images, :, ::-1]
            history_numbers = history_numbers.copy()
            history_numbers[np.ix_(flip_samples, np.arange(history_numbers.shape[1]), mirror)] *= -1
            target_bins, target_offsets = target_bins.copy(), target_offsets.copy()
            rows = np.ix_(flip_samples, mirror)
            bins = target_bins[rows]
            # Turn ranges are symmetric: bin i mirrors to bin (n - 1 - i), the offset flips.
            target_bins[rows] = np.where(bins >= 0, data.n_bins - 1 - bins, bins)
            target_offsets[rows] = -target_offsets[rows]
            # The goal's bearing mirrors too: sector i (to the right) becomes sector -i.
            target_bearing = target_bearing.copy()
            turned = flip_samples & (target_bearing >= 0)
            target_bearing[turned] = (BEARING_SECTORS - target_bearing[turned]) % BEARING_SECTORS
        yield {
            "images": torch.from_numpy(np.ascontiguousarray(images)).permute(0, 3, 1, 2).contiguous(),
            "window_images": torch.from_numpy(local),
            "instruction": torch.from_numpy(data.instruction[samples]),
            "history_template": torch.from_numpy(data.history_template[samples]),
            "history_numbers": torch.from_numpy(history_numbers),
            "history_speech": torch.from_numpy(data.history_speech[samples]),
            "target_template": torch.from_numpy(data.target_template[samples]),
            "target_bins": torch.from_numpy(target_bins),
            "target_offsets": torch.from_numpy(target_offsets),
            "target_speech": torch.from_numpy(data.target_speech[samples]),
            "target_visible": torch.from_numpy(data.target_visible[samples]),
            "target_bearing": torch.from_numpy(target_bearing),
            "target_distance": torch.from_numpy(data.target_distance[samples]),
        }

"""Minari datasets written one episode at a time, safe against a crash at any moment.

The dataset uses Minari's ``arrow`` storage, lossless (``jpeg_encoding=False``): each
episode is its own directory ``data/<index>/`` and ``data/metadata.json`` says how many
episodes there are. An episode is appended by (1) writing it with Minari's own encoder
into a staging directory outside the dataset, (2) renaming that directory into
``data/`` and (3) replacing ``metadata.json`` atomically with the new count. A crash
between any two steps leaves a dataset that loads with the episodes counted so far: Minari
only reads episodes ``0 .. total_episodes - 1``, so an extra directory is invisible and is
replaced when the episode is written again.

The encoding (Minari's own encoder: the costly part) and the commit (renames and the count)
are separate steps: :class:`EpisodeEncoder` turns an episode into the files of its
directory wherever it was recorded (``legent-gym collect``'s worker processes, in
parallel), and :meth:`MinariWriter.append_encoded` commits them in the one process that
owns the dataset, which then writes a few files per episode.

Datasets live under a root directory laid out as Minari's own datasets directory
(``<root>/<namespace>/<name>-v<version>/data``), so ``minari.load_dataset(dataset_id)``
finds them with ``MINARI_DATASETS_PATH=<root>``.
"""

from __future__ import annotations

import json
import os
import shutil
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from legent_gym.data.rollout import Episode
from legent_gym.utils.atomic import atomic_write_text

DATA_FORMAT = "arrow"
METADATA = "metadata.json"
NAMESPACE_METADATA = "namespace_metadata.json"


def stack_space(space: gym.Space, values: list[Any]) -> Any:
    """A list of per-step values of ``space`` -> the columnar layout Minari stores."""
    if isinstance(space, spaces.Dict):
        return {key: stack_space(sub, [v[key] for v in values]) for key, sub in space.spaces.items()}
    if isinstance(space, spaces.Tuple):
        return tuple(stack_space(sub, [v[i] for v in values]) for i, sub in enumerate(space.spaces))
    if isinstance(space, spaces.Box):
        return np.stack([np.asarray(v, dtype=space.dtype) for v in values])
    if isinstance(space, spaces.Discrete | spaces.MultiDiscrete | spaces.MultiBinary):
        return np.asarray(values, dtype=space.dtype)
    if isinstance(space, spaces.Text):
        return [str(v) for v in values]
    return list(values)


def _dir_megabytes(path: Path) -> float:
    return sum(f.stat().st_size for f in path.rglob("*") if f.is_file()) / 1e6


def _namespaces(dataset_id: str) -> list[str]:
    """``"a/b/name-v0"`` -> ``["a", "a/b"]``."""
    parts = dataset_id.split("/")[:-1]
    return ["/".join(parts[:i + 1]) for i in range(len(parts))]


def check_dataset_id(dataset_id: str) -> None:
    # minari: the data extra
    from minari.dataset.minari_dataset import parse_dataset_id

    try:
        parse_dataset_id(dataset_id)
    except Exception as err:  # minari raises a bare Error type of its own
        raise ValueError(f"invalid Minari dataset id {dataset_id!r}: {err}") from err
    if dataset_id.startswith("/") or ".." in dataset_id.split("/"):
        raise ValueError(f"invalid Minari dataset id {dataset_id!r}: must be a relative name")


@dataclass
class EncodedEpisode:
    """An episode in Minari's on-disk form, made by :class:`EpisodeEncoder`: the files of its
    directory (path relative to it -> bytes), its ``metadata.json`` as a dict (its ``id`` set
    when it is committed) and its number of steps."""

    files: dict[str, bytes]
    metadata: dict[str, Any]
    steps: int

    @property
    def megabytes(self) -> float:
        return sum(len(data) for data in self.files.values()) / 1e6


class EpisodeEncoder:
    """Episodes of one dataset's spaces -> :class:`EncodedEpisode`, through a scratch Minari
    storage in ``scratch`` (a folder of its own: each episode is written there and read
    back). Made once per process: setting the storage up costs more than an episode."""

    def __init__(self, scratch: str | os.PathLike, observation_space: gym.Space, action_space: gym.Space):
        # minari: the data extra
        from minari.dataset.minari_storage import MinariStorage

        self.scratch = Path(scratch).absolute()
        shutil.rmtree(self.scratch, ignore_errors=True)
        self.scratch.parent.mkdir(parents=True, exist_ok=True)
        self.storage = MinariStorage.new(self.scratch, observation_space=observation_space,
                                         action_space=action_space, data_format=DATA_FORMAT, jpeg_encoding=False)
        # Minari re-reads metadata.json several times per episode written; the spaces in it
        # (a Box's bounds element by element) make that slow, and the scratch storage holds
        # its spaces in memory anyway: keep only the counters.
        atomic_write_text(self.scratch / METADATA, json.dumps(
            {"total_episodes": 0, "total_steps": 0, "data_format": DATA_FORMAT, "jpeg_encoding": False}),
            durable=False)

    def encode(self, episode: Episode) -> EncodedEpisode:
        # minari: the data extra
        from minari.data_collector import EpisodeBuffer

        storage = self.storage
        written = self.scratch / "0"
        shutil.rmtree(written, ignore_errors=True)
        storage.update_episodes([EpisodeBuffer(
            id=0, seed=episode.seed,
            observations=stack_space(storage.observation_space, episode.observations),
            actions=stack_space(storage.action_space, episode.actions),
            rewards=np.asarray(episode.rewards, dtype=np.float64),
            terminations=np.asarray(episode.terminations, dtype=bool),
            truncations=np.asarray(episode.truncations, dtype=bool),
            infos={key: [info[key] for info in episode.infos] for key in episode.infos[0]},
        )])
        metadata = json.loads((written / METADATA).read_text())
        metadata.update(attempt=episode.attempt, success=episode.success, instruction=episode.instruction)
        files = {str(f.relative_to(written)): f.read_bytes() for f in sorted(written.rglob("*"))
                 if f.is_file() and f.name != METADATA}
        shutil.rmtree(written)
        return EncodedEpisode(files, metadata, episode.steps)

    def close(self) -> None:
        shutil.rmtree(self.scratch, ignore_errors=True)


class MinariWriter:
    """Appends episodes to one Minari dataset under ``root`` (see the module docstring).

    ``staging`` is a scratch directory on the same file system as ``root`` (renames must
    not cross file systems) and outside the dataset.
    """

    def __init__(self, root: str | os.PathLike, dataset_id: str, staging: str | os.PathLike):
        check_dataset_id(dataset_id)
        # Absolute: Minari's storage joins the folder it writes an episode to with its own
        # data path, so a relative one would be taken twice.
        self.root = Path(root).absolute()
        self.dataset_id = dataset_id
        self.dataset_dir = self.root / dataset_id
        self.data_path = self.dataset_dir / "data"
        self._staging_dir = Path(staging).absolute()
        self._encoder: EpisodeEncoder | None = None
        self._metadata: dict[str, Any] | None = None
        self._count_written = True

    @property
    def exists(self) -> bool:
        return (self.data_path / METADATA).exists()

    # -- creation --------------------------------------------------------------------------
    def create(self, env_spec, observation_space: gym.Space, action_space: gym.Space, *,
               algorithm_name: str, description: str) -> None:
        """Make the empty dataset (atomically: it appears whole or not at all)."""
        # minari: the data extra
        from minari import __version__ as minari_version
        from minari.dataset.minari_storage import MinariStorage

        if self.exists:
            raise ValueError(f"a Minari dataset already exists at {self.dataset_dir}")
        self.dataset_dir.parent.mkdir(parents=True, exist_ok=True)
        building = self.dataset_dir.parent / f".{self.dataset_dir.name}.creating"
        shutil.rmtree(building, ignore_errors=True)
        building.mkdir()
        storage = MinariStorage.new(building / "data", observation_space=observation_space, action_space=action_space,
                                    env_spec=env_spec, data_format=DATA_FORMAT, jpeg_encoding=False)
        storage.update_metadata({
            "dataset_id": self.dataset_id,
            "algorithm_name": algorithm_name,
            "description": description,
            "minari_version": minari_version,
            "requirements": ["legent-gym"],
            "dataset_size": 0.0,
        })
        for namespace in _namespaces(self.dataset_id):
            marker = self.root / namespace / NAMESPACE_METADATA
            if not marker.exists():  # Minari lists namespaces by this file
                atomic_write_text(marker, "{}")
        shutil.rmtree(self.dataset_dir, ignore_errors=True)  # a leftover without metadata
        os.rename(building, self.dataset_dir)

    # -- the committed state ---------------------------------------------------------------
    def metadata(self) -> dict[str, Any]:
        if self._metadata is None:
            self._metadata = json.loads((self.data_path / METADATA).read_text())
        return self._metadata

    def _write_metadata(self, durable: bool) -> None:
        atomic_write_text(self.data_path / METADATA, json.dumps(self._metadata), durable=durable)

    def truncate(self, total_episodes: int, total_steps: int) -> None:
        """Forget episodes from ``total_episodes`` on (written after the last count)."""
        metadata = self.metadata()
        if int(metadata["total_episodes"]) < total_episodes:
            raise ValueError(f"the Minari dataset at {self.dataset_dir} has {metadata['total_episodes']} "
                             f"episodes, fewer than the {total_episodes} the progress file records")
        for child in self.data_path.iterdir():
            if child.is_dir() and child.name.isdigit() and int(child.name) >= total_episodes:
                shutil.rmtree(child)
        metadata.update(total_episodes=total_episodes, total_steps=total_steps,
                        dataset_size=round(_dir_megabytes(self.data_path), 1))
        self._write_metadata(durable=True)

    # -- appending ---------------------------------------------------------------------------
    def encoder(self) -> EpisodeEncoder:
        """An encoder of this dataset's spaces, in the staging directory."""
        if self._encoder is None:
            # minari: the data extra
            from minari.dataset.minari_storage import MinariStorage

            reference = MinariStorage.read(self.data_path)
            self._encoder = EpisodeEncoder(self._staging_dir / "encoding", reference.observation_space,
                                           reference.action_space)
        return self._encoder

    def append(self, episode: Episode, index: int, extra_metadata: dict[str, Any] | None = None,
               *, durable: bool = True) -> None:
        """Write ``episode`` as episode ``index`` (the next one) and count it.
        ``durable=False``: no fsync of the count (see :func:`legent_gym.utils.atomic.atomic_write_bytes`)."""
        self.append_encoded(self.encoder().encode(episode), index, extra_metadata, durable=durable)

    def append_encoded(self, encoded: EncodedEpisode, index: int, extra_metadata: dict[str, Any] | None = None,
                       *, durable: bool = True, count: bool = True) -> None:
        """Commit an episode encoded by an :class:`EpisodeEncoder` of this dataset's spaces
        as episode ``index`` (the next one). ``count=False`` leaves the count on disk as it
        was until :meth:`write_count` (the episode is committed when the count is written:
        fewer writes of ``metadata.json`` when many episodes come at once)."""
        metadata = self.metadata()
        if index != int(metadata["total_episodes"]):
            raise ValueError(f"episode {index} is not the next one: the dataset has {metadata['total_episodes']}")
        incoming = self._staging_dir / "incoming"
        shutil.rmtree(incoming, ignore_errors=True)
        for name, data in encoded.files.items():
            path = incoming / name
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_bytes(data)
        (incoming / METADATA).write_text(json.dumps({**encoded.metadata, "id": index, **(extra_metadata or {})}))
        target = self.data_path / str(index)
        if target.exists():  # left by a crash after the rename, before the count
            shutil.rmtree(target)
        os.rename(incoming, target)
        metadata.update(total_episodes=index + 1,
                        total_steps=int(metadata["total_steps"]) + encoded.steps,
                        dataset_size=round(float(metadata.get("dataset_size", 0.0)) + encoded.megabytes, 1))
        self._count_written = False
        if count:
            self.write_count(durable)

    def write_count(self, durable: bool = True) -> None:
        """Write the episodes appended so far into ``metadata.json`` (if any is not yet)."""
        if not self._count_written:
            self._write_metadata(durable)
            self._count_written = True

    def close(self) -> None:
        self.write_count(durable=False)
        if self._encoder is not None:
            self._encoder.close()
            self._encoder = None
        shutil.rmtree(self._staging_dir, ignore_errors=True)


def load_minari_dataset(root: str | os.PathLike, dataset_id: str):
    """Open a dataset written here (same as ``minari.load_dataset(dataset_id)`` with
    ``MINARI_DATASETS_PATH=root``, without touching the environment variable)."""
    # minari: the data extra
    from minari import MinariDataset

    data_path = Path(root) / dataset_id / "data"
    if not (data_path / METADATA).exists():
        raise FileNotFoundError(f"no Minari dataset {dataset_id!r} under {root}")
    return MinariDataset(data_path)

"""Collecting successful trajectories in parallel, resumable after any interruption.

Attempt ``k`` resets the env with seed ``seed + k``; attempts are judged in order and the
successful ones become episodes ``0, 1, 2, ...`` until there are ``episodes`` of them, so the
dataset depends on the seed alone, not on the number of workers or on interruptions.
Failed attempts are counted, not kept (as in LEGENT).

Layout of the output directory::

    progress.json            how far the run got (rewritten atomically, every COUNT_SECONDS)
    minari/<dataset_id>/     the Minari dataset (MINARI_DATASETS_PATH=OUT/minari)
    legent/                  LEGENT's format and interleaved.jsonl (legent_format.py)
    video/<id>.mp4           captioned H.264 video, video/<id>_map.png the path from above

Each episode is committed in order: its trajectory folder, its video, its Minari episode
(encoded by the worker that recorded it), then the Minari count and ``progress.json``.
Whatever a crash interrupts is past the count in ``progress.json`` and is dropped and redone
by the next run, which gives the same episode again (same seed).

The attempts are computed by worker processes on this machine or by Ray tasks on a
cluster (``backend``; see :mod:`legent_gym.utils.scale` and ``docs/scale.md``); a task returns
its attempt whole to this process, which commits as above. So both backends write the
same output, and a run killed on one resumes on either.
"""

from __future__ import annotations

import fcntl
import json
import math
import os
import tempfile
import time
from collections.abc import Callable, Generator
from contextlib import closing
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any, TypeVar

import gymnasium as gym
from tqdm import tqdm

from legent_gym.data.legent_format import DEFAULT_WINDOW, LegentWriter, encode_png, episode_pngs
from legent_gym.data.minari_store import (
    EncodedEpisode,
    EpisodeEncoder,
    MinariWriter,
    check_dataset_id,
)
from legent_gym.data.rollout import EXPERT, Episode, make_env, record_episode, resolve_policy
from legent_gym.data.video import episode_map, episode_video
from legent_gym.experts.planners import FIND_STRATEGIES
from legent_gym.utils.atomic import atomic_write_bytes, atomic_write_text
from legent_gym.utils.scale import Backend, BackendUnavailable
from legent_gym.utils.workers import map_ordered

if TYPE_CHECKING:
    from legent_gym.world.scene import Scene

FORMATS = ("minari", "legent", "video")
PROGRESS_FILE = "progress.json"
PROGRESS_VERSION = 1
#: The aggregate files are rewritten at most this often (and at the end).
CHECKPOINT_SECONDS = 2.0
#: The counts (progress.json, the Minari count) are written at most this often while
#: episodes come, so that committing stays cheap beside many workers: a crash loses at most
#: this long of episodes, which the next run redoes (the same episodes, the same seeds).
COUNT_SECONDS = 0.25


class CollectError(Exception):
    """A problem with the request or the output directory (printed without a traceback)."""


@dataclass(frozen=True)
class CollectConfig:
    env_id: str
    episodes: int
    out: str
    formats: tuple[str, ...] = ("minari", "legent")
    workers: int = 1
    seed: int = 0
    env_kwargs: dict[str, Any] = field(default_factory=dict)
    #: ``"expert"`` (plays ``info["expert_action"]``) or ``"module:function"``, a callable
    #: ``(obs, info) -> action`` that worker processes can import. The env is always wrapped
    #: in ``ExpertInfo``, so any policy can read the expert's action.
    policy: str = EXPERT
    window: int = DEFAULT_WINDOW
    dataset_id: str | None = None
    #: Stop after this many attempts in all (default ``10 * episodes + 100``).
    max_attempts: int | None = None
    #: Recovery data: the probability per step of executing a random perturbation in place
    #: of the policy's action, labelled with the expert's (see ``record_episode``).
    perturb: float = 0.0
    #: How the expert's ``find(a)`` looks for an object out of view: ``"direct"`` (LEGENT's)
    #: or ``"scan"`` (look around in place first; see ``legent_gym.experts.planners``).
    find_strategy: str = "direct"
    #: Where the attempts are computed: ``"process"`` (worker processes here) or ``"ray"``
    #: (Ray tasks; ``ray_address`` as in :mod:`legent_gym.utils.scale`). This process commits
    #: them in order either way, so the output does not depend on it.
    backend: str = "process"
    ray_address: str | None = None

    def resolved_dataset_id(self) -> str:
        if self.dataset_id:
            return self.dataset_id
        name = self.env_id.split("/")[-1]
        name = name.rsplit("-v", 1)[0] if "-v" in name else name
        return f"legent/{name}/{'expert' if self.policy == EXPERT else 'policy'}-v0"

    def identity(self) -> dict[str, Any]:
        """What a resumed run must share with the first (the episode count may grow)."""
        identity = {"env_id": self.env_id, "env_kwargs": self.env_kwargs, "seed": self.seed,
                    "formats": sorted(self.formats), "policy": self.policy, "window": self.window,
                    "dataset_id": self.resolved_dataset_id()}
        if self.perturb:  # absent when 0: collections made before the option still resume
            identity["perturb"] = self.perturb
        if self.find_strategy != "direct":  # likewise
            identity["find_strategy"] = self.find_strategy
        return identity

    def attempt_limit(self) -> int:
        return self.max_attempts if self.max_attempts is not None else 10 * self.episodes + 100


@dataclass
class CollectSummary:
    out: str
    episodes: int
    new_episodes: int
    failures: int
    attempts: int
    seconds: float
    dataset_id: str | None

    @property
    def success_rate(self) -> float:
        return self.episodes / self.attempts if self.attempts else math.nan

    @property
    def episodes_per_second(self) -> float:
        return self.new_episodes / self.seconds if self.seconds > 0 else math.nan


@dataclass
class _Progress:
    committed: int = 0
    next_attempt: int = 0
    failures: int = 0
    total_steps: int = 0
    complete: bool = False


# -- workers ---------------------------------------------------------------------------------
@dataclass
class AttemptResult:
    attempt: int
    success: bool
    steps: int
    episode: Episode | None = None  # only for successes
    pngs: list[bytes] | None = None
    video: bytes | None = None
    map_png: bytes | None = None
    minari: EncodedEpisode | None = None


class _Worker:
    """One env and one policy; encodes images and video where it runs (in parallel)."""

    def __init__(self, env_id: str, env_kwargs: dict, policy: str | Callable, formats: tuple[str, ...],
                 perturb: float = 0.0, find_strategy: str = "direct"):
        self.env_id, self.formats, self.perturb = env_id, formats, perturb
        # Every policy sees info["expert_action"] (a noisy expert or DAgger-style mixing needs it).
        self.env = make_env(env_id, env_kwargs, expert=True, find_strategy=find_strategy)
        self.policy = resolve_policy(policy) if isinstance(policy, str) else policy
        self.encoder = None
        if "minari" in formats:  # Minari's encoding here, in parallel; the committing process renames
            self.encoder = EpisodeEncoder(tempfile.mkdtemp(prefix="legent-minari-", dir=_scratch_root()),
                                          self.env.observation_space, self.env.action_space)

    def run(self, attempt: int, seed: int) -> AttemptResult:
        episode = record_episode(self.env, self.policy, seed=seed, attempt=attempt, env_id=self.env_id,
                                 perturb=self.perturb)
        if not episode.success:
            return AttemptResult(attempt, False, episode.steps)
        result = AttemptResult(attempt, True, episode.steps, episode)
        if "legent" in self.formats:
            result.pngs = episode_pngs(episode)
        if "video" in self.formats:
            result.video = episode_video(episode)
            result.map_png = encode_png(episode_map(self._scene(), episode))
        if self.encoder is not None:
            result.minari = self.encoder.encode(episode)
        episode.observations = []  # encoded above: spare the pipe
        return result

    def _scene(self) -> Scene:
        """The scene of the env's current house (from its episode engine)."""
        engine = getattr(self.env.unwrapped, "episode", None)
        if engine is None:
            raise TypeError(f"{self.env_id} is not a legent_gym env: it has no episode engine")
        return engine.require().scene

    def close(self) -> None:
        self.env.close()
        if self.encoder is not None:
            self.encoder.close()


def _scratch_root() -> str | None:
    """Where a worker's encoding scratch goes: memory (``/dev/shm``) where there is one, as
    each episode's files are written there and read straight back (creating a file on a disk
    file system can cost a millisecond); else the temporary directory."""
    return "/dev/shm" if os.path.isdir("/dev/shm") and os.access("/dev/shm", os.W_OK) else None


_worker: _Worker | None = None


def _init_worker(*args) -> None:
    global _worker
    _worker = _Worker(*args)


def _run_attempt(attempt: int, seed: int) -> AttemptResult:
    if _worker is None:
        raise RuntimeError("this process has no collection worker (_init_worker did not run)")
    return _worker.run(attempt, seed)


def _attempt_results(config: CollectConfig, policy, start: int,
                     limit: int) -> Generator[AttemptResult, None, None]:
    """Results of attempts ``start, start + 1, ...`` in order (computed ahead in parallel)."""
    worker_args = (config.env_id, config.env_kwargs, policy, tuple(config.formats), config.perturb,
                   config.find_strategy)
    if config.workers == 1 and config.backend == "process":
        worker = _Worker(*worker_args)
        try:
            for attempt in range(start, limit):
                yield worker.run(attempt, config.seed + attempt)
        finally:
            worker.close()
        return
    calls = ((attempt, config.seed + attempt) for attempt in range(start, limit))
    yield from map_ordered(_run_attempt, calls, workers=config.workers, initializer=_init_worker,
                           initargs=worker_args, backend=Backend(config.backend, config.ray_address))


# -- the run ---------------------------------------------------------------------------------
def _check(config: CollectConfig, policy: Callable | None) -> None:
    """Fail early, in this process, with a message naming what is wrong."""
    if config.episodes < 1:
        raise CollectError(f"--episodes must be >= 1, got {config.episodes}")
    if config.workers < 1:
        raise CollectError(f"--workers must be >= 1, got {config.workers}")
    if config.window < 1:
        raise CollectError(f"--window must be >= 1, got {config.window}")
    try:
        Backend(config.backend, config.ray_address).check()
    except (ValueError, BackendUnavailable) as err:
        raise CollectError(str(err)) from None
    if not 0.0 <= config.perturb < 1.0:
        raise CollectError(f"--perturb must be in [0, 1), got {config.perturb}")
    if config.perturb and config.env_kwargs.get("action_type", "text") != "text":
        raise CollectError("--perturb needs text actions (the labels are action code)")
    if config.find_strategy not in FIND_STRATEGIES:
        raise CollectError(f"--find-strategy must be one of {', '.join(FIND_STRATEGIES)}, got {config.find_strategy!r}")
    unknown = sorted(set(config.formats) - set(FORMATS))
    if unknown or not config.formats:
        raise CollectError(f"unknown format(s) {', '.join(unknown) or '(none given)'}; "
                           f"choose from {', '.join(FORMATS)}")
    try:
        gym.spec(config.env_id)
    except gym.error.Error as err:
        raise CollectError(f"unknown env id {config.env_id!r}: {err}") from None
    try:
        gym.make(config.env_id, **config.env_kwargs).close()  # no reset: cheap, no OpenGL
    except (TypeError, ValueError) as err:
        raise CollectError(f"cannot make {config.env_id} with {config.env_kwargs}: {err}") from None
    if policy is None:
        try:
            resolve_policy(config.policy)
        except (ValueError, ImportError) as err:
            raise CollectError(f"--policy {config.policy}: {err}") from None
    if "minari" in config.formats:
        try:
            check_dataset_id(config.resolved_dataset_id())
        except ValueError as err:
            raise CollectError(str(err)) from None


def _lock(out: Path):
    handle = open(out / ".lock", "w")  # noqa: SIM115  (held for the whole run)
    try:
        fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        handle.close()
        raise CollectError(f"another collect is writing to {out}") from None
    return handle


def _load_progress(out: Path, config: CollectConfig) -> _Progress | None:
    path = out / PROGRESS_FILE
    if not path.exists():
        return None
    saved = json.loads(path.read_text())
    if saved.get("version") != PROGRESS_VERSION:
        raise CollectError(f"{path} was written by another version of legent-gym collect")
    if saved["config"] != config.identity():
        now = config.identity()
        # Over both key sets: an option left at its default is absent from one of them.
        diff = {k: (saved["config"].get(k), now.get(k)) for k in {**saved["config"], **now}
                if saved["config"].get(k) != now.get(k)}
        raise CollectError(f"{out} holds a collection made with other options "
                           f"({', '.join(f'{k}: was {a!r}, now {b!r}' for k, (a, b) in diff.items())}); "
                           "resume with the same options or use a new --out")
    return _Progress(**saved["progress"])


def _save_progress(out: Path, config: CollectConfig, progress: _Progress, durable: bool = True) -> None:
    atomic_write_text(out / PROGRESS_FILE, json.dumps(
        {"version": PROGRESS_VERSION, "config": config.identity(), "episodes_requested": config.episodes,
         "progress": asdict(progress)}, indent=1), durable=durable)


def _clean_videos(video_dir: Path, committed: int) -> None:
    if not video_dir.exists():
        return
    for child in video_dir.iterdir():
        stem = child.name.split("_")[0].split(".")[0]
        if child.name.startswith(".") or (stem.isdigit() and int(stem) >= committed):
            child.unlink()


def _open_minari(out: Path, config: CollectConfig, progress: _Progress):
    writer = MinariWriter(out / "minari", config.resolved_dataset_id(), staging=out / ".staging")
    if writer.exists:
        writer.truncate(progress.committed, progress.total_steps)
        return writer
    if progress.committed:
        raise CollectError(f"the Minari dataset {writer.dataset_dir} is missing although {out / PROGRESS_FILE} "
                           f"counts {progress.committed} episodes: use a new --out")
    env = gym.make(config.env_id, **config.env_kwargs)  # spaces and spec only: no reset, no OpenGL
    try:
        writer.create(env.spec, env.observation_space, env.action_space,
                      algorithm_name=f"legent_gym collect --policy {config.policy}",
                      description=f"Successful {config.env_id} trajectories (seed {config.seed}), "
                                  "collected by legent_gym; lossless images.")
    finally:
        env.close()
    return writer


@dataclass
class _Writers:
    minari: Any = None
    legent: LegentWriter | None = None
    video_dir: Path | None = None

    def commit(self, result: AttemptResult, index: int) -> None:
        """Write one successful episode everywhere (the caller then counts it)."""
        episode, traj_id = _required(result.episode, "episode"), LegentWriter.trajectory_id(index)
        if self.legent is not None:
            self.legent.write(episode, index, _required(result.pngs, "PNGs"))
        if self.video_dir is not None:
            atomic_write_bytes(self.video_dir / f"{traj_id}_map.png", _required(result.map_png, "map"), durable=False)
            atomic_write_bytes(self.video_dir / f"{traj_id}.mp4", _required(result.video, "video"), durable=False)
        if self.minari is not None:
            # Counted by count(), which the caller calls before progress.json is written.
            self.minari.append_encoded(_required(result.minari, "Minari episode"), index, {"legent_id": traj_id},
                                       durable=False, count=False)

    def count(self) -> None:
        """Write the counts of the episodes committed so far (before progress.json)."""
        if self.minari is not None:
            self.minari.write_count(durable=False)

    def close(self) -> None:
        if self.legent is not None:
            self.legent.checkpoint(durable=False)
        if self.minari is not None:
            self.minari.close()


_T = TypeVar("_T")


def _required(value: _T | None, what: str) -> _T:
    """A part of a successful attempt's result (a worker encodes each format the run writes)."""
    if value is None:
        raise ValueError(f"the attempt result has no {what}: only a successful attempt, encoded in "
                         "every format the run writes, is committed")
    return value


def _open_writers(out: Path, config: CollectConfig, progress: _Progress) -> _Writers:
    try:
        return _resume_writers(out, config, progress)
    except ValueError as err:  # the output no longer matches progress.json (edited by hand)
        raise CollectError(str(err)) from None


def _resume_writers(out: Path, config: CollectConfig, progress: _Progress) -> _Writers:
    writers = _Writers()
    if "minari" in config.formats:
        writers.minari = _open_minari(out, config, progress)
    if "legent" in config.formats:
        writers.legent = LegentWriter(out / "legent", config.window)
        writers.legent.resume(progress.committed)
        writers.legent.checkpoint(durable=False)  # the aggregates exist (and agree) from the start
    if "video" in config.formats:
        writers.video_dir = out / "video"
        _clean_videos(writers.video_dir, progress.committed)
        writers.video_dir.mkdir(exist_ok=True)
    return writers


def _run(config: CollectConfig, policy, out: Path, progress: _Progress, writers: _Writers, bar,
         checkpoint_seconds: float) -> None:
    # Rewriting the aggregates costs O(dataset); space the rewrites so they stay a few percent.
    last_checkpoint, interval = time.monotonic(), checkpoint_seconds
    last_count = time.monotonic()
    with closing(_attempt_results(config, policy, progress.next_attempt, config.attempt_limit())) as results:
        for result in results:
            progress.next_attempt = result.attempt + 1
            if not result.success:
                progress.failures += 1
            else:
                writers.commit(result, progress.committed)
                progress.committed += 1
                progress.total_steps += result.steps
                progress.complete = progress.committed >= config.episodes
                if progress.complete or time.monotonic() - last_count >= COUNT_SECONDS:
                    writers.count()
                    _save_progress(out, config, progress, durable=False)
                    last_count = time.monotonic()
                bar.update(1)
                if writers.legent is not None and time.monotonic() - last_checkpoint >= interval:
                    began = time.monotonic()
                    writers.legent.checkpoint(durable=False)
                    last_checkpoint = time.monotonic()
                    interval = max(checkpoint_seconds, 20 * (last_checkpoint - began))
            bar.set_postfix(success=f"{progress.committed / (progress.committed + progress.failures):.0%}",
                            failed=progress.failures)
            if progress.complete:
                return


def collect(config: CollectConfig, *, policy: Callable | None = None, show_progress: bool = True,
            checkpoint_seconds: float = CHECKPOINT_SECONDS) -> CollectSummary:
    """Collect ``config.episodes`` successful trajectories into ``config.out`` (resuming
    what is there). ``policy`` overrides ``config.policy`` with a callable (it must be
    importable by worker processes when ``workers > 1``)."""
    if policy is not None:  # a resumed run must be made by the same policy: record its name
        config = replace(config, policy=f"{policy.__module__}:{policy.__qualname__}")
    _check(config, policy)
    out = Path(config.out)
    out.mkdir(parents=True, exist_ok=True)
    lock = _lock(out)
    try:
        progress = _load_progress(out, config)
        if progress is None:
            if any((out / name).exists() for name in ("minari", "legent", "video")):
                raise CollectError(f"{out} holds data but no {PROGRESS_FILE}: use an empty or new --out")
            progress = _Progress()
            _save_progress(out, config, progress)
        writers = _open_writers(out, config, progress)
        start_committed, start = progress.committed, time.perf_counter()
        bar = tqdm(total=config.episodes, initial=min(progress.committed, config.episodes), unit="ep",
                   desc=config.env_id.split("/")[-1], disable=not show_progress, dynamic_ncols=True)
        try:
            if progress.committed < config.episodes:
                _run(config, policy or config.policy, out, progress, writers, bar, checkpoint_seconds)
        finally:
            bar.close()
            writers.close()  # counts what was committed
            _save_progress(out, config, progress, durable=False)
            # Everything was written crash-safe (whole or absent) but without an fsync each;
            # one sync makes the run durable before the final count.
            os.sync()
        progress.complete = progress.committed >= config.episodes
        _save_progress(out, config, progress)
        summary = CollectSummary(str(out), progress.committed, progress.committed - start_committed,
                                 progress.failures, progress.committed + progress.failures,
                                 time.perf_counter() - start,
                                 config.resolved_dataset_id() if writers.minari is not None else None)
        if not progress.complete:
            raise CollectError(f"only {progress.committed} of {config.episodes} episodes succeeded in "
                               f"{summary.attempts} attempts (the limit is {config.attempt_limit()}; raise "
                               f"--max-attempts); what succeeded is kept in {out}")
        return summary
    finally:
        lock.close()


def describe(summary: CollectSummary) -> str:
    rate = f"{summary.success_rate:.1%}" if summary.attempts else "n/a"
    speed = f", {summary.episodes_per_second:.2f} episodes/s" if summary.new_episodes else ""
    lines = [f"{summary.episodes} episodes in {summary.out} ({summary.new_episodes} new in "
             f"{summary.seconds:.1f} s{speed}); {summary.failures} failed attempts, success rate {rate}"]
    if summary.dataset_id:
        lines.append(f"Minari: MINARI_DATASETS_PATH={Path(summary.out) / 'minari'} "
                     f"python -c \"import minari; minari.load_dataset('{summary.dataset_id}')\"")
    return "\n".join(lines)

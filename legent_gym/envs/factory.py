"""Helper processes that prepare the coming episodes, so that a reset only takes one.

An :class:`~legent_gym.envs.episode.Episode` begun without a seed plays the episode of a
seed that is known before it is asked for (:meth:`Episode.upcoming`: the next seeds of
the current block of ``episodes_per_house``, then blocks drawn from the env's generator),
and the episode of a seed depends on the seed alone (:meth:`Episode.play`). So the
coming episodes can be played ahead, elsewhere: :class:`EpisodeFactory` keeps ``helpers``
processes, each holding a copy of the episode engine, busy playing the seeds the env will
ask for next (generating and compiling the house, drawing spawns and the goal, checking
its feasibility, measuring the distance to it), and shipping each as a
:class:`PreparedEpisode`: the house (the compiled model as MuJoCo's binary, its state as
built, its tables and navigation grid) unless the env holds it already, the spawns, the
goal and the distance fields found on the way. The env's reset then loads that instead of
doing the work. For a new house that is the model from its binary, a new ``MjData`` set to
the state as built (kept as that state alone: :class:`~legent_gym.world.state.WorldState`),
one ``mj_forward``, the renderer's upload of the house's meshes and texture and the first
frame; the asset library's models are loaded only when something reads them
(:class:`HouseAssets`).

* The same seeds give the same episodes with or without helpers (``tests/envs/test_factory.py``
  compares observations and infos): a helper runs the same code on the same seed; an
  episode not prepared (a seed nobody predicted, a helper's error) is played in the env's
  process as without helpers.
* Each helper is a child process (``python -m legent_gym.envs.factory``, so that an env in a
  daemonic vector-env worker may have them too), at the CPU affinity its env's process had
  before a vector env's worker pinned itself to one core (``legent_gym/envs/vector.py``),
  so helpers use the cores the stepping processes leave. The env hands work out a few
  episodes ahead (:attr:`EpisodeFactory.lookahead`), the episodes of one house to one
  helper, which keeps the house.
* Helpers stop with :meth:`EpisodeFactory.close` (the env's ``close()``), at interpreter
  exit, and by themselves when their env's process goes (their pipe ends: they stop once
  the episode in hand is done, and remove the folder below). A helper that dies makes the next reset that waits on it
  raise :class:`HelperDied`, naming its exit status.
* What they ship lies in a private temporary folder (on ``/dev/shm`` where there is one),
  removed on close.

Helpers are used for generated houses (a new seed each episode, or a fixed ``house_seed``)
and ``houses`` folders; with a fixed ``scene`` or a ``house_pool`` (whose houses depend on
what was drawn before) episodes are played in the env's process.
"""

from __future__ import annotations

import atexit
import contextlib
import dataclasses
import os
import pickle
import shutil
import socket
import subprocess
import sys
import tempfile
import threading
import traceback
import weakref
from collections import OrderedDict, deque
from collections.abc import Collection, Iterator, Mapping
from dataclasses import dataclass
from multiprocessing.connection import Connection, wait
from pathlib import Path
from typing import TYPE_CHECKING, Any

import mujoco
import numpy as np

from legent_gym.envs.houses import House, HouseDraw
from legent_gym.world.assets import registry
from legent_gym.world.assets.model import AssetModel
from legent_gym.world.builder import World
from legent_gym.world.navigation import NavGrid
from legent_gym.world.scene import Scene, Spawn
from legent_gym.world.state import WorldState

if TYPE_CHECKING:  # episode.py starts the factory: its class is named here for the types alone
    from legent_gym.envs.episode import Episode

#: What a helper's world state is shipped as (all MuJoCo needs to go on from it).
STATE = mujoco.mjtState.mjSTATE_INTEGRATION
#: World fields shipped beside the model and data (the rest are made again on use).
WORLD_TABLES = tuple(f.name for f in dataclasses.fields(World) if f.init and f.name not in ("model", "data"))
#: Seconds close() waits for a helper to exit before it is killed.
CLOSE_TIMEOUT = 5.0
#: Episodes of new houses each helper is given ahead of the env (one playing, one waiting).
AHEAD_PER_HELPER = 2
#: House keys a helper remembers having shipped (see ``helper_main``).
RECENT_HOUSES = 16


class HelperDied(RuntimeError):
    """An episode helper process ended while its env waited for it."""


def _not_loadable() -> tuple[Scene, NavGrid | None]:
    raise RuntimeError("this house came built from an episode helper and cannot be loaded again")


class ShippedModel:
    """An asset library model as a helper pickled it: unpickled on first use, once.

    An episode's tasks read a few of its house's models (names, category, bounds,
    receptacles of the objects the goal names), most are never read in the env's process;
    and a model is dozens of small arrays, which cost more to unpickle than the rest of a
    prepared episode."""

    __slots__ = ("blob", "_model")

    def __init__(self, blob: bytes):
        self.blob = blob
        self._model: AssetModel | None = None

    def get(self) -> AssetModel:
        if self._model is None:
            self._model = pickle.loads(self.blob)
            self.blob = b""
        return self._model


class HouseAssets(Mapping[int, AssetModel]):
    """``World.assets`` of a house a helper built: object id -> asset model, each made
    on first use (see :class:`ShippedModel`); a model no helper shipped is made by the
    asset library."""

    def __init__(self, refs: dict[int, tuple[str, int] | None], own: dict[int, AssetModel],
                 library: dict[tuple[str, int], ShippedModel]):
        self._refs = refs
        self._own = own
        self._library = library
        self._models: dict[int, AssetModel] = {}

    def __getitem__(self, object_id: int) -> AssetModel:
        model = self._models.get(object_id)
        if model is None:
            ref = self._refs[object_id]
            if ref is None:
                model = self._own[object_id]
            else:
                shipped = self._library.get(ref)
                model = shipped.get() if shipped is not None else registry.make(*ref)
            self._models[object_id] = model
        return model

    def __iter__(self) -> Iterator[int]:
        return iter(self._refs)

    def __len__(self) -> int:
        return len(self._refs)


@dataclass
class HousePayload:
    """A house built by a helper: what the env needs to use it without building it."""

    key: tuple
    seed: int | None
    draw_seed: int | None
    spawns_drawn: bool
    repeats: bool
    scene: Scene
    nav: NavGrid
    tables: dict[str, Any]
    #: The world's state as built (mj_getState of :data:`STATE`).
    state: np.ndarray
    geom_contype: np.ndarray
    geom_conaffinity: np.ndarray
    model_path: str
    #: Object id -> (asset id, variant) of the objects whose model is the asset library's
    #: own (None for the others, shipped in ``tables``), in the world's order of ``assets``.
    asset_refs: dict[int, tuple[str, int] | None]
    #: The library's models of the refs this helper has not shipped before, each pickled
    #: on its own (see :class:`ShippedModel`).
    library: dict[tuple[str, int], bytes]

    @classmethod
    def of(cls, house: House, model_path: str, shipped: set[tuple[str, int]]) -> HousePayload:
        """The payload of ``house``, whose model as built is at ``model_path`` (MuJoCo's
        binary); the library models named in ``shipped`` (what the env was sent before)
        are named, not shipped, and ``shipped`` gets the rest."""
        world, built = house.world, house.built
        if built.data is not None:
            state = np.empty(mujoco.mj_stateSize(world.model, STATE))
            mujoco.mj_getState(world.model, built.data, state, STATE)
        else:  # a house loaded as a payload (legent_gym.envs.house_store) keeps that state alone
            assert built.integration is not None
            state = built.integration
        draw = house.draw
        tables = {name: getattr(world, name) for name in WORLD_TABLES}
        refs: dict[int, tuple[str, int] | None] = dict.fromkeys(world.assets)
        for obj in house.scene.objects:
            if obj.id in refs and registry.has(obj.asset) and registry.make(obj.asset, obj.variant) is world.assets[obj.id]:
                refs[obj.id] = (obj.asset, obj.variant)
        tables["assets"] = {i: model for i, model in world.assets.items() if refs[i] is None}
        library = {}
        for i, ref in refs.items():
            if ref is not None and ref not in shipped:
                library[ref] = pickle.dumps(world.assets[i], protocol=pickle.HIGHEST_PROTOCOL)
                shipped.add(ref)
        return cls(draw.key, house.seed, draw.seed, draw.spawns_drawn, draw.repeats, house.scene, house.nav,
                   tables, state, built.geom_contype, built.geom_conaffinity, model_path, refs, library)

    def to_house(self, library: dict[tuple[str, int], ShippedModel]) -> House:
        """The house, built from the shipped model (as the helper built it); ``library``
        holds the asset library's models helpers shipped before (it gets these ones).

        The world's data holds the state as built but not yet what ``mj_forward`` computes
        from it: the episode that enters the house restores that state and runs
        ``mj_forward`` (``Episode._enter``); its state as built is kept as that state
        alone (no second ``MjData``)."""
        model = mujoco.MjModel.from_binary_path(self.model_path)
        data = mujoco.MjData(model)
        mujoco.mj_setState(model, data, self.state, STATE)
        model.geom_contype[:] = self.geom_contype
        model.geom_conaffinity[:] = self.geom_conaffinity
        for ref, blob in self.library.items():
            library[ref] = ShippedModel(blob)
        assets = HouseAssets(self.asset_refs, self.tables["assets"], library)
        world = World(model=model, data=data, **{**self.tables, "assets": assets})
        built = WorldState(None, self.geom_contype, self.geom_conaffinity, integration=self.state)
        draw = HouseDraw(self.key, self.draw_seed, _not_loadable, spawns_drawn=self.spawns_drawn,
                         repeats=self.repeats)
        return House(draw, self.scene, world, self.nav, built, self.seed)


@dataclass
class PreparedEpisode:
    """One episode a helper played: enough for :meth:`Episode.begin` to take it as it is."""

    seed: int
    attempts: int
    #: The key of its house, and the house itself unless the env was known to hold it.
    key: tuple
    house: HousePayload | None
    #: The house's episode count after this episode began.
    episodes: int
    agent: Spawn
    user: Spawn | None
    goal: Any
    #: The task context's distance caches (see ``TaskContext.cached_distances``).
    distances: dict[str, dict]


#: The asset library's models this helper has shipped to its env (see HousePayload.of).
_SHIPPED_ASSETS: set[tuple[str, int]] = set()


def prepare(episode: Episode, seed: int, known: set, folder: str, shipped: Collection[tuple]) -> PreparedEpisode:
    """Play ``seed`` in ``episode`` (a helper's copy) and describe the result; the house
    goes along unless its key is in ``known`` or in ``shipped`` (sent with an episode the
    env will take before this one)."""
    attempts = episode.play(seed)
    ctx, goal, house = episode.require(), episode.require_goal(), episode.house
    assert house is not None
    goal.distance_left(ctx)  # what the env's reset measures, found here
    key = house.draw.key
    payload = None
    if key not in known and key not in shipped:
        assert house.binary is not None, "the helper keeps its houses' binaries"
        model_path = os.path.join(folder, f"{os.getpid()}-{seed}.mjb")
        Path(model_path).write_bytes(house.binary.tobytes())
        payload = HousePayload.of(house, model_path, _SHIPPED_ASSETS)
    return PreparedEpisode(seed, attempts, key, payload, house.episodes, ctx.scene.agent, ctx.scene.user, goal,
                           ctx.cached_distances())


# -- the env's side ---------------------------------------------------------------------------
_LIVE: weakref.WeakSet[EpisodeFactory] = weakref.WeakSet()


@atexit.register
def _close_all() -> None:
    for factory in list(_LIVE):
        factory.close()


def _shared_memory_dir() -> str | None:
    return "/dev/shm" if os.path.isdir("/dev/shm") and os.access("/dev/shm", os.W_OK) else None


def _helper_affinity() -> set[int] | None:
    """The cores helpers may use: those of the process that started this vector-env worker
    when the worker pinned itself to one core, else this process's."""
    if not hasattr(os, "sched_getaffinity"):
        return None
    mine = os.sched_getaffinity(0)
    if len(mine) == 1:
        with contextlib.suppress(OSError):
            return os.sched_getaffinity(os.getppid())
    return mine


class _Helper:
    """One helper process and its pipe."""

    def __init__(self, index: int, blob: bytes, folder: str):
        self.index = index
        ours, theirs = socket.socketpair()
        self.proc = subprocess.Popen([sys.executable, "-m", "legent_gym.envs.factory", str(theirs.fileno())],
                                     pass_fds=(theirs.fileno(),), stdin=subprocess.DEVNULL, close_fds=True)
        theirs.close()
        self.conn = Connection(ours.detach())
        affinity = _helper_affinity()
        if affinity:
            with contextlib.suppress(OSError):
                os.sched_setaffinity(self.proc.pid, affinity)
        self.conn.send({"episode": blob, "folder": folder})
        #: Seeds sent and not yet answered, in order.
        self.outstanding: deque[int] = deque()

    def died(self) -> HelperDied:
        code = self.proc.wait()
        return HelperDied(f"episode helper process {self.index} (pid {self.proc.pid}) exited with status {code} "
                          "while its env waited for an episode; its error, if any, is on stderr above")

    def close(self) -> None:
        with contextlib.suppress(OSError, ValueError):
            self.conn.send(None)
        with contextlib.suppress(OSError):
            self.conn.close()
        try:
            self.proc.wait(timeout=CLOSE_TIMEOUT)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()


class EpisodeFactory:
    """``helpers`` processes preparing the episodes of the seeds an :class:`Episode` will
    ask for (see the module docstring)."""

    def __init__(self, episode: Episode, helpers: int):
        if helpers < 1:
            raise ValueError(f"an episode factory needs at least one helper, got {helpers}")
        k = episode.episodes_per_house
        #: How many coming episodes are handed out: the houses of ``helpers`` blocks ahead.
        self.lookahead = helpers * AHEAD_PER_HELPER if k == 1 else k * (helpers + 1)
        self.episodes_per_house = k
        self.folder = tempfile.mkdtemp(prefix="legent-episodes-", dir=_shared_memory_dir())
        blob = pickle.dumps(episode, protocol=pickle.HIGHEST_PROTOCOL)
        self._lock = threading.Lock()
        self._helpers: list[_Helper] = []
        self._closed = False
        _LIVE.add(self)
        try:
            for i in range(helpers):
                self._helpers.append(_Helper(i, blob, self.folder))
        except BaseException:
            self.close()
            raise
        #: seed -> the helper playing it, for seeds sent and not yet answered.
        self._playing: dict[int, _Helper] = {}
        #: seed -> ("ok", its files) or ("error", [the helper's traceback]): answers not yet taken.
        self._ready: dict[int, tuple[str, list[str]]] = {}
        #: Files of episodes taken or dropped, for the next job's helper to remove.
        self._spent: list[str] = []
        #: Errors helpers reported (the episode was then played in the env's process).
        self.errors: list[str] = []
        #: Episodes taken that brought their house.
        self.houses_received = 0
        #: The asset library's models helpers shipped, by (asset id, variant).
        self.library: dict[tuple[str, int], ShippedModel] = {}

    @property
    def pids(self) -> list[int]:
        """The helper processes' ids."""
        return [h.proc.pid for h in self._helpers]

    # -- asking ---------------------------------------------------------------------------------
    def want(self, seeds: list[int], known: set) -> None:
        """Have ``seeds`` prepared (those not already), in order; ``known`` are the keys of
        the houses the env holds (not shipped again). Answers for other seeds are dropped."""
        self._receive(block=False)
        wanted = set(seeds)
        for seed in [s for s in self._ready if s not in wanted]:
            status, files = self._ready.pop(seed)
            if status == "ok":
                self._spent.extend(files)
        k = self.episodes_per_house
        jobs: dict[int, list[int]] = {}
        for seed in seeds:
            if seed not in self._playing and seed not in self._ready:
                jobs.setdefault(seed // k, []).append(seed)
        # Blocks with an episode sent before: its house comes with that one (when it is not
        # known), which the env takes first; a helper that shipped it does not ship it again.
        coming = {s // k for s in self._playing} | {s // k for s in self._ready}
        for block, job in jobs.items():
            helper = self._helper_for(job[0])
            # The helper removes the files of episodes taken or dropped (not the env's time).
            try:
                helper.conn.send({"seeds": job, "known": known, "remove": self._spent, "coming": block in coming})
            except OSError as err:
                raise helper.died() from err
            self._spent = []
            helper.outstanding.extend(job)
            for seed in job:
                self._playing[seed] = helper

    def _helper_for(self, seed: int) -> _Helper:
        """The helper already playing this seed's block (it holds the house), else the least busy."""
        block = seed // self.episodes_per_house
        for s, helper in self._playing.items():
            if s // self.episodes_per_house == block:
                return helper
        return min(self._helpers, key=lambda h: len(h.outstanding))

    def take(self, seed: int) -> PreparedEpisode | None:
        """The episode of ``seed`` if it was asked for (waiting for it), else None; None
        too when its helper failed (the env then plays it itself)."""
        if seed not in self._playing and seed not in self._ready:
            return None
        while seed not in self._ready:
            self._receive(block=True, helper=self._playing[seed])
        status, files = self._ready.pop(seed)
        if status != "ok":
            self.errors.extend(files)
            return None
        self._spent.extend(files)
        with open(files[0], "rb") as fh:
            prepared: PreparedEpisode = pickle.load(fh)
        self.houses_received += prepared.house is not None
        return prepared

    def take_ready(self, seed: int) -> PreparedEpisode | None:
        """:meth:`take` if the episode of ``seed`` has come (never waits); else None."""
        if seed not in self._ready:
            if seed not in self._playing:
                return None
            self._receive(block=False)
            if seed not in self._ready:
                return None
        return self.take(seed)

    def _receive(self, *, block: bool, helper: _Helper | None = None) -> None:
        busy = [h for h in self._helpers if h.outstanding]
        if helper is not None:
            busy = [helper]
        if not busy:
            return
        by_id = {id(h.conn): h for h in busy}
        for conn in wait([h.conn for h in busy], timeout=None if block else 0):
            h = by_id[id(conn)]
            try:
                status, seed, files = h.conn.recv()
            except (EOFError, OSError) as err:
                raise h.died() from err
            h.outstanding.popleft()
            self._playing.pop(seed, None)
            self._ready[seed] = (status, files)

    # -- cleaning up ----------------------------------------------------------------------------
    def close(self) -> None:
        """Stop the helpers and remove what they left (idempotent)."""
        with self._lock:
            if self._closed:
                return
            self._closed = True
        for helper in self._helpers:
            helper.close()
        shutil.rmtree(self.folder, ignore_errors=True)
        _LIVE.discard(self)


# -- the helper's side ------------------------------------------------------------------------
def helper_main(fd: int) -> int:
    """Play the seeds the env sends until it sends None or goes (see the module docstring)."""
    conn = Connection(fd)
    try:
        init = conn.recv()
    except EOFError:
        return 0
    episode: Episode = pickle.loads(init["episode"])
    episode.prepare_ahead, episode.helpers, episode.keep_binaries = False, 0, True
    folder = init["folder"]
    #: Keys of the houses this helper shipped last, oldest first.
    recent: OrderedDict[tuple, None] = OrderedDict()
    while True:
        try:
            job = conn.recv()
        except EOFError:  # the env's process is gone without closing: nobody else cleans up
            shutil.rmtree(folder, ignore_errors=True)
            return 0
        if job is None:
            return 0
        for spent in job["remove"]:
            with contextlib.suppress(OSError):
                os.unlink(spent)
        shipped = set(recent) if job["coming"] else set()
        for seed in job["seeds"]:
            path = os.path.join(folder, f"{os.getpid()}-{seed}.pkl")
            try:
                prepared = prepare(episode, seed, job["known"], folder, shipped)
                shipped.add(prepared.key)
                if prepared.house is not None:
                    recent[prepared.key] = None
                    while len(recent) > RECENT_HOUSES:
                        recent.popitem(last=False)
                tmp = path + ".tmp"
                with open(tmp, "wb") as fh:
                    pickle.dump(prepared, fh, protocol=pickle.HIGHEST_PROTOCOL)
                os.replace(tmp, path)
                files = [path] + ([prepared.house.model_path] if prepared.house is not None else [])
                answer: tuple[str, int, list[str]] = ("ok", seed, files)
            except Exception:  # noqa: BLE001 - the env plays this seed itself and meets the error there
                answer = ("error", seed, [traceback.format_exc()])
            try:
                conn.send(answer)
            except OSError:
                shutil.rmtree(folder, ignore_errors=True)
                return 0


if __name__ == "__main__":
    # The module's own names, not __main__'s, so that what helpers pickle loads in the env.
    from legent_gym.envs.factory import helper_main as _main

    sys.exit(_main(int(sys.argv[1])))

"""Our vector env: worker processes that write observations straight into one shared batch.

``gym.make_vec(id, num_envs=N, vectorization_mode="vector_entry_point")`` (or with no
``vectorization_mode``: Gymnasium then prefers a registered vector entry point) returns a
:class:`SharedMemoryVectorEnv` for every registered id::

    import gymnasium as gym
    import legent_gym

    envs = gym.make_vec("Legent/ComeHere-OneRoom-v0", num_envs=8, vectorization_mode="vector_entry_point")
    obs, info = envs.reset(seed=0)
    obs, reward, terminated, truncated, info = envs.step(actions)
    envs.close()

It returns the same observations, rewards, terminations, truncations and infos as
Gymnasium's ``SyncVectorEnv`` (``vectorization_mode="sync"``) of the same seeds and
actions, with Gymnasium's next-step autoreset (``metadata["autoreset_mode"]`` is
``AutoresetMode.NEXT_STEP``: the step after an episode's last one returns the reset
observation, reward 0 and no termination, and ignores its action), but runs each env in a
worker process and costs the calling process little per env-step:

* one worker process per env, started by a ``forkserver`` (never forked from this process:
  see ``docs/architecture.md``, "Processes and OpenGL"), which the env pins to one core,
  round robin over the cores this process may use (``legent_gym/envs/vector.py``);
* observations are written by the workers into one block of shared memory that holds the
  whole batch (NumPy arrays; text as Unicode code points, as
  :class:`~legent_gym.envs.text_space.VectorSafeText` does), with the rewards, terminations
  and truncations; nothing of an observation is pickled;
* commands and replies pass through per-worker slots of shared memory (see
  :class:`_Channel`): this process wakes one worker per batch (the wake-up passes down a
  tree of workers) and is woken once, by the worker whose reply completes the batch;
* a worker's reply carries only the ``info`` entries that changed since its previous one
  (the key structure and types again only when they change); this process keeps every
  env's latest info, per kind of leaf in one block, and a batch's info is a copy per kind
  (Gymnasium's ``_add_info`` layout: ``info[k]`` an array over envs, ``info["_k"]`` its
  mask; ``lazy_infos=True`` builds it only when read);
* the autoreset happens in the worker;
* an exception in a worker's env is raised here as :class:`WorkerError`, naming the worker
  and carrying its traceback; a worker that dies raises it too, with its exit code;
* :meth:`SharedMemoryVectorEnv.send` / :meth:`~SharedMemoryVectorEnv.recv` (with
  ``batch_size``) step EnvPool's way: ``recv()`` returns the first envs done;
* ``close()`` ends the workers and frees the shared memory (an unlinked file, and
  named semaphores that ``multiprocessing`` unlinks when they are freed, or its resource
  tracker when this process is killed: nothing is left in ``/dev/shm``); workers also end
  by themselves when this process goes.

Observation spaces of ``Box``, ``Discrete``, ``MultiBinary``, ``MultiDiscrete`` and
``Text`` leaves, nested in ``Dict`` and ``Tuple``, are supported (all the envs' spaces); the
class may be made directly, with an env id, the env's keyword arguments and its own
options (``copy``, ``lazy_infos``, ``batch_size``; also through ``make_vec``)::

    from legent_gym.envs.shared_vector import SharedMemoryVectorEnv

    envs = SharedMemoryVectorEnv("Legent/ComeHere-OneRoom-v0", 4, copy=False, episodes_per_house=8)
"""

from __future__ import annotations

import contextlib
import multiprocessing
import multiprocessing.connection
import os
import pickle
import signal
import time
import traceback
from collections.abc import Callable, Iterable, Iterator, Sequence
from copy import deepcopy
from itertools import chain
from operator import itemgetter
from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium import spaces
from gymnasium.vector import AutoresetMode, VectorEnv
from gymnasium.vector.utils import batch_space, iterate

__all__ = ["LazyInfos", "SharedMemoryVectorEnv", "WorkerError", "make_vector"]

#: The vector entry point registered for every id (``legent_gym/envs/registration.py``).
VECTOR_ENTRY_POINT = f"{__name__}:make_vector"
#: The start method of the workers.
CONTEXT = "forkserver"
#: Seconds close() waits for a worker to end before it is terminated.
CLOSE_TIMEOUT = 10.0
#: Seconds between checks that the workers live while waiting for their replies.
POLL_SECONDS = 1.0
#: Bytes of a worker's command slot and reply slot in shared memory (a bigger message goes
#: through its pipe).
COMMAND_SLOT = 16 * 1024
REPLY_SLOT = 64 * 1024
#: Alignment of each array in the shared block (bytes).
ALIGN = 64

# Commands (this process -> worker) and replies (worker -> this process): one byte, then a
# pickled payload where there is one.
_STEP, _RESET, _CALL, _SETATTR, _CLOSE = b"s", b"r", b"c", b"a", b"x"
_STEP_TEXT = b"t"  # a step whose action is a str, sent as UTF-8 (no pickling)
_DONE, _VALUE, _ERROR = 0x6F, 0x76, 0x65  # "o", "v", "e" as the first byte of a reply
_DONE_BYTE = b"o"
_PICKLE = pickle.HIGHEST_PROTOCOL


class WorkerError(RuntimeError):
    """A worker's env raised (its traceback is in the message) or the worker died."""

    def __init__(self, message: str, index: int):
        super().__init__(message)
        #: The env's index in the vector env.
        self.index = index


# -- the shared batch ---------------------------------------------------------------------------
class _Leaf:
    """One array of the shared batch: a path into the observation (``()`` for the top) or a
    name, and how to view it."""

    __slots__ = ("path", "kind", "dtype", "shape", "offset", "max_length")

    def __init__(self, path: tuple, kind: str, dtype: np.dtype, shape: tuple[int, ...], max_length: int = 0):
        self.path, self.kind, self.dtype, self.shape, self.max_length = path, kind, dtype, shape, max_length
        self.offset = 0

    def nbytes(self, n: int) -> int:
        return int(n * int(np.prod(self.shape, dtype=np.int64)) * self.dtype.itemsize)

    def view(self, buffer: Any, n: int) -> np.ndarray:
        return np.ndarray((n, *self.shape), dtype=self.dtype, buffer=buffer, offset=self.offset)


def _leaves(space: spaces.Space, path: tuple = ()) -> list[_Leaf]:
    """The arrays a batch of observations of ``space`` is kept in."""
    if isinstance(space, spaces.Dict):
        return [leaf for key, sub in space.spaces.items() for leaf in _leaves(sub, (*path, key))]
    if isinstance(space, spaces.Tuple):
        return [leaf for i, sub in enumerate(space.spaces) for leaf in _leaves(sub, (*path, i))]
    if isinstance(space, spaces.Text):
        return [_Leaf(path, "text", np.dtype((np.str_, space.max_length)), (), space.max_length)]
    if isinstance(space, spaces.Box | spaces.Discrete | spaces.MultiBinary | spaces.MultiDiscrete):
        return [_Leaf(path, "array", np.dtype(space.dtype), tuple(space.shape or ()))]
    raise TypeError(f"SharedMemoryVectorEnv cannot keep observations of {type(space).__name__} spaces in shared "
                    f"memory ({space}); use gym.make_vec(..., vectorization_mode='async') for this env")


class _Layout:
    """Where the batch's observation leaves, rewards, terminations and truncations lie in
    one shared block."""

    def __init__(self, space: spaces.Space, n: int):
        self.space, self.n = space, n
        self.obs = _leaves(space)
        self.rewards = _Leaf(("reward",), "array", np.dtype(np.float64), ())
        self.terminations = _Leaf(("terminated",), "array", np.dtype(np.bool_), ())
        self.truncations = _Leaf(("truncated",), "array", np.dtype(np.bool_), ())
        # Per env, a count of the changes of each text leaf: this process decodes a text
        # again only when its count moved.
        self.texts = [k for k, leaf in enumerate(self.obs) if leaf.kind == "text"]
        self.text_versions = _Leaf(("text versions",), "array", np.dtype(np.int64), (max(1, len(self.texts)),))
        offset = 0
        for leaf in (*self.obs, self.rewards, self.terminations, self.truncations, self.text_versions):
            leaf.offset = offset
            offset += -(-leaf.nbytes(n) // ALIGN) * ALIGN
        self.size = max(offset, ALIGN)


class _Views:
    """NumPy views of a shared block laid out by a :class:`_Layout`."""

    def __init__(self, layout: _Layout, buffer: Any):
        n = layout.n
        self.obs = [leaf.view(buffer, n) for leaf in layout.obs]
        self.rewards = layout.rewards.view(buffer, n)
        self.terminations = layout.terminations.view(buffer, n)
        self.truncations = layout.truncations.view(buffer, n)
        self.text_versions = layout.text_versions.view(buffer, n)


def _get(obs: Any, path: tuple) -> Any:
    for key in path:
        obs = obs[key]
    return obs


class _ObsReader:
    """In this process: the batched observation, in the structure Gymnasium's
    ``concatenate`` gives (arrays, and a tuple of ``str`` for a text), read from the shared
    batch; texts decoded only where their change counts moved."""

    def __init__(self, layout: _Layout, views: _Views, copy: bool):
        self.space, self.layout, self.views, self.copy = layout.space, layout, views, copy
        self._texts: dict[int, tuple[str, ...]] = {}
        self._versions = b""

    def read(self) -> Any:
        views, layout = self.views, self.layout
        values: list[Any] = [view.copy() if self.copy and leaf.kind != "text" else view
                             for leaf, view in zip(layout.obs, views.obs)]
        if layout.texts:
            versions = views.text_versions.tobytes()
            if versions != self._versions:
                self._texts.clear()
                self._versions = versions
            for k in layout.texts:
                text = self._texts.get(k)
                if text is None:
                    text = self._texts[k] = tuple(views.obs[k].tolist())
                values[k] = text
        it = iter(values)
        return _assemble(self.space, it)

    def read_rows(self, rows: np.ndarray) -> Any:
        """The observations of the envs ``rows`` (copies), in that order."""
        values = [tuple(view[rows].tolist()) if leaf.kind == "text" else view[rows]
                  for leaf, view in zip(self.layout.obs, self.views.obs)]
        return _assemble(self.space, iter(values))


def _assemble(space: spaces.Space, values: Iterator[Any]) -> Any:
    if isinstance(space, spaces.Dict):
        return {key: _assemble(sub, values) for key, sub in space.spaces.items()}
    if isinstance(space, spaces.Tuple):
        return tuple(_assemble(sub, values) for sub in space.spaces)
    return next(values)


# -- infos ----------------------------------------------------------------------------------------
def _flatten(info: dict, prefix: tuple, out: list) -> None:
    """(path, value) of every leaf of a nested info dict, in its order; an empty dict is a leaf."""
    for key, value in info.items():
        if type(value) is dict and value:
            _flatten(value, (*prefix, key), out)
        else:
            out.append(((*prefix, key), value))


def _unflatten(schema: Sequence[tuple[tuple, type]], values: Sequence[Any]) -> dict:
    out: dict = {}
    for (path, _), value in zip(schema, values):
        node = out
        for key in path[:-1]:
            node = node.setdefault(key, {})
        node[path[-1]] = value
    return out


def _same(a: Any, b: Any) -> bool:
    if a is b:
        return True
    if type(a) is not type(b) or isinstance(a, np.ndarray | dict | list):
        return False
    try:
        return bool(a == b)
    except Exception:  # a value whose == is not a truth value (tuples of arrays)
        return False


def _numeric(t: type) -> bool:
    """A leaf type ``_add_info`` keeps in an array of that type (not an object array)."""
    return t in (int, float, bool) or issubclass(t, np.number)


class _InfoSender:
    """In a worker: the info message that brings this process's copy up to date."""

    def __init__(self) -> None:
        self.schema: tuple | None = None
        self.values: list = []

    def message(self, info: dict) -> bytes:
        flat: list = []
        _flatten(info, (), flat)
        schema = tuple((path, type(value)) for path, value in flat)
        values = [value for _, value in flat]
        if schema != self.schema:
            self.schema, self.values = schema, values
            return pickle.dumps((schema, values), _PICKLE)
        changed = [(j, v) for j, (v, old) in enumerate(zip(values, self.values)) if not _same(v, old)]
        self.values = values
        return pickle.dumps(changed, _PICKLE) if changed else b""


class _InfoBook:
    """In this process: each env's latest info (schema and values), and the batched infos."""

    def __init__(self, n: int, add_info: Callable[[dict, dict, int], dict]):
        self.n, self._add_info = n, add_info
        self.schemas: list[tuple] = [()] * n
        self.values: list[list] = [[] for _ in range(n)]
        self._interned: dict[tuple, tuple] = {}
        # Whether every env's schema is the same one, of plain leaves (the fast path).
        self._uniform: bool | None = None
        self._plans: dict[tuple, _ColumnPlan] = {}
        self._kept: _KeptColumns | None = None

    def update(self, i: int, payload: bytes | memoryview) -> None:
        if not payload:
            return
        data = pickle.loads(payload)
        if type(data) is tuple:  # (schema, values): a new structure
            schema, values = data
            self.schemas[i] = self._interned.setdefault(schema, schema)
            self.values[i] = values
            self._uniform, self._kept = None, None
        else:
            values = self.values[i]
            kept = self._kept
            if kept is None:
                for j, value in data:
                    values[j] = value
            else:
                where = kept.where
                for j, value in data:
                    values[j] = value
                    spot = where.get(j)
                    if spot is not None:
                        spot[0][spot[1], i] = value

    def batch(self, envs: Sequence[int] | None = None) -> dict:
        """The batched infos of ``envs`` (all when None), as ``SyncVectorEnv`` gives them."""
        if envs is None and self._fast():
            return self._columns()
        infos: dict = {}
        for i in range(self.n) if envs is None else envs:
            infos = self._add_info(infos, _unflatten(self.schemas[i], self.values[i]), i)
        return infos

    def lazy(self, envs: Sequence[int] | None = None) -> LazyInfos:
        """:meth:`batch` of the infos as they are now, built on first use."""
        book = _InfoBook(self.n, self._add_info)
        book.schemas, book.values = list(self.schemas), [list(v) for v in self.values]
        if self._uniform:
            book._uniform, book._plan = True, self._plan
        return LazyInfos(lambda: book.batch(envs))


    def _fast(self) -> bool:
        if self._uniform is None:
            first = self.schemas[0]
            self._uniform = all(s is first for s in self.schemas) and not any(
                t is dict or path == ("final_obs",) for path, t in first)
            if self._uniform:
                self._plan = _ColumnPlan(first)
                self._kept = _KeptColumns(self._plan, self.values, self.n)
        return self._uniform

    def _columns(self) -> dict:
        return self._plan.build(self.values, self.n, self._kept)

    def compact(self, envs: Sequence[int]) -> dict:
        """The infos of ``envs`` batched as a vector env of ``len(envs)`` envs would give
        them, in that order (what :meth:`SharedMemoryVectorEnv.recv` returns)."""
        schema = self.schemas[envs[0]]
        if all(self.schemas[i] is schema for i in envs) and not any(
                t is dict or path == ("final_obs",) for path, t in schema):
            plan = self._plans.get(schema)
            if plan is None:
                plan = self._plans[schema] = _ColumnPlan(schema)
            return plan.build([self.values[i] for i in envs], len(envs))
        sized = _Sized(len(envs))
        infos: dict = {}
        for k, i in enumerate(envs):
            infos = sized._add_info(infos, _unflatten(self.schemas[i], self.values[i]), k)  # type: ignore[misc]
        return infos


class _Sized:
    """Gymnasium's ``_add_info`` for a batch of ``num_envs`` envs."""

    _add_info = VectorEnv._add_info

    def __init__(self, num_envs: int):
        self.num_envs = num_envs

class LazyInfos(dict):
    """A vector env's batched infos (a ``dict``), built from the workers' messages the
    first time anything reads them (``SharedMemoryVectorEnv(..., lazy_infos=True)``).
    Reading, writing, copying or pickling it gives the same as the plain dict would; it
    is a ``dict`` subclass, so code that asks ``type(infos) is dict`` (Gymnasium's
    ``data_equivalence``) tells them apart: ``dict(infos)`` is the plain dict."""

    __slots__ = ("_build",)

    def __init__(self, build: Callable[[], dict]):
        super().__init__()
        self._build: Callable[[], dict] | None = build

    def _fill(self) -> None:
        build, self._build = self._build, None
        if build is not None:
            dict.update(self, build())

    def __getitem__(self, key: Any) -> Any:
        self._fill()
        return dict.__getitem__(self, key)

    def __contains__(self, key: object) -> bool:
        self._fill()
        return dict.__contains__(self, key)

    def __iter__(self) -> Iterator[Any]:
        self._fill()
        return dict.__iter__(self)

    def __len__(self) -> int:
        self._fill()
        return dict.__len__(self)

    def __repr__(self) -> str:
        self._fill()
        return dict.__repr__(self)

    def __eq__(self, other: object) -> bool:
        self._fill()
        if isinstance(other, LazyInfos):
            other._fill()
        return dict.__eq__(self, other)

    __hash__ = None

    def __setitem__(self, key: Any, value: Any) -> None:
        self._fill()
        dict.__setitem__(self, key, value)

    def __delitem__(self, key: Any) -> None:
        self._fill()
        dict.__delitem__(self, key)

    def __reversed__(self) -> Iterator[Any]:
        self._fill()
        return dict.__reversed__(self)

    def __or__(self, other: Any) -> dict:
        self._fill()
        return dict(self) | other

    def __ror__(self, other: Any) -> dict:
        self._fill()
        return other | dict(self)

    def __ior__(self, other: Any) -> LazyInfos:
        self._fill()
        dict.update(self, other)
        return self

    def __reduce__(self) -> tuple:
        self._fill()
        return dict, (dict(self),)

    def __copy__(self) -> dict:
        self._fill()
        return dict(self)

    def __deepcopy__(self, memo: dict) -> dict:
        self._fill()
        return deepcopy(dict(self), memo)

    def keys(self):
        self._fill()
        return dict.keys(self)

    def values(self):
        self._fill()
        return dict.values(self)

    def items(self):
        self._fill()
        return dict.items(self)

    def get(self, key: Any, default: Any = None) -> Any:
        self._fill()
        return dict.get(self, key, default)

    def copy(self) -> dict:
        self._fill()
        return dict(self)

    def pop(self, *args: Any) -> Any:
        self._fill()
        return dict.pop(self, *args)

    def popitem(self) -> tuple[Any, Any]:
        self._fill()
        return dict.popitem(self)

    def setdefault(self, key: Any, default: Any = None) -> Any:
        self._fill()
        return dict.setdefault(self, key, default)

    def update(self, *args: Any, **kwargs: Any) -> None:
        self._fill()
        dict.update(self, *args, **kwargs)

    def clear(self) -> None:
        self._build = None
        dict.clear(self)

class _ColumnPlan:
    """How to batch infos that all have one schema with a few NumPy calls: the leaves of one
    kind (each numeric type, objects) gathered into one block per kind, whose rows are the
    batched leaves; every mask a row of one block of ones. The arrays, their types and the
    key order are those of Gymnasium's ``_add_info`` (numeric leaves in an array of their
    type, arrays stacked, anything else in an object array)."""

    def __init__(self, schema: tuple):
        self.schema = schema
        kinds: dict[Any, list[int]] = {}
        for j, (_, t) in enumerate(schema):
            kinds.setdefault(t if _numeric(t) else np.ndarray if t is np.ndarray else object, []).append(j)
        self.groups = [(kind, idx, itemgetter(*idx) if len(idx) > 1 else _one(idx[0])) for kind, idx in kinds.items()]
        where = {j: (g, row) for g, (_, idx, _) in enumerate(self.groups) for row, j in enumerate(idx)}
        # What build() does, in order: (node to put into, key, mask key, mask row, what
        # goes in: (group, row) of a leaf, or the number of a new nested node).
        nodes: dict[tuple, int] = {(): 0}
        self.steps: list[tuple[int, Any, str, int, tuple[int, int] | int]] = []
        for j, (path, _) in enumerate(schema):
            for k in range(1, len(path)):
                if path[:k] not in nodes:
                    nodes[path[:k]] = len(nodes)
                    self.steps.append((nodes[path[:k - 1]], path[k - 1], f"_{path[k - 1]}", len(self.steps),
                                       nodes[path[:k]]))
            self.steps.append((nodes[path[:-1]], path[-1], f"_{path[-1]}", len(self.steps), where[j]))
        self.nodes = len(nodes)

    def build(self, values: list[list], n: int, kept: _KeptColumns | None = None) -> dict:
        blocks: list[Any] = []
        for g, (kind, idx, get) in enumerate(self.groups):
            k = len(idx)
            block = None if kept is None else kept.blocks[g]
            if block is not None:
                blocks.append(list(block.copy()))
            elif kind is object:
                flat = np.fromiter(chain.from_iterable(map(get, values)), dtype=object, count=n * k)
                blocks.append(list(flat.reshape(n, k).T))
            elif kind is np.ndarray:
                rows = []
                for j in idx:
                    column = [v[j] for v in values]
                    array = np.zeros((n, *column[0].shape), dtype=column[0].dtype)
                    for i, value in enumerate(column):
                        array[i] = value
                    rows.append(array)
                blocks.append(rows)
            else:
                blocks.append(list(np.array(list(map(get, values)), dtype=kind).reshape(n, k).T))
        masks = list(np.ones((len(self.steps), n), dtype=np.bool_))
        made: list[dict] = [{} for _ in range(self.nodes)]
        for node, key, mask_key, m, what in self.steps:
            into = made[node]
            if isinstance(what, int):
                into[key] = made[what]
            else:
                into[key] = blocks[what[0]][what[1]]
            into[mask_key] = masks[m]
        return made[0]


class _KeptColumns:
    """For a :class:`_ColumnPlan`, per kind of leaf (but arrays) a (leaves, envs) block that
    holds every env's current values, set as the workers' messages come: a batch is then
    one copy per kind."""

    def __init__(self, plan: _ColumnPlan, values: list[list], n: int):
        self.blocks: list[np.ndarray | None] = []
        #: leaf number -> (its block, its row)
        self.where: dict[int, tuple[np.ndarray, int]] = {}
        for kind, idx, _ in plan.groups:
            if kind is np.ndarray:
                self.blocks.append(None)
                continue
            block = np.empty((len(idx), n), dtype=kind)
            for row, j in enumerate(idx):
                for i in range(n):
                    block[row, i] = values[i][j]
                self.where[j] = (block, row)
            self.blocks.append(block)


def _one(j: int) -> Callable[[Sequence[Any]], tuple]:
    return lambda values: (values[j],)


# -- the worker -------------------------------------------------------------------------------
class _Channel:
    """How this process and its workers talk, with one wake-up of this process and one
    semaphore release by it per batch.

    * Per worker, a command slot and a reply slot in shared memory (a message bigger than
      its slot goes through the worker's pipe instead), with a header: the command's
      length, whether it is in the pipe, the number of the batch it belongs to, the reply's
      length and whether it is in the pipe.
    * Per worker a semaphore it sleeps on. This process writes the batch's commands and
      releases worker 0's; each worker woken releases those of its two children in a binary
      tree (worker i wakes 2i+1 and 2i+2) before it runs its command, so that this process
      wakes one worker, not all of them. A worker woken for a batch with no command for it
      only passes the wake-up on.
    * A shared count of replies and the count awaited, and one semaphore that the worker
      whose reply completes the count releases: this process sleeps once per batch.

    Messages are bytes: a command or reply code, then a pickled payload where there is one."""

    def __init__(self, ctx: Any, n: int, command_size: int = COMMAND_SLOT, reply_size: int = REPLY_SLOT):
        self.n, self.command_size, self.reply_size = n, command_size, reply_size
        self.go = [ctx.Semaphore(0) for _ in range(n)]
        self.lock = ctx.Lock()
        self.all_in = ctx.Semaphore(0)
        # Replies produced, replies consumed, replies awaited, whether this process sleeps on
        # all_in; then a ring of the workers' numbers in the order their replies came.
        self.counts = ctx.RawArray("i", 4 + n)
        self.headers = ctx.RawArray("q", _HEADER * n)
        self.slots = ctx.RawArray("B", n * (command_size + reply_size))
        self.batch = 0  # in this process: the number of the last batch sent
        self._relaying = False  # in this process: whether every idle worker passes wake-ups on
        self._views: tuple[memoryview, memoryview, memoryview] | None = None

    def __getstate__(self) -> dict:
        return {**self.__dict__, "_views": None}

    @property
    def views(self) -> tuple[memoryview, memoryview, memoryview]:
        """The slots' bytes, the headers' and the counts' integers as memoryviews (cheaper
        to index than the ctypes arrays)."""
        if self._views is None:
            self._views = (memoryview(self.slots).cast("B"), memoryview(self.headers).cast("B").cast("q"),
                           memoryview(self.counts).cast("B").cast("i"))
        return self._views

    def _put(self, at: int, header: int, message: bytes, size: int, conn: Any) -> None:
        memory, headers, _ = self.views
        length = len(message)
        headers[header] = length
        if length <= size:
            headers[header + 1] = 0
            memory[at:at + length] = message
        else:
            headers[header + 1] = 1
            conn.send_bytes(message)

    def _get(self, at: int, header: int, conn: Any) -> bytes:
        memory, headers, _ = self.views
        if headers[header + 1]:
            return conn.recv_bytes()
        return memory[at:at + headers[header]].tobytes()

    # In this process.
    def send(self, messages: dict[int, bytes], conns: Sequence[Any], relay: bool = True) -> None:
        """Give each listed worker its command and wake them: ``relay`` (every worker idle)
        by waking worker 0, whose wake-up passes down the tree; else each one directly."""
        headers = self.views[1]
        self.batch += 1
        stride = self.command_size + self.reply_size
        if relay and not self._relaying:
            for i in range(self.n):
                headers[_HEADER * i + 5] = 1
        self._relaying = relay
        for i, message in messages.items():
            self._put(i * stride, _HEADER * i, message, self.command_size, conns[i])
            headers[_HEADER * i + 2] = self.batch
            if not relay:
                headers[_HEADER * i + 5] = 0
        if relay:
            self.go[0].release()
        else:
            for i in messages:
                self.go[i].release()

    def wait(self, need: int, timeout: float) -> list[int] | None:
        """The workers whose replies came, in that order, once ``need`` have come that this
        process has not taken; None if they have not within ``timeout`` seconds."""
        counts = self.views[2]
        deadline = time.monotonic() + timeout
        while True:
            with self.lock:
                ready = counts[0] - counts[1] >= need
                if not ready:
                    counts[2], counts[3] = need, 1
            if ready:
                return self.pop(need)
            if not self.all_in.acquire(timeout=max(0.0, deadline - time.monotonic())):
                return None

    def pop(self, need: int) -> list[int]:
        """The next ``need`` replies' workers (they have come)."""
        counts, n = self.views[2], self.n
        first = counts[1]
        ids = [counts[4 + (first + k) % n] for k in range(need)]
        counts[1] = first + need
        return ids

    def wake(self, i: int) -> None:
        """Wake worker ``i`` again (its parent in the tree died before passing the wake-up on)."""
        self.go[i].release()

    def replies_in(self) -> int:
        """Replies that have come and were not taken."""
        counts = self.views[2]
        return counts[0] - counts[1]

    # In a worker.
    def take(self, i: int, conn: Any, lifeline: Any, last: list[int],
             idle: Callable[[], bool] | None = None) -> bytes | None:
        """The next command for worker ``i`` (``last``: the number of the batch of its
        previous one), or None once this process's parent is gone (``lifeline``, the read
        end of a pipe nobody writes to, then reads as closed). While none has come, ``idle``
        is called (it does a short piece of work and says whether it did)."""
        headers = self.views[1]
        children = [c for c in (2 * i + 1, 2 * i + 2) if c < self.n]
        while True:
            if not self.go[i].acquire(False):
                if idle is not None and idle():
                    continue
                if not self.go[i].acquire(timeout=POLL_SECONDS):
                    if lifeline.poll(0):
                        return None
                    continue
            if headers[_HEADER * i + 5]:
                for child in children:
                    self.go[child].release()
            batch = headers[_HEADER * i + 2]
            if batch != last[0]:
                last[0] = batch
                return self._get(i * (self.command_size + self.reply_size), _HEADER * i, conn)

    def answer(self, i: int, message: bytes, conn: Any) -> None:
        self._put(i * (self.command_size + self.reply_size) + self.command_size, _HEADER * i + 3, message,
                  self.reply_size, conn)
        counts = self.views[2]
        with self.lock:
            counts[4 + counts[0] % self.n] = i
            counts[0] += 1
            done = counts[3] and counts[0] - counts[1] >= counts[2]
            if done:
                counts[3] = 0
        if done:
            self.all_in.release()


#: Integers of a worker's header: command length, command in the pipe, command's batch,
#: reply length, reply in the pipe, whether the worker passes its wake-up on.
_HEADER = 6


def _worker(index: int, env_id: str, kwargs: dict, conn: multiprocessing.connection.Connection, buffer: Any,
            layout: _Layout, channel: _Channel, lifeline: multiprocessing.connection.Connection) -> None:
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # this process's parent handles Ctrl-C

    def reply(message: bytes) -> None:
        channel.answer(index, message, conn)

    try:
        env = gym.make(env_id, **kwargs)
    except Exception as err:
        reply(bytes([_ERROR]) + pickle.dumps(_failure(err, "making the env"), _PICKLE))
        conn.close()
        return
    reply(bytes([_VALUE]) + pickle.dumps(None, _PICKLE))  # ready
    # An env that sets up its next episode ahead (helpers: Episode.stage) does it here, in
    # the time the worker waits for the other workers and the next step, not after its steps.
    idle = getattr(env.unwrapped, "stage_ahead", None)
    if idle is not None:
        env.unwrapped.stage_after_step = False  # type: ignore[attr-defined]
    last_batch = [0]
    views = _Views(layout, buffer)
    obs_leaves = list(zip(layout.obs, views.obs))
    info = _InfoSender()
    autoreset = False

    texts_written: dict[int, str] = {}
    text_versions = views.text_versions[index]

    def write(obs: Any, reward: float, terminated: bool, truncated: bool) -> None:
        for k, (leaf, view) in enumerate(obs_leaves):
            value = _get(obs, leaf.path)
            if leaf.kind == "text":
                if texts_written.get(k) == value:
                    continue
                if len(value) > leaf.max_length:
                    raise ValueError(f"an observation text of {len(value)} characters does not fit its space's "
                                     f"max_length={leaf.max_length}: {value[:40]!r}...")
                texts_written[k] = value
                text_versions[layout.texts.index(k)] += 1
            view[index] = value
        views.rewards[index], views.terminations[index], views.truncations[index] = reward, terminated, truncated

    try:
        while True:
            try:
                message = channel.take(index, conn, lifeline, last_batch, idle)
            except (EOFError, OSError):  # this process's parent is gone
                break
            if message is None:
                break
            command, payload = message[:1], message[1:]
            try:
                if command in (_STEP, _STEP_TEXT):
                    if autoreset:
                        obs, step_info = env.reset()
                        reward: Any = 0.0
                        terminated, truncated = False, False
                    else:
                        action = payload.decode() if command == _STEP_TEXT else pickle.loads(payload)
                        obs, reward, terminated, truncated, step_info = env.step(action)
                    autoreset = bool(terminated or truncated)
                    write(obs, reward, terminated, truncated)
                    reply(_DONE_BYTE + info.message(step_info))
                elif command == _RESET:
                    seed, options = pickle.loads(payload)
                    obs, reset_info = env.reset(seed=seed, options=options)
                    autoreset = False
                    write(obs, 0.0, False, False)
                    reply(_DONE_BYTE + info.message(reset_info))
                elif command == _CALL:
                    name, args, call_kwargs = pickle.loads(payload)
                    attr = env.get_wrapper_attr(name)
                    value = attr(*args, **call_kwargs) if callable(attr) else attr
                    reply(bytes([_VALUE]) + pickle.dumps(value, _PICKLE))
                elif command == _SETATTR:
                    name, value = pickle.loads(payload)
                    env.set_wrapper_attr(name, value)
                    reply(bytes([_VALUE]) + pickle.dumps(None, _PICKLE))
                elif command == _CLOSE:
                    break
                else:
                    raise ValueError(f"unknown command {command!r}")
            except Exception as err:
                reply(bytes([_ERROR]) + pickle.dumps(_failure(err, _COMMANDS.get(command, "?")), _PICKLE))
    finally:
        with contextlib.suppress(Exception):
            env.close()
        conn.close()


_COMMANDS = {_STEP: "step", _STEP_TEXT: "step", _RESET: "reset", _CALL: "call", _SETATTR: "set_attr", _CLOSE: "close"}


def _step_message(action: Any) -> bytes:
    if type(action) is str:
        try:
            return _STEP_TEXT + action.encode()
        except UnicodeEncodeError:  # lone surrogates: pickled as they are
            pass
    return _STEP + pickle.dumps(action, _PICKLE)


def _failure(err: BaseException, doing: str) -> tuple[str, str, str, str]:
    return type(err).__name__, str(err), "".join(traceback.format_exception(err)), doing


# -- the vector env ---------------------------------------------------------------------------
def env_id_of(kwargs: dict) -> str:
    """The registered id whose own keyword arguments (task and layout) ``kwargs`` holds
    (``make_vec`` hands a vector entry point the id's keyword arguments merged with the
    caller's, not the id); failing that, the first id of the task (a layout given by the
    caller), whose spec is the same but for its keyword arguments."""
    task = kwargs.get("task")
    ids = [(env_id, spec.kwargs) for env_id, spec in gym.registry.items()
           if spec.vector_entry_point == VECTOR_ENTRY_POINT and spec.kwargs.get("task") == task]
    for env_id, own in ids:
        if all(kwargs.get(key) == value for key, value in own.items()):
            return env_id
    if ids:
        return ids[0][0]
    raise ValueError(f"no registered id has task={task!r} and this vector entry point")


def make_vector(num_envs: int = 1, **kwargs: Any) -> SharedMemoryVectorEnv:
    """The vector entry point of every registered id (``gym.make_vec(id, num_envs,
    vectorization_mode="vector_entry_point", **kwargs)``): ``kwargs`` are the env's,
    ``max_episode_steps`` among them."""
    return SharedMemoryVectorEnv(env_id_of(kwargs), num_envs, **kwargs)


class SharedMemoryVectorEnv(VectorEnv):
    """``num_envs`` copies of ``gym.make(env_id, **kwargs)``, each in a worker process, with
    the observations of all of them in one shared batch (see the module docstring).

    ``copy`` (default True): return copies of the batch's arrays, as ``SyncVectorEnv``
    does; False returns views of the shared memory, which the next ``step`` overwrites.
    ``lazy_infos`` (default False): return the infos as a :class:`LazyInfos`, built the
    first time they are read (the same contents; a training loop that does not read them
    saves building them). ``batch_size`` (default ``num_envs``): how many envs
    :meth:`recv` returns (EnvPool-style stepping: :meth:`async_reset`, then :meth:`recv`
    and :meth:`send` in turn, so that an env that resets holds no batch back; ``step`` and
    ``reset`` wait for every env as usual). All three are the vector env's own keywords,
    also through ``gym.make_vec(..., copy=False, lazy_infos=True, batch_size=4)``; every
    other keyword is the env's.
    """

    metadata = {"autoreset_mode": AutoresetMode.NEXT_STEP}

    def __init__(self, env_id: str, num_envs: int, *, copy: bool = True, lazy_infos: bool = False,
                 batch_size: int | None = None, **kwargs: Any):
        if not isinstance(num_envs, int) or isinstance(num_envs, bool) or num_envs < 1:
            raise ValueError(f"num_envs must be a positive integer, got {num_envs!r}")
        if batch_size is not None and not 1 <= batch_size <= num_envs:
            raise ValueError(f"batch_size must be between 1 and num_envs={num_envs}, got {batch_size!r}")
        #: How many envs :meth:`recv` returns at a time.
        self.batch_size = num_envs if batch_size is None else int(batch_size)
        self._in_flight: set[int] = set()
        self.num_envs, self.copy, self.lazy_infos, self.closed = num_envs, copy, lazy_infos, False
        self._processes: list[Any] = []
        self._lifeline: multiprocessing.connection.Connection | None = None
        self._conns: list[multiprocessing.connection.Connection] = []
        self._broken: str | None = None
        self._dead: set[int] = set()
        # The spaces, metadata and render mode of one env, made here (no house is built
        # before the first reset) without episode helpers.
        dummy = gym.make(env_id, **{**kwargs, "helpers": 0} if "helpers" in kwargs else kwargs)
        try:
            self.single_observation_space = dummy.observation_space
            self.single_action_space = dummy.action_space
            self.render_mode = dummy.render_mode
            self.metadata = {**dummy.metadata, "autoreset_mode": AutoresetMode.NEXT_STEP}
        finally:
            dummy.close()
        self.observation_space = batch_space(self.single_observation_space, num_envs)
        self.action_space = batch_space(self.single_action_space, num_envs)
        self.env_id, self.env_kwargs = env_id, dict(kwargs)

        self._layout = _Layout(self.single_observation_space, num_envs)
        ctx: Any = multiprocessing.get_context(CONTEXT)
        with contextlib.suppress(Exception):  # the workers import this module once, in the server
            ctx.set_forkserver_preload([__name__])
        self._buffer = ctx.RawArray("B", self._layout.size)
        self._views = _Views(self._layout, self._buffer)
        self._obs = _ObsReader(self._layout, self._views, copy)
        self._infos = _InfoBook(num_envs, self._add_info)
        self._channel = _Channel(ctx, num_envs)
        # The workers' sign that this process is gone (even unreaped): its end closes.
        lifeline, self._lifeline = ctx.Pipe(duplex=False)
        try:
            for i in range(num_envs):
                parent, child = ctx.Pipe()  # for messages too big for their slots
                process = ctx.Process(target=_worker, name=f"SharedMemoryVectorEnv-{i}", daemon=True,
                                      args=(i, env_id, kwargs, child, self._buffer, self._layout, self._channel,
                                            lifeline))
                process.start()
                child.close()
                self._processes.append(process)
                self._conns.append(parent)
            self._receive(range(num_envs), "making its env")
        except BaseException:
            self.close(terminate=True)
            raise
        finally:
            lifeline.close()

    # -- Gymnasium API ------------------------------------------------------------------------
    def reset(self, *, seed: int | Sequence[int | None] | None = None,
              options: dict[str, Any] | None = None) -> tuple[Any, dict[str, Any]]:
        self._check_usable(idle=True)
        seeds = self._seeds(seed)
        envs: list[int] | None = None
        if options is not None and "reset_mask" in options:
            mask = options.pop("reset_mask")
            if not isinstance(mask, np.ndarray):
                raise TypeError(f"`options['reset_mask']` must be a numpy array, got {type(mask)}")
            if mask.shape != (self.num_envs,):
                raise ValueError(f"`options['reset_mask']` must have shape `({self.num_envs},)`, got {mask.shape}")
            if mask.dtype != np.bool_:
                raise TypeError(f"`options['reset_mask']` must have `dtype=np.bool_`, got {mask.dtype}")
            if not np.any(mask):
                raise ValueError("`options['reset_mask']` must contain a boolean array with at least one True "
                                 f"value, got reset_mask={mask}")
            envs = [int(i) for i in np.flatnonzero(mask)]
        targets = range(self.num_envs) if envs is None else envs
        self._command({i: _RESET + pickle.dumps((seeds[i], options), _PICKLE) for i in targets}, "reset")
        obs = self._obs.read()
        return obs, self._infos.lazy(envs) if self.lazy_infos else self._infos.batch(envs)

    def step(self, actions: Any) -> tuple[Any, np.ndarray, np.ndarray, np.ndarray, dict[str, Any]]:
        self._check_usable(idle=True)
        messages = [_step_message(action) for action in iterate(self.action_space, actions)]
        if len(messages) != self.num_envs:
            raise ValueError(f"{len(messages)} actions for {self.num_envs} envs")
        self._command(dict(enumerate(messages)), "step")
        views = self._views
        obs = self._obs.read()
        return (obs, views.rewards.copy(), views.terminations.copy(), views.truncations.copy(),
                self._infos.lazy() if self.lazy_infos else self._infos.batch())

    # -- EnvPool-style asynchronous stepping ----------------------------------------------------
    def async_reset(self, *, seed: int | Sequence[int | None] | None = None,
                    options: dict[str, Any] | None = None) -> None:
        """Reset every env (``seed`` as :meth:`reset` takes it) without waiting: the reset
        observations come from :meth:`recv`, ``batch_size`` at a time."""
        self._check_usable()
        seeds = self._seeds(seed)
        self._send_async({i: _RESET + pickle.dumps((seeds[i], options), _PICKLE) for i in range(self.num_envs)})

    def send(self, actions: Any, env_ids: Sequence[int] | np.ndarray | None = None) -> None:
        """Step the envs ``env_ids`` (all when None; each must have been received since it
        was last sent) with ``actions`` (one per env id, batched as for :meth:`step`)
        without waiting. With the next-step autoreset, the action sent to an env whose
        episode ended resets it."""
        self._check_usable()
        ids = list(range(self.num_envs)) if env_ids is None else [int(i) for i in np.asarray(env_ids).ravel()]
        messages = [_step_message(action) for action in iterate(self.action_space, actions)]
        if len(messages) != len(ids):
            raise ValueError(f"{len(messages)} actions for {len(ids)} env ids")
        self._send_async(dict(zip(ids, messages, strict=True)))

    def recv(self) -> tuple[Any, np.ndarray, np.ndarray, np.ndarray, dict[str, Any]]:
        """The first ``batch_size`` envs to finish what was sent to them (fewer if fewer are
        out): observations, rewards, terminations, truncations and infos batched over them
        in the order they finished, their indices in ``infos["env_id"]``. An env that resets
        does not hold the others back."""
        self._check_usable()
        need = min(self.batch_size, len(self._in_flight))
        if need == 0:
            raise RuntimeError("recv() with nothing sent: call send() or async_reset() first")
        channel = self._channel
        while (ids := channel.wait(need, POLL_SECONDS)) is None:
            dead = [i for i in self._in_flight if not self._processes[i].is_alive()]
            if dead:
                self._broken = self._died(dead[0], "stepping")
                raise WorkerError(self._broken, dead[0])
        self._in_flight.difference_update(ids)
        self._read(ids, "step")
        rows = np.array(ids)
        views = self._views
        infos = self._infos.compact(ids)
        infos["env_id"] = rows
        return (self._obs.read_rows(rows), views.rewards[rows], views.terminations[rows], views.truncations[rows],
                infos)

    def _send_async(self, messages: dict[int, bytes]) -> None:
        busy = sorted(self._in_flight.intersection(messages))
        if busy:
            raise ValueError(f"envs {busy} were sent work that recv() has not returned yet")
        # Every worker idle: the wake-up may pass down the tree; else each is woken itself.
        self._channel.send(messages, self._conns, relay=not self._in_flight)
        self._in_flight.update(messages)

    def _seeds(self, seed: int | Sequence[int | None] | None) -> list[int | None]:
        if seed is None:
            seeds: list[int | None] = [None] * self.num_envs
        elif isinstance(seed, int):
            seeds = [seed + i for i in range(self.num_envs)]
        else:
            seeds = list(seed)
        if len(seeds) != self.num_envs:
            raise ValueError(f"If seeds are passed as a list the length must match num_envs={self.num_envs} "
                             f"but got length={len(seeds)}.")
        return seeds

    def call(self, name: str, *args: Any, **kwargs: Any) -> tuple[Any, ...]:
        """``name`` of each env (``env.get_wrapper_attr``), called with the arguments when callable."""
        self._check_usable(idle=True)
        if name in ("reset", "step", "close", "set_attr"):
            raise ValueError(f"Trying to call function `{name}` with `call`, use `{name}` directly instead.")
        message = _CALL + pickle.dumps((name, args, kwargs), _PICKLE)
        return tuple(self._command(dict.fromkeys(range(self.num_envs), message), f"call {name!r}"))

    def get_attr(self, name: str) -> tuple[Any, ...]:
        return self.call(name)

    def set_attr(self, name: str, values: list[Any] | tuple[Any, ...] | Any) -> None:
        self._check_usable(idle=True)
        if not isinstance(values, list | tuple):
            values = [values] * self.num_envs
        if len(values) != self.num_envs:
            raise ValueError(f"Values must be a list or tuple with length equal to the number of environments. "
                             f"Got `{len(values)}` values for {self.num_envs} environments.")
        self._command({i: _SETATTR + pickle.dumps((name, value), _PICKLE) for i, value in enumerate(values)},
                      f"set_attr {name!r}")

    def render(self) -> tuple[Any, ...] | None:
        return self.call("render")

    def close_extras(self, timeout: float | None = CLOSE_TIMEOUT, terminate: bool = False) -> None:
        """End the workers (each closes its env; ``terminate``: at once) and free the shared batch."""
        channel = getattr(self, "_channel", None)
        if not terminate and channel is not None:
            with contextlib.suppress(OSError):
                channel.send(dict.fromkeys(range(len(self._processes)), _CLOSE), self._conns, relay=False)
            for i, process in enumerate(self._processes):  # a dead worker passes no wake-up on
                if not process.is_alive():
                    for child in (2 * i + 1, 2 * i + 2):
                        if child < len(self._processes):
                            channel.wake(child)
        deadline = time.monotonic() + (timeout if timeout is not None else 1e9)
        for process in self._processes:
            process.join(0 if terminate else max(0.0, deadline - time.monotonic()))
            if process.is_alive():
                process.terminate()
                process.join(1.0)
            if process.is_alive():
                process.kill()
                process.join()
        for conn in self._conns:
            conn.close()
        if self._lifeline is not None:
            self._lifeline.close()
        self._conns, self._processes = [], []
        self._views = None  # type: ignore[assignment]
        self._buffer = self._channel = None  # type: ignore[assignment]

    def __del__(self) -> None:
        if not getattr(self, "closed", True):
            with contextlib.suppress(Exception):
                self.close(terminate=True)

    # -- talking to the workers -----------------------------------------------------------------
    def _check_usable(self, idle: bool = False) -> None:
        if self.closed:
            raise RuntimeError("this SharedMemoryVectorEnv is closed")
        if self._broken is not None:
            raise RuntimeError(f"this SharedMemoryVectorEnv cannot go on after a worker's error: {self._broken}")
        if idle and self._in_flight:
            raise RuntimeError(f"envs {sorted(self._in_flight)} were sent work with send() or async_reset(): "
                               "recv() it before step(), reset(), call() or set_attr()")

    def _died(self, i: int, doing: str, err: BaseException | None = None) -> str:
        process = self._processes[i]
        process.join(1.0)
        code = process.exitcode
        return (f"worker {i} (pid {process.pid}) of {self.env_id} died while {doing} "
                f"({'still running' if code is None else f'exit code {code}'}"
                f"{'' if err is None else '; ' + type(err).__name__})")

    def _command(self, messages: dict[int, bytes], doing: str) -> list[Any]:
        """Send each worker its message and wait for all replies (values of calls, in order)."""
        try:
            self._channel.send(messages, self._conns)
        except OSError as err:  # a pipe of a worker that died
            i = next((i for i in messages if not self._processes[i].is_alive()), next(iter(messages)))
            self._broken = self._died(i, f"receiving a command to {doing}", err)
            raise WorkerError(self._broken, i) from err
        return self._receive(messages, doing)

    def _wait_all_in(self, envs: Iterable[int]) -> list[int]:
        """Sleep until the replies of ``envs`` have come (woken once, by the worker whose reply
        completes them); the workers, in the order their replies came. A worker that died
        never replies: then wait for the live ones' replies."""
        envs = list(envs)
        channel = self._channel
        while (ids := channel.wait(len(envs), POLL_SECONDS)) is None:
            dead = [i for i in range(self.num_envs) if not self._processes[i].is_alive()]
            if dead:
                # The dead do not pass the wake-up on: wake the others (one woken twice
                # sees no new command the second time), and wait for their replies.
                for i in range(self.num_envs):
                    if i not in dead:
                        channel.wake(i)
                while channel.replies_in() < len(set(envs) - set(dead)):
                    time.sleep(0.01)
                    dead = [i for i in range(self.num_envs) if not self._processes[i].is_alive()]
                self._dead = set(dead)
                return channel.pop(channel.replies_in())
        return ids

    def _receive(self, envs: Iterable[int], doing: str) -> list[Any]:
        """Every listed worker's reply (an info message or a value); raises the first error
        once all have answered, so that the pipes stay in step."""
        self._wait_all_in(envs)
        return self._read(envs, doing)

    def _read(self, envs: Iterable[int], doing: str) -> list[Any]:
        """The replies of ``envs``, which have come."""
        values: list[Any] = []
        errors: list[tuple[int, str]] = []
        infos = self._infos
        channel, conns, dead = self._channel, self._conns, self._dead
        memory, headers, _ = channel.views
        stride, first = channel.command_size + channel.reply_size, channel.command_size
        for i in envs:
            if i in dead:
                errors.append((i, self._died(i, doing)))
                continue
            header = _HEADER * i + 3
            if headers[header + 1]:  # in the pipe
                try:
                    reply = conns[i].recv_bytes()
                except (EOFError, OSError) as err:
                    errors.append((i, self._died(i, doing, err)))
                    continue
            else:
                at = i * stride + first
                reply = memory[at:at + headers[header]].tobytes()
            kind = reply[0]
            if kind == _DONE:
                if len(reply) > 1:
                    infos.update(i, memoryview(reply)[1:])
            elif kind == _VALUE:
                values.append(pickle.loads(memoryview(reply)[1:]))
            else:
                name, text, trace, during = pickle.loads(memoryview(reply)[1:])
                errors.append((i, f"worker {i} (pid {self._processes[i].pid}) of {self.env_id} raised "
                                  f"{name} in {during}: {text}\n\nThe worker's traceback:\n{trace}"))
        if errors:
            i, message = errors[0]
            self._broken = message.split("\n", 1)[0]
            raise WorkerError(message, i)
        return values

    def worker_pids(self) -> list[int]:
        """The workers' process ids (for tests and monitoring)."""
        return [p.pid for p in self._processes if p.pid is not None]

    def __repr__(self) -> str:
        return f"SharedMemoryVectorEnv({self.env_id!r}, num_envs={self.num_envs})"


def worker_pids(envs: SharedMemoryVectorEnv) -> list[int]:
    """The workers' process ids (for tests and monitoring)."""
    return envs.worker_pids()


if os.name != "posix":  # pragma: no cover
    raise ImportError("SharedMemoryVectorEnv needs a POSIX system (forkserver, shared memory)")

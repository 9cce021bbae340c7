"""Env steps/s in the training loop, as ratios against Miniworld measured in the same run.

    python benchmarks/throughput.py [--steps 1000] [--rounds 5] [--only oneroom,tworoom,...]
                                    [--collect-episodes 100] [--house-count 32] [--helpers 1] [--json OUT]
    python benchmarks/throughput.py --scaling [--helpers 1] [--rounds 3]
    python benchmarks/throughput.py --profile-resets 50 [--profile-id Legent/ComeHere-TwoRoom-v0]

``benchmarks/step.py`` keeps one house and measures stepping alone; training code resets
every ~20 steps (episodes end at 25 actions or on success), so here every row is the loop a
training run goes through: ``gym.make(id, width=96, height=96)`` (the registered 25-action
cap), seeded random actions, ``env.reset()`` whenever ``terminated or truncated``, 96x96
observations, one core. Rows (``--only`` names):

* ``oneroom``, ``tworoom``: ``Legent/ComeHere-{OneRoom,TwoRoom}-v0``, a new house every episode;
* ``oneroom-eph8``, ``tworoom-eph8``: the same with ``episodes_per_house=8``;
* ``oneroom-houses``, ``tworoom-houses``: the same with ``houses=DIR``, a folder of
  ``--house-count`` scenes written by ``legent-gym generate --count N --out-dir DIR`` (before
  timing). Where the env does not know the keyword (TypeError) or the CLI has no
  ``--count``, the row says "n/a (not supported by this version)". ``*-houses-kept``: the
  same with ``houses_kept=N`` (every house of the folder kept once built); ``*-houses-cache``:
  the same with ``house_cache=DIR2`` (``legent_gym/envs/house_store.py``), every house of the
  folder built and stored there before timing, so that each is loaded, not built;
* ``mw-oneroom``, ``mw-fourrooms``: Miniworld's ``MiniWorld-OneRoom-v0`` and
  ``MiniWorld-FourRooms-v0`` with ``obs_width=96, obs_height=96`` and Miniworld's own episode
  caps (180 and 250 steps), random discrete actions, the same loop. ``mw-fourrooms`` is the
  reference of the ratios and is always measured;
* ``oneroom-helpers``, ``tworoom-helpers``, ``tworoom-eph8-helpers``,
  ``tworoom-houses-helpers``: those rows with ``helpers=H`` (``--helpers``; episodes
  prepared in helper processes, ``legent_gym/envs/factory.py``), not pinned: the helpers
  use the other cores;
* ``tworoom-free``, ``tworoom-eph8-free``, ``tworoom-houses-cache-free``, ``oneroom-eph8-free``:
  those rows in a process left on every core, as ``gym.make`` runs in a user's training
  process (the other single-env rows pin their process to one core, as a vector env pins
  its workers): llvmpipe draws in the rendering thread, as ``legent_gym.world.render``
  has it for "fast" renderers. ``*-free-threads``: the same with ``LP_NUM_THREADS`` set to
  the number of cores, Mesa's own default, so that llvmpipe splits each frame between its
  rasteriser threads (``docs/performance.md``, "Rendering threads");
* ``vec1``, ``vec2``, ``vec8`` (any ``vecN``, and ``vecN-eph8``, ``vecN-helpers``): ``gym.make_vec("Legent/ComeHere-OneRoom-v0", num_envs=N,
  vectorization_mode="async")`` (forkserver workers, same-step autoreset), steps summed over
  the envs. N=1 runs pinned to one core (the parent and its env process), N=2 unpinned;
  reported as the ratio N=2 / N=1. With N=2 each env process pins itself to a core of its
  own and draws in its own thread (``legent_gym/envs/vector.py``) and makes its next house
  ahead in the time it waits for the other (``prepare_ahead``, on in pinned workers; the
  pinned N=1 process has one core and does not). ``vec1-eph8``, ``vec2-eph8``: the same
  with ``episodes_per_house=8``; ``vec2-inline``: N=2 with ``prepare_ahead=False``;
* ``svec1``, ``svec2``, ``svec8`` (any ``svecN``, and ``-eph8``, ``-helpers``): the same
  with ``vectorization_mode="vector_entry_point"`` (``legent_gym/envs/shared_vector.py``:
  shared-memory batch, next-step autoreset, whose reset steps are not counted as steps);
  ``svecN-lazy``: with ``lazy_infos=True`` (infos built only when read: the loop does not
  read them); ``svecN-pool``: its ``send``/``recv``, ``batch_size=N/2``, the next actions
  sent to the envs each ``recv`` returns;
* ``collect``: ``legent-gym collect Legent/ComeHere-OneRoom-v0 --episodes 100 --out DIR
  --workers 1`` (its Python function, one core, default formats): successful expert
  trajectories per second, the whole call timed (a fresh DIR each round).
  ``collect-eph8``: the same with ``--env-kwargs '{"episodes_per_house": 8}'``.
  ``collectN`` (any N > 1): ``--workers N``, ``--collect-episodes`` times N episodes, not
  pinned, reported with its ratio to ``collect`` (``--scaling`` runs N = 1, 2, 4, ... cores).

Legent's actions are ``benchmarks/step.py``'s random move/turn/tilt text actions, one in ten
with an interaction appended (``interact()``, ``grab()``, ``put()``, ``open()``,
``close()``); Miniworld's are uniform over its discrete actions. Both come from seeded numpy
generators (not ``env.action_space.sample()``), so runs repeat.

Each row lives in a worker process of its own (set up before timing: env made, first reset,
a few warm-up steps), and the rows are measured in alternating blocks: ``--rounds`` rounds,
each giving every row ``--steps`` steps (one collection for ``collect``), the order rotated
every round, so that other load on the shared machine weighs on all rows alike. Only one
worker runs at a time; pinned workers share one core. ``steps/s`` is the median over
rounds and includes the resets: it is what a training loop gets. ``x MW`` columns are the
medians of the per-round ratios to the Miniworld rows of the same round; ``cpu x MW
FourRooms`` is that ratio in process CPU time (the one-process rows; steadier under other
load). ``reset ms`` is the median time inside ``reset`` calls (autoresets included; resets
inside the vector env's processes are not seen), ``reset ms (p99)`` their 99th
percentile, ``reset ms (mean)`` their mean (with ``episodes_per_house`` the median is an
in-house reset, the mean counts the new houses too): the time the stepping process sees.
``steps per CPU-s, all processes`` counts the CPU time (user + system, ``psutil``) of the
row's worker and every process under it (helpers, vector env workers, their forkserver)
over the round, and ``(x MW FourRooms)`` is its ratio to Miniworld's in the same round:
what a row costs the machine, whatever runs where. ``parent CPU us/step`` (vector rows) is
the process CPU time of the process that holds the vector env per env-step (receiving and
decoding observations).

``rawN`` (the reference of scaling): N processes, each drawing a OneRoom house with MuJoCo's
own ``mujoco.Renderer`` and stepping its physics (``mj_step``) from random agent poses, with
nothing of ours in between; each process draws ``--steps`` frames a round, frames/s summed
over the processes (N=1 pinned to one core).
``rawN / raw1`` is what the machine gives N copies of a plain MuJoCo loop: the ceiling of
any N-worker ratio on it (shared caches, memory bandwidth, SMT siblings, the GL driver).

``--scaling`` measures the async vector env and the vector entry point at N = 1, 2, 4, ...
up to the cores the process may use (and that count), with a new house every episode,
``episodes_per_house=8`` and (with ``--helpers`` > 0) helpers, and prints each N's steps/s and its ratio to N=1,
and ``collect`` against ``collectN`` at the same N: the run for a many-core machine.

Headless Miniworld: Miniworld draws with pyglet 1.5 (OpenGL). With no display, a worker sets
``PYOPENGL_PLATFORM=egl`` and ``pyglet.options["headless"] = True`` before pyglet or
miniworld is imported; pyglet then opens an EGL pbuffer context on Mesa's software device
(llvmpipe), as MuJoCo does for legent. The Debian libraries this uses (all in the project's
machine image already, nothing to install): libegl1, libegl-mesa0, libgl1, libgl1-mesa-dri,
libglu1-mesa and libgbm1. Miniworld itself is the ``bench`` extra: ``pip install -e ".[bench]"``.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import math
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
import traceback
from pathlib import Path

HERE = Path(__file__).resolve().parent
LEGENT_IDS = {"OneRoom": "Legent/ComeHere-OneRoom-v0", "TwoRoom": "Legent/ComeHere-TwoRoom-v0"}
INTERACTIONS = ("interact()", "grab()", "put()", "open()", "close()")
REFERENCE = "mw-fourrooms"
UNSUPPORTED = "n/a (not supported by this version)"


def _configs() -> dict[str, dict]:
    rows: dict[str, dict] = {}
    for layout, env_id in LEGENT_IDS.items():
        low = layout.lower()
        rows[low] = {"kind": "legent", "label": f"{env_id}", "env_id": env_id, "kwargs": {}}
        rows[f"{low}-eph8"] = {"kind": "legent", "label": f"{env_id}, episodes_per_house=8", "env_id": env_id,
                               "kwargs": {"episodes_per_house": 8}}
        rows[f"{low}-houses"] = {"kind": "legent", "label": f"{env_id}, houses=DIR", "env_id": env_id,
                                 "kwargs": {"houses": None}, "layout": layout}
        rows[f"{low}-houses-kept"] = {"kind": "legent", "label": f"{env_id}, houses=DIR, houses_kept=N",
                                      "env_id": env_id, "kwargs": {"houses": None, "houses_kept": None},
                                      "layout": layout}
        rows[f"{low}-houses-cache"] = {"kind": "legent", "label": f"{env_id}, houses=DIR, house_cache=CACHE",
                                       "env_id": env_id, "kwargs": {"houses": None, "house_cache": None},
                                       "layout": layout}
    rows["mw-oneroom"] = {"kind": "miniworld", "label": "MiniWorld-OneRoom-v0", "env_id": "MiniWorld-OneRoom-v0"}
    rows["mw-fourrooms"] = {"kind": "miniworld", "label": "MiniWorld-FourRooms-v0",
                            "env_id": "MiniWorld-FourRooms-v0"}
    for base in ("tworoom", "tworoom-eph8", "tworoom-houses", "oneroom"):
        # The same with episode helpers (legent_gym/envs/factory.py), unpinned: the helper
        # processes take the other cores.
        row = dict(rows[base], kwargs={**rows[base]["kwargs"], "helpers": "HELPERS"}, pinned=False)
        row["label"] += ", helpers=H"
        rows[f"{base}-helpers"] = row
    for base in ("tworoom", "tworoom-eph8", "tworoom-houses-cache", "oneroom-eph8"):
        rows[f"{base}-free"] = dict(rows[base], pinned=False, label=rows[base]["label"] + ", unpinned")
        rows[f"{base}-free-threads"] = dict(rows[base], pinned=False, env={"LP_NUM_THREADS": str(os.cpu_count())},
                                            label=rows[base]["label"] + ", unpinned, llvmpipe's threads")
    for n in (1, 2, 8):
        rows.update({name: vector_config(name) for name in (f"vec{n}", f"vec{n}-eph8", f"svec{n}")})
    rows["svec8-lazy"] = vector_config("svec8-lazy")  # other svec rows (-eph8, -pool) by name
    rows["vec2-inline"] = {"kind": "vector", "env_id": LEGENT_IDS["OneRoom"], "num_envs": 2,
                           "label": "make_vec ComeHere-OneRoom, async, N=2, prepare_ahead=False",
                           "kwargs": {"prepare_ahead": False}}
    rows["collect"] = {"kind": "collect", "label": "legent-gym collect ComeHere-OneRoom, --workers 1",
                       "env_id": LEGENT_IDS["OneRoom"], "kwargs": {}}
    rows["collect-eph8"] = {"kind": "collect", "env_id": LEGENT_IDS["OneRoom"],
                            "label": "legent-gym collect ComeHere-OneRoom, --workers 1, "
                                     "--env-kwargs '{\"episodes_per_house\": 8}'",
                            "kwargs": {"episodes_per_house": 8}}
    return rows


def vector_config(name: str) -> dict:
    """``vecN`` (a new house every episode), ``vecN-eph8`` (``episodes_per_house=8``), and
    either with ``-helpers`` (``helpers=H`` in every env); ``svec...``: the same with the
    registered vector entry point instead of the async vector env."""
    parts = name.split("-")
    n = int(parts[0].removeprefix("s")[3:])
    kwargs: dict = {}
    label = f"make_vec ComeHere-OneRoom, async, N={n}"
    if "eph8" in parts:
        kwargs["episodes_per_house"] = 8
        label += ", episodes_per_house=8"
    if "helpers" in parts:
        kwargs["helpers"] = "HELPERS"
        label += ", helpers=H"
    if name.startswith("svec"):
        label = label.replace(", async,", ", vector_entry_point,")
        if "lazy" in parts:
            kwargs["lazy_infos"] = True
            label += ", lazy_infos"
        config = {"kind": "vector", "mode": "vector_entry_point", "label": label, "env_id": LEGENT_IDS["OneRoom"],
                  "num_envs": n, "kwargs": kwargs}
        if "pool" in parts:  # send/recv, half the envs a batch
            config["batch_size"] = max(1, n // 2)
            config["label"] += f", send/recv batch_size={config['batch_size']}"
        return config
    return {"kind": "vector", "label": label, "env_id": LEGENT_IDS["OneRoom"], "num_envs": n, "kwargs": kwargs}


def collect_config(workers: int) -> dict:
    """``legent-gym collect`` with ``--workers N``, unpinned: its workers take the other cores."""
    return {"kind": "collect", "env_id": LEGENT_IDS["OneRoom"], "kwargs": {}, "workers": workers, "pinned": False,
            "label": f"legent-gym collect ComeHere-OneRoom, --workers {workers}"}


def row_config(name: str) -> dict:
    """A row's configuration (vector rows of any N: see :func:`vector_config`)."""
    if name in CONFIGS:
        return CONFIGS[name]
    if name.startswith("raw") and name[3:].isdigit() and int(name[3:]) >= 1:
        n = int(name[3:])
        return {"kind": "raw", "num_envs": n, "env_id": LEGENT_IDS["OneRoom"], "pinned": n == 1,
                "label": f"raw MuJoCo (mj_step + mujoco.Renderer), {n} process{'es' if n > 1 else ''}"}
    if name.startswith("collect") and name[7:].isdigit() and int(name[7:]) >= 1:
        return CONFIGS["collect"] if int(name[7:]) == 1 else collect_config(int(name[7:]))
    bare = name.removeprefix("s")
    if bare.startswith("vec") and bare[3:].split("-")[0].isdigit():
        return vector_config(name)
    raise KeyError(name)


def scaling_rows(cores: int, extra: str = "", prefix: str = "vec") -> list[str]:
    """``vecN`` (``prefix``) rows for N = 1, 2, 4, ... up to ``cores`` (and ``cores`` itself)."""
    counts, n = [], 1
    while n < cores:
        counts.append(n)
        n *= 2
    counts.append(cores)
    return [f"{prefix}{n}{extra}" for n in counts]


def tree_cpu() -> float:
    """CPU seconds (user + system) of this process and all its descendants, living or
    reaped: what a row costs the machine, helper processes included."""
    import psutil

    me = psutil.Process()
    times = me.cpu_times()
    total = times.user + times.system + times.children_user + times.children_system
    for child in me.children(recursive=True):
        with contextlib.suppress(psutil.Error):
            t = child.cpu_times()
            total += t.user + t.system
    return total


CONFIGS = _configs()


# -- worker side ------------------------------------------------------------------------------
def legent_actions(n: int, seed: int, interact_p: float = 0.1) -> list[str]:
    """``step.py``'s random move/turn/tilt text actions, an interaction appended to about
    ``interact_p`` of them."""
    import numpy as np
    from step import random_actions

    rng = np.random.default_rng(seed + 7919)
    out = []
    for action in random_actions(n, seed):
        if rng.random() < interact_p:
            action += ", " + INTERACTIONS[int(rng.integers(len(INTERACTIONS)))]
        out.append(action)
    return out


class _Loop:
    """One env in the training loop: step with the next action, reset when the episode ends."""

    def __init__(self, env, actions, seed: int):
        self.env, self.actions, self.i = env, actions, 0
        env.reset(seed=seed)

    def run(self, steps: int) -> dict:
        env, actions, n = self.env, self.actions, len(self.actions)
        reset_ms, reset_cpu_ms, ends, successes = [], [], 0, 0
        perf, cpu = time.perf_counter, time.process_time
        wall0, cpu0, tree0 = perf(), cpu(), tree_cpu()
        for _ in range(steps):
            _, _, terminated, truncated, _ = env.step(actions[self.i % n])
            self.i += 1
            if terminated or truncated:
                ends += 1
                successes += bool(terminated)
                start, start_cpu = perf(), cpu()
                env.reset()
                reset_ms.append((perf() - start) * 1e3)
                # the stepping process's own work in the reset (not its wait for a helper)
                reset_cpu_ms.append((cpu() - start_cpu) * 1e3)
        return {"steps": steps, "wall": perf() - wall0, "cpu": cpu() - cpu0, "tree_cpu": tree_cpu() - tree0,
                "reset_ms": reset_ms, "reset_cpu_ms": reset_cpu_ms, "episodes": ends, "terminated": successes}


class _VecLoop:
    def __init__(self, vec, actions, seed: int):
        import gymnasium as gym

        self.vec, self.actions, self.i = vec, actions, 0
        self.n = vec.num_envs
        # With the next-step autoreset the step after an episode's end is its reset, not a
        # step: those are not counted (the same-step autoreset resets within the last step).
        self.next_step = vec.metadata.get("autoreset_mode") == gym.vector.AutoresetMode.NEXT_STEP
        self.resetting = 0
        vec.reset(seed=seed)

    def run(self, steps: int) -> dict:
        vec, actions, n, k = self.vec, self.actions, len(self.actions), self.n
        batches = max(1, steps // k)
        ends = resets = 0
        wall0, cpu0, tree0 = time.perf_counter(), time.process_time(), tree_cpu()
        for _ in range(batches):
            batch = tuple(actions[(self.i + j) % n] for j in range(k))
            self.i += k
            _, _, terminated, truncated, _ = vec.step(batch)
            resets += self.resetting
            ended = int(terminated.sum() + truncated.sum())
            ends += ended
            self.resetting = ended if self.next_step else 0
        # "cpu" is the parent's alone (receiving and decoding observations); "tree_cpu" all
        # processes' (the env workers and their helpers).
        return {"steps": batches * k - resets, "wall": time.perf_counter() - wall0, "cpu": None,
                "parent_cpu": time.process_time() - cpu0, "tree_cpu": tree_cpu() - tree0, "reset_ms": [],
                "episodes": ends, "terminated": None}


class _PoolLoop(_VecLoop):
    """The vector entry point's send/recv: step the first ``batch_size`` envs done."""

    def __init__(self, vec, actions, seed: int):
        self.vec, self.actions, self.i, self.n = vec, actions, 0, vec.num_envs
        self.resetting: set[int] = set()
        vec.async_reset(seed=seed)

    def run(self, steps: int) -> dict:
        vec, actions, n = self.vec, self.actions, len(self.actions)
        done = ends = 0
        wall0, cpu0, tree0 = time.perf_counter(), time.process_time(), tree_cpu()
        while done < steps:
            _, _, terminated, truncated, info = vec.recv()
            ids = info["env_id"]
            # A reply to an env's reset (sent after its episode ended) is not a step.
            done += sum(1 for i in ids if int(i) not in self.resetting)
            ended = terminated | truncated
            ends += int(ended.sum())
            self.resetting = {int(i) for i, e in zip(ids, ended) if e} | (self.resetting - {int(i) for i in ids})
            vec.send(tuple(actions[(self.i + j) % n] for j in range(len(ids))), env_ids=ids)
            self.i += len(ids)
        return {"steps": done, "wall": time.perf_counter() - wall0, "cpu": None,
                "parent_cpu": time.process_time() - cpu0, "tree_cpu": tree_cpu() - tree0, "reset_ms": [],
                "episodes": ends, "terminated": None}


class _CollectLoop:
    def __init__(self, env_id: str, episodes: int, scratch: Path, env_kwargs: dict, workers: int = 1):
        from legent_gym.data.collect import CollectConfig, collect

        self.collect, self.CollectConfig = collect, CollectConfig
        # N workers collect N times the episodes, so that starting them weighs alike.
        self.env_id, self.episodes, self.scratch, self.round = env_id, episodes * workers, scratch, 0
        self.env_kwargs, self.workers = env_kwargs, workers
        self._collect(2)  # warm-up: imports, writers, the first GL context

    def _collect(self, episodes: int):
        out = self.scratch / f"collect-{os.getpid()}-{self.round}"
        self.round += 1
        shutil.rmtree(out, ignore_errors=True)
        config = self.CollectConfig(self.env_id, episodes, str(out), workers=self.workers, seed=0,
                                    env_kwargs=dict(self.env_kwargs))
        wall0, cpu0, tree0 = time.perf_counter(), time.process_time(), tree_cpu()
        summary = self.collect(config, show_progress=False)
        result = {"steps": summary.new_episodes, "wall": time.perf_counter() - wall0,
                  "cpu": time.process_time() - cpu0, "tree_cpu": tree_cpu() - tree0, "reset_ms": [], "episodes": summary.new_episodes,
                  "terminated": summary.new_episodes, "attempts": summary.attempts,
                  "collect_seconds": summary.seconds}
        shutil.rmtree(out, ignore_errors=True)
        return result

    def run(self, steps: int) -> dict:
        return self._collect(self.episodes)


def _raw_process(env_id: str, size: int, seed: int, conn) -> None:
    """One process of a ``rawN`` row: a house, MuJoCo's own renderer, frames on request."""
    sys.path.insert(0, str(HERE))
    import legent_gym  # noqa: F401, I001  (first: it picks MuJoCo's GL backend)
    import gymnasium as gym
    import mujoco
    import numpy as np
    from benchmarks_common import StockRender, place_agent_camera

    env = gym.make(env_id, width=size, height=size)
    env.reset(seed=seed)
    base = env.unwrapped
    world = base.episode.world
    reference = StockRender(base.episode.renderer)
    lo, hi = world.model.stat.center[:2] - 2.0, world.model.stat.center[:2] + 2.0
    rng = np.random.default_rng(seed)
    conn.send("ready")
    while (frames := conn.recv()) > 0:
        for _ in range(frames):
            x, y = rng.uniform(lo, hi)
            place_agent_camera(world, float(x), float(y), float(rng.uniform(-180, 180)), 0.0)
            mujoco.mj_step(world.model, world.data)
            reference.rgb()
        conn.send(frames)
    reference.close()
    env.close()


class _RawLoop:
    """``rawN``: N processes of :func:`_raw_process`, each drawing the round's frames."""

    def __init__(self, env_id: str, n: int, size: int, seed: int):
        import multiprocessing as mp

        ctx = mp.get_context("spawn")
        self.conns, self.procs = [], []
        for i in range(n):
            ours, theirs = ctx.Pipe()
            proc = ctx.Process(target=_raw_process, args=(env_id, size, seed + i, theirs), daemon=True)
            proc.start()
            self.conns.append(ours)
            self.procs.append(proc)
        for conn in self.conns:
            if conn.recv() != "ready":
                raise RuntimeError("a raw MuJoCo process did not start")

    def run(self, steps: int) -> dict:
        wall0, tree0 = time.perf_counter(), tree_cpu()
        for conn in self.conns:
            conn.send(steps)  # each process: it runs as long as the one process of raw1
        done = sum(conn.recv() for conn in self.conns)
        return {"steps": done, "wall": time.perf_counter() - wall0, "cpu": None, "tree_cpu": tree_cpu() - tree0,
                "reset_ms": [], "episodes": 0, "terminated": None}

    def close(self) -> None:
        for conn in self.conns:
            with contextlib.suppress(OSError):
                conn.send(0)
        for proc in self.procs:
            proc.join(timeout=10)


def _make_worker(config: dict, args) -> tuple[object, dict]:
    """The row's loop, set up and warmed up, and facts about it."""
    kind, seed = config["kind"], args.seed
    if config.get("kwargs", {}).get("helpers") == "HELPERS":
        config = dict(config, kwargs={**config["kwargs"], "helpers": args.helpers})
    facts: dict = {}
    if kind == "miniworld":
        os.environ.setdefault("PYOPENGL_PLATFORM", "egl")
        import pyglet

        if not (os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")):
            pyglet.options["headless"] = True
        import gymnasium as gym
        import miniworld  # noqa: F401  (registers MiniWorld-*)
        import numpy as np

        env = gym.make(config["env_id"], obs_width=args.size, obs_height=args.size)
        rng = np.random.default_rng(seed)
        actions = [int(a) for a in rng.integers(env.action_space.n, size=4096)]
        loop = _Loop(env, actions, seed)
        from pyglet import gl

        facts["gl_renderer"] = gl.gl_info.get_renderer()
        facts["episode_cap"] = getattr(env.unwrapped, "max_episode_steps", None)
        facts["miniworld"] = getattr(miniworld, "__version__", "?")
    elif kind == "legent":
        import gymnasium as gym

        import legent_gym  # noqa: F401

        kwargs = dict(config["kwargs"])
        if "houses" in kwargs:
            kwargs["houses"] = args.houses[config["layout"]]
        if "houses_kept" in kwargs:
            kwargs["houses_kept"] = args.house_count
        if "house_cache" in kwargs:
            kwargs["house_cache"] = str(Path(args.scratch) / "house-cache" / config["layout"])
        env = gym.make(config["env_id"], width=args.size, height=args.size, **kwargs)
        if "house_cache" in kwargs:  # every house of the folder stored before timing
            store = env.unwrapped.episode.house_store
            for fill_seed in range(50 * args.house_count):
                if store.stored >= args.house_count:
                    break
                env.reset(seed=10**6 + fill_seed)
        loop = _Loop(env, legent_actions(4096, seed), seed)
        facts["episode_cap"] = env.spec.max_episode_steps
    elif kind == "vector":
        import gymnasium as gym

        import legent_gym  # noqa: F401

        if config.get("mode") == "vector_entry_point":
            vec = gym.make_vec(config["env_id"], num_envs=config["num_envs"], vectorization_mode="vector_entry_point",
                               width=args.size, height=args.size, **config["kwargs"],
                               **({"batch_size": config["batch_size"]} if "batch_size" in config else {}))
        else:
            vec = gym.make_vec(config["env_id"], num_envs=config["num_envs"], vectorization_mode="async",
                               vector_kwargs={"context": "forkserver",
                                              "autoreset_mode": gym.vector.AutoresetMode.SAME_STEP},
                               width=args.size, height=args.size, **config["kwargs"])
        loop = (_PoolLoop if "batch_size" in config else _VecLoop)(vec, legent_actions(4096, seed), seed)
        facts["cores"] = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else None
    elif kind == "raw":
        loop = _RawLoop(config["env_id"], config["num_envs"], args.size, args.seed)
    elif kind == "collect":
        import legent_gym  # noqa: F401

        loop = _CollectLoop(config["env_id"], args.collect_episodes, Path(args.scratch), config["kwargs"],
                            config.get("workers", 1))
        return loop, facts
    else:
        raise ValueError(kind)
    loop.run(30)  # warm-up, untimed
    return loop, facts


def _unsupported(err: TypeError, config: dict) -> bool:
    text = str(err)
    return "unexpected keyword" in text and any(k in text for k in config.get("kwargs", {}))


def worker_main(name: str, args) -> int:
    """Replies on the original stdout, one JSON line per request; anything else the row's code
    prints goes to stderr (a log file)."""
    proto = os.fdopen(os.dup(1), "w", buffering=1)
    os.dup2(2, 1)
    sys.path.insert(0, str(HERE))
    config = row_config(name)
    os.environ.update(config.get("env", {}))  # before any OpenGL: the row's processes inherit it
    if config.get("pinned", True) and (config["kind"] not in ("vector", "raw") or config["num_envs"] == 1):
        from benchmarks_common import pin_to_one_core

        pin_to_one_core()
    try:
        loop, facts = _make_worker(config, args)
    except TypeError as err:
        if _unsupported(err, config):
            print(json.dumps({"status": "unsupported", "reason": str(err)}), file=proto)
            return 0
        traceback.print_exc()
        print(json.dumps({"status": "error", "reason": f"{type(err).__name__}: {err}"}), file=proto)
        return 1
    except Exception as err:
        traceback.print_exc()
        print(json.dumps({"status": "error", "reason": f"{type(err).__name__}: {err}"}), file=proto)
        return 1
    print(json.dumps({"status": "ready", "facts": facts}), file=proto)
    for line in sys.stdin:
        request = json.loads(line)
        if request["cmd"] == "exit":
            break
        try:
            result = loop.run(request["steps"])
        except Exception as err:
            traceback.print_exc()
            print(json.dumps({"status": "error", "reason": f"{type(err).__name__}: {err}"}), file=proto)
            return 1
        print(json.dumps({"status": "ok", "result": result}), file=proto)
    with contextlib.suppress(Exception):
        (loop.vec if hasattr(loop, "vec") else getattr(loop, "env", None) or loop).close()
    return 0


# -- parent side ------------------------------------------------------------------------------
class Worker:
    def __init__(self, name: str, argv: list[str], log: Path):
        self.name, self.log = name, log
        self.status, self.reason, self.facts, self.results = "starting", "", {}, []
        self._log = open(log, "w")  # noqa: SIM115  (open as long as the worker runs; closed in close())
        self.proc = subprocess.Popen([sys.executable, str(Path(__file__).resolve()), "--worker", name, *argv],
                                     stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=self._log,
                                     text=True, bufsize=1, cwd=HERE.parent)

    def _reply(self) -> dict:
        line = self.proc.stdout.readline()
        if not line:
            self.proc.wait()
            return {"status": "error", "reason": f"worker exited ({self.proc.returncode}): {self._tail()}"}
        return json.loads(line)

    def _tail(self) -> str:
        self._log.flush()
        lines = [ln for ln in self.log.read_text().splitlines() if ln.strip()]
        return lines[-1] if lines else "no output"

    def wait_ready(self) -> None:
        reply = self._reply()
        self.status = reply["status"]
        self.reason, self.facts = reply.get("reason", ""), reply.get("facts", {})
        if self.status == "error" and "worker exited" not in self.reason:
            self.reason += f" (log: {self.log})"

    def run(self, steps: int) -> None:
        if self.status != "ready":
            return
        self.proc.stdin.write(json.dumps({"cmd": "run", "steps": steps}) + "\n")
        self.proc.stdin.flush()
        reply = self._reply()
        if reply["status"] == "ok":
            result = reply["result"]
            self.results.append(result)
            # As it comes, so that a run stopped early (a time limit) has shown what it measured.
            cpu = f", {result['tree_cpu']:.2f} CPU-s (all processes)" if result.get("tree_cpu") else ""
            print(f"    {self.name}: {result['steps']} in {result['wall']:.2f} s = {_rate(result):.1f}/s{cpu}",
                  file=sys.stderr, flush=True)
        else:
            self.status, self.reason = "error", reply.get("reason", "?") + f" (log: {self.log})"

    def close(self) -> None:
        with contextlib.suppress(Exception):
            if self.proc.poll() is None:
                self.proc.stdin.write(json.dumps({"cmd": "exit"}) + "\n")
                self.proc.stdin.flush()
        try:
            self.proc.wait(timeout=60)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()
        self._log.close()


def generate_houses(layout: str, count: int, out_dir: Path) -> str | None:
    """Write ``count`` houses with the CLI; None when it works, else why not."""
    cli = [sys.executable, "-c", "import sys; from legent_gym.cli import main; sys.exit(main())"]
    done = subprocess.run([*cli, "generate", "--preset", layout, "--seed", "1000", "--count", str(count),
                           "--out-dir", str(out_dir)], capture_output=True, text=True)
    if done.returncode != 0:
        err = done.stderr.strip().splitlines()
        if "--count" in done.stderr or "unrecognized arguments" in done.stderr:
            return UNSUPPORTED + " (legent-gym generate has no --count)"
        return f"legent-gym generate failed: {err[-1] if err else done.returncode}"
    return None


def _rate(result: dict) -> float:
    return result["steps"] / result["wall"] if result["wall"] > 0 else float("nan")


def summarise(workers: dict[str, Worker], rounds: int) -> dict:
    rows = {}
    ref = workers.get(REFERENCE)
    mw1 = workers.get("mw-oneroom")
    for name, w in workers.items():
        row = {"label": row_config(name)["label"], "status": w.status, "reason": w.reason, "facts": w.facts,
               "rounds": w.results}
        if w.results:
            rates = [_rate(r) for r in w.results]
            row["rate"] = statistics.median(rates)
            row["rate_overall"] = sum(r["steps"] for r in w.results) / sum(r["wall"] for r in w.results)
            resets = [ms for r in w.results for ms in r["reset_ms"]]
            row["reset_ms"] = statistics.median(resets) if resets else None
            row["reset_ms_mean"] = statistics.fmean(resets) if resets else None
            row["reset_ms_p99"] = percentile(resets, 99) if resets else None
            row["resets"] = len(resets)
            reset_cpu = [ms for r in w.results for ms in r.get("reset_cpu_ms", [])]
            row["reset_cpu_ms"] = statistics.median(reset_cpu) if reset_cpu else None
            row["reset_cpu_ms_p99"] = percentile(reset_cpu, 99) if reset_cpu else None
            eps = sum(r["episodes"] for r in w.results)
            row["steps_per_episode"] = sum(r["steps"] for r in w.results) / eps if eps else None
            for key, other in (("x_fourrooms", ref), ("x_oneroom", mw1)):
                if other is not None and other.results and other is not w:
                    pairs = zip(w.results, other.results)
                    row[key] = statistics.median(_rate(a) / _rate(b) for a, b in pairs)
            if all(r["cpu"] for r in w.results) and ref is not None and ref.results:
                # The same in process CPU time: what the process itself spent, steadier on a
                # shared machine (the pinned rows have no render threads of their own).
                row["cpu_x_fourrooms"] = statistics.median(
                    (a["steps"] / a["cpu"]) / (b["steps"] / b["cpu"]) for a, b in zip(w.results, ref.results))
            if all(r.get("tree_cpu") for r in w.results) and ref is not None and ref.results:
                # Steps per CPU-second of the row's whole process tree (helpers and vector
                # env workers included) against Miniworld's, round by round.
                row["tree_steps_per_cpu_s"] = statistics.median(r["steps"] / r["tree_cpu"] for r in w.results)
                row["tree_x_fourrooms"] = statistics.median(
                    (a["steps"] / a["tree_cpu"]) / (b["steps"] / b["tree_cpu"]) for a, b in zip(w.results, ref.results))
            if all(r.get("parent_cpu") is not None for r in w.results):
                row["parent_us_per_step"] = statistics.median(1e6 * r["parent_cpu"] / r["steps"] for r in w.results)
            if row_config(name)["kind"] == "collect":
                row["attempts"] = sum(r["attempts"] for r in w.results)
        rows[name] = row
    for name in workers:
        reference = _one_worker_row(name)
        if reference is not None and reference[0] in workers:
            one, many = workers[reference[0]].results, workers[name].results
            if one and many:
                rows[name][reference[1]] = statistics.median(_rate(b) / _rate(a) for a, b in zip(one, many))
    return rows


def _one_worker_row(name: str) -> tuple[str, str] | None:
    """The N=1 row a scaling row is compared with, and the key of that ratio; None for a
    row that is no N > 1 row (``collectN`` against ``collect``, ``rawN`` against ``raw1``,
    ``[s]vecN...`` against ``[s]vec1...`` with the same suffix but ``inline``)."""
    if name.startswith("collect") and name[7:].isdigit():
        return ("collect", "x_collect1") if name != "collect1" else None
    if name.startswith("raw") and name[3:].isdigit():
        return ("raw1", "x_vec1") if name != "raw1" else None
    prefix = "svec" if name.startswith("svec") else "vec"
    if not name.startswith(prefix) or name.startswith(f"{prefix}1-") or name == f"{prefix}1":
        return None
    rest = name.split("-", 1)[1] if "-" in name else ""
    return f"{prefix}1" + (f"-{rest}" if rest and rest != "inline" else ""), "x_vec1"


def percentile(values: list[float], q: float) -> float:
    """The ``q``-th percentile (nearest rank) of ``values``."""
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, max(0, math.ceil(q / 100 * len(ordered)) - 1))]


def _fmt(value, spec: str, missing: str = "") -> str:
    return missing if value is None else format(value, spec)


def markdown(rows: dict) -> str:
    out = ["| row | steps/s | x MW FourRooms | cpu x MW FourRooms | x MW OneRoom | steps per CPU-s, all processes "
           "| (x MW FourRooms) | reset ms (median) | reset ms (p99) | reset ms (mean) "
           "| reset CPU ms (median) | reset CPU ms (p99) | steps/episode | parent CPU us/step |",
           "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for name, row in rows.items():
        if row_config(name)["kind"] == "collect":
            continue
        label = row["label"].replace("Legent/", "")
        if row["status"] != "ready" or "rate" not in row:
            if row["status"] == "unsupported":
                text = UNSUPPORTED
            elif row["reason"].startswith("n/a"):
                text = row["reason"]
            else:
                text = f"error: {row['reason']}"
            out.append(f"| {label} | {text} | | | | | | | | | | | | |")
            continue
        extra = f" (N={row_config(name)['num_envs']}/N=1: {row['x_vec1']:.2f})" if "x_vec1" in row else ""
        out.append(f"| {label} | {row['rate']:.0f}{extra} | {_fmt(row.get('x_fourrooms'), '.2f', '1')} | "
                   f"{_fmt(row.get('cpu_x_fourrooms'), '.2f', '1' if name == REFERENCE else '')} | "
                   f"{_fmt(row.get('x_oneroom'), '.2f', '1' if name == 'mw-oneroom' else '')} | "
                   f"{_fmt(row.get('tree_steps_per_cpu_s'), '.0f')} | "
                   f"{_fmt(row.get('tree_x_fourrooms'), '.2f', '1' if name == REFERENCE else '')} | "
                   f"{_fmt(row.get('reset_ms'), '.1f', 'n/a')} | {_fmt(row.get('reset_ms_p99'), '.1f', 'n/a')} | "
                   f"{_fmt(row.get('reset_ms_mean'), '.1f', 'n/a')} | {_fmt(row.get('reset_cpu_ms'), '.1f', 'n/a')} | "
                   f"{_fmt(row.get('reset_cpu_ms_p99'), '.1f', 'n/a')} | {_fmt(row.get('steps_per_episode'), '.1f')} | "
                   f"{_fmt(row.get('parent_us_per_step'), '.0f')} |")
    for name in [n for n in rows if row_config(n)["kind"] == "collect"]:
        row = rows[name]
        out.append("")
        if "rate" in row:
            workers = row_config(name).get("workers", 1)
            where = "one core" if workers == 1 else f"{workers} workers"
            ratio = f", {row['x_collect1']:.2f}x --workers 1" if "x_collect1" in row else ""
            out.append(f"Collection ({row['label']}, {where}): "
                       f"**{row['rate']:.2f} successful trajectories/s**{ratio} (median of rounds; "
                       f"{sum(r['episodes'] for r in row['rounds'])} trajectories in {row['attempts']} attempts).")
        else:
            out.append(f"Collection ({row['label']}): {row['reason']}")
    return "\n".join(out)


def _atomic_json(path: str, data: dict) -> None:
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        with os.fdopen(fd, "w") as fh:
            json.dump(data, fh, indent=1)
            fh.flush()
            os.fsync(fh.fileno())
        os.chmod(tmp, 0o644)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def profile_resets(env_id: str, n: int, size: int, top: int = 25) -> None:
    import cProfile
    import pstats

    sys.path.insert(0, str(HERE))
    from benchmarks_common import pin_to_one_core

    pin_to_one_core()
    import gymnasium as gym

    import legent_gym  # noqa: F401

    env = gym.make(env_id, width=size, height=size)
    env.reset(seed=0)
    profiler = cProfile.Profile()
    start = time.perf_counter()
    profiler.enable()
    for _ in range(n):
        env.reset()
    profiler.disable()
    print(f"{n} resets of {env_id}: {(time.perf_counter() - start) / n * 1e3:.1f} ms each (under cProfile)")
    pstats.Stats(profiler).sort_stats("cumulative").print_stats(top)
    env.close()


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--steps", type=int, default=1000, help="steps per row per round")
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--only", default="", help=f"comma-separated rows of: {', '.join(CONFIGS)} "
                        f"({REFERENCE}, the reference, is always added)")
    parser.add_argument("--size", type=int, default=96)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--collect-episodes", type=int, default=100, help="episodes per collection (one a round)")
    parser.add_argument("--house-count", type=int, default=32, help="houses generated for the houses=DIR rows")
    parser.add_argument("--json", metavar="OUT", help="also write the results as JSON (atomically)")
    parser.add_argument("--profile-resets", type=int, default=0, metavar="N",
                        help="instead: cProfile N resets of --profile-id and print the top 25 by cumulative time")
    parser.add_argument("--profile-id", default=LEGENT_IDS["TwoRoom"])
    parser.add_argument("--helpers", type=int, default=1, help="helpers=H of the *-helpers rows")
    parser.add_argument("--scaling", action="store_true",
                        help="instead of --only: the async vector env at N = 1, 2, 4, ... cores workers "
                             "(vecN, vecN-eph8, and with --helpers > 0 vecN-helpers) and the same of the vector "
                             "entry point (svecN...), ratios to N=1")
    parser.add_argument("--worker", help=argparse.SUPPRESS)
    parser.add_argument("--houses-json", help=argparse.SUPPRESS)
    parser.add_argument("--scratch", help=argparse.SUPPRESS)
    args = parser.parse_args(argv)

    if args.worker:
        args.houses = json.loads(args.houses_json) if args.houses_json else {}
        return worker_main(args.worker, args)
    if args.profile_resets:
        profile_resets(args.profile_id, args.profile_resets, args.size)
        return 0

    names = [n.strip() for n in args.only.split(",") if n.strip()] or list(CONFIGS)
    if args.scaling:
        cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count() or 1
        names = scaling_rows(cores) + scaling_rows(cores, "-eph8")
        names += scaling_rows(cores, prefix="svec") + scaling_rows(cores, "-eph8", prefix="svec")
        names += ["collect"] + scaling_rows(cores, prefix="collect")[1:] + scaling_rows(cores, prefix="raw")
        if args.helpers:
            names += scaling_rows(cores, "-helpers") + scaling_rows(cores, "-helpers", prefix="svec")
    unknown = []
    for n in names:
        try:
            row_config(n)
        except (KeyError, ValueError):
            unknown.append(n)
    if unknown:
        parser.error(f"unknown rows {unknown}; known: {', '.join(CONFIGS)}, [s]vecN[-eph8][-helpers], collectN and rawN")
    if REFERENCE not in names:
        names.append(REFERENCE)
    known = [n for n in CONFIGS if n in names]
    names = known + [n for n in names if n not in known]  # the table's order, then other vector rows

    load_before = os.getloadavg()
    scratch = Path(tempfile.mkdtemp(prefix="legent-throughput-"))
    try:
        houses, house_problem = {}, {}
        for layout in LEGENT_IDS:
            rows = [n for n in names if row_config(n).get("layout") == layout]
            if rows:
                folder = scratch / "houses" / layout
                problem = generate_houses(layout, args.house_count, folder)
                houses[layout] = str(folder)
                if problem:
                    house_problem.update(dict.fromkeys(rows, problem))
        common = ["--size", str(args.size), "--seed", str(args.seed), "--helpers", str(args.helpers), "--collect-episodes",
                  str(args.collect_episodes), "--houses-json", json.dumps(houses), "--scratch", str(scratch)]
        workers: dict[str, Worker] = {}
        for name in names:
            if name in house_problem:
                continue
            workers[name] = Worker(name, common, scratch / f"{name}.log")
        for w in workers.values():
            w.wait_ready()
            state = w.status if w.status != "ready" else "ready"
            print(f"  {w.name}: {state}{(': ' + w.reason) if w.reason else ''}", file=sys.stderr, flush=True)
        order = [w for w in workers.values() if w.status == "ready"]
        for r in range(args.rounds):
            shift = r % len(order) if order else 0
            for w in order[shift:] + order[:shift]:
                w.run(args.steps)
            print(f"  round {r + 1}/{args.rounds} done", file=sys.stderr, flush=True)
            if args.json and r + 1 < args.rounds:  # what is measured so far, should the run be stopped
                _atomic_json(args.json, {"args": {k: v for k, v in vars(args).items() if k != "worker"},
                                         "rounds_done": r + 1, "rows": summarise(workers, r + 1)})
        for w in workers.values():
            w.close()
        rows = summarise(workers, args.rounds)
        for name, problem in house_problem.items():
            rows[name] = {"label": row_config(name)["label"], "status": "unsupported" if problem.startswith("n/a")
                          else "error", "reason": problem, "facts": {}, "rounds": []}
        rows = {n: rows[n] for n in names if n in rows}
        load_after = os.getloadavg()
        gl = next((r["facts"].get("gl_renderer") for r in rows.values() if r["facts"].get("gl_renderer")), None)
        machine = {"cpus": os.cpu_count(), "gl_renderer": gl, "load_before": load_before, "load_after": load_after,
                   "python": sys.version.split()[0]}
        print(f"\n{args.rounds} rounds x {args.steps} steps per row, {args.size}x{args.size}, one core "
              f"(vector rows with N > 1 and *-helpers rows: all cores; helpers={args.helpers}); {machine['cpus']} CPUs, GL: {gl}, load {load_before[0]:.1f} -> {load_after[0]:.1f}\n")
        print(markdown(rows))
        if args.json:
            _atomic_json(args.json, {"args": {k: v for k, v in vars(args).items() if k not in ("worker",)},
                                     "machine": machine, "rows": rows})
        failed = [n for n, r in rows.items() if r["status"] == "error"]
        return 1 if failed else 0
    finally:
        shutil.rmtree(scratch, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())

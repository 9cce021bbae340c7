"""Soak run: many steps, resets and make/close cycles in one process, watching for leaks.

    python benchmarks/soak.py [--env single|multi|both] [--layouts OneRoom TwoRoom FourRoom]
                              [--steps 100000] [--resets 5000] [--cycles 500] [--size 96]
                              [--samples 20] [--seed 0] [--warmup-resets 400] [--no-trim]
                              [--vector N] [--budget RESETS]

For each layout, one env (``gym.make("Legent/ComeHere-<layout>-v0")`` or the PettingZoo
parallel env of the same id, where the user acts too) takes random text actions (moves,
turns, tilts, speech, interactions, and malformed text that the env answers with a no-op
step), starting a new generated house every ``steps // resets`` steps (or when the episode
ends). Interleaved with the steps, ``cycles`` times: a second env is made, reset, stepped
once and closed. At every sample point the process is in the same state (the soaking env
open, no other env), and the script records resident memory (before and after
handing glibc's free heap pages back with ``malloc_trim``, unless ``--no-trim``: the first
is what the process holds, the second what it uses), open file descriptors, live
OpenGL and MuJoCo rendering contexts (:func:`legent_gym.utils.gl_backend.live_contexts`) and
steps/s since the last sample. After every step it checks MuJoCo's state for NaN or
infinity (``qpos``, ``qvel``) and adds up MuJoCo's warning counters (``data.warning``).

The sample at ``--warmup-resets`` resets is the baseline; the report says how much memory
grew since then and whether fds and contexts stayed equal to it. ``--vector N`` then steps
Gymnasium's async vector env of N workers of the layout for ``steps // N`` vector steps and
reports the resident memory of every process and their total. ``--budget RESETS`` instead
says what one process's memory is made of after RESETS houses (:func:`budget`). The soak
pins itself to one core, as the other benchmarks do (the vector env's workers get every core).
"""

from __future__ import annotations

import argparse
import gc
import os
import sys
import time
from dataclasses import dataclass, field

import numpy as np

ENV_ID = "Legent/ComeHere-OneRoom-v0"
_MOVES = ("move_forward({:.2f})", "rotate_right({:.1f})", "rotate_down({:.1f})")
_OTHERS = ("interact()", "grab()", "put()", "open()", "close()", 'speak("where are you?")',
           "grab({})", "open({})", "interact({})")
_MALFORMED = ("move_forward(", "fly()", "rotate_right(nan)", "", "speak(\"unterminated", "grab(-3)",
              "move_forward(1e400)", "))))", "rotate_right(1, 2)")


def random_action(rng: np.random.Generator) -> str:
    """One step of text: one to three primitives, or (one time in ten) malformed text."""
    roll = rng.random()
    if roll < 0.1:
        return str(rng.choice(_MALFORMED))
    parts = []
    for _ in range(int(rng.integers(1, 4))):
        if rng.random() < 0.8:
            template = str(rng.choice(_MOVES))
            parts.append(template.format(rng.uniform(-1.0, 2.0) if "forward" in template
                                         else rng.uniform(-90.0, 90.0)))
        else:
            parts.append(str(rng.choice(_OTHERS)).format(int(rng.integers(0, 40))))
    return ", ".join(parts)


def trim_heap() -> bool:
    """Hand the C heap's free pages back to the system (:func:`legent_gym.utils.heap.trim`); False
    where there is no glibc. Freed memory that glibc keeps for reuse counts in the resident size
    until then, so a resident size measured after this is the memory still in use."""
    from legent_gym.utils import heap

    return heap.trim()


def rss_mb() -> float:
    """Resident memory of this process, MiB (:func:`legent_gym.utils.heap.resident_bytes`)."""
    from legent_gym.utils import heap

    size = heap.resident_bytes()
    if size is None:
        raise RuntimeError("/proc/self/statm cannot be read: no resident size to measure")
    return size / 2**20


def open_fds() -> int:
    return len(os.listdir("/proc/self/fd"))


@dataclass
class Sample:
    steps: int
    resets: int
    cycles: int
    seconds: float
    rss_mb: float  # after trim_heap(): the memory in use
    untrimmed_mb: float  # before it: what the process held
    fds: int
    contexts: dict[str, int]
    steps_per_s: float  # since the previous sample


@dataclass
class SoakReport:
    env: str
    samples: list[Sample] = field(default_factory=list)
    baseline: int = 0  # index of the sample after the warm-up
    steps: int = 0
    resets: int = 0
    cycles: int = 0
    non_finite_steps: int = 0  # steps after which qpos or qvel held NaN or infinity
    warnings: dict[str, int] = field(default_factory=dict)  # MuJoCo warning name -> count

    @property
    def growth_mb(self) -> float:
        return self.samples[-1].rss_mb - self.samples[self.baseline].rss_mb

    @property
    def untrimmed_growth_mb(self) -> float:
        return self.samples[-1].untrimmed_mb - self.samples[self.baseline].untrimmed_mb

    @property
    def fds_constant(self) -> bool:
        return len({s.fds for s in self.samples[self.baseline:]}) == 1

    @property
    def gl_constant(self) -> bool:
        """The OpenGL (EGL) contexts alive stayed as many as at the baseline."""
        return len({s.contexts.get("gl", 0) for s in self.samples[self.baseline:]}) == 1

    @property
    def max_mjr(self) -> int:
        """The most MuJoCo rendering contexts alive at a sample after the warm-up (the
        soaking env's renderers and the one a closed renderer leaves for the next)."""
        return max(s.contexts.get("mjr", 0) for s in self.samples[self.baseline:])

    def lines(self) -> list[str]:
        out = [f"{self.env}: {self.steps} steps, {self.resets} resets, {self.cycles} make/close cycles",
               f"{'steps':>8} {'resets':>7} {'cycles':>6} {'s':>8} {'RSS MiB':>8} {'untrim':>7} {'fds':>4} "
               f"{'gl':>3} {'mjr':>4} {'steps/s':>8}"]
        for i, s in enumerate(self.samples):
            mark = "  <- baseline (after warm-up)" if i == self.baseline else ""
            out.append(f"{s.steps:>8} {s.resets:>7} {s.cycles:>6} {s.seconds:>8.1f} {s.rss_mb:>8.1f} "
                       f"{s.untrimmed_mb:>7.1f} {s.fds:>4} "
                       f"{s.contexts.get('gl', 0):>3} {s.contexts.get('mjr', 0):>4} {s.steps_per_s:>8.1f}{mark}")
        first = self.samples[0]
        out.append(f"RSS at start {first.rss_mb:.1f} MiB, after warm-up {self.samples[self.baseline].rss_mb:.1f} MiB, "
                   f"at end {self.samples[-1].rss_mb:.1f} MiB (growth after warm-up {self.growth_mb:+.1f} MiB; "
                   f"untrimmed {self.samples[self.baseline].untrimmed_mb:.1f} -> {self.samples[-1].untrimmed_mb:.1f} "
                   f"MiB, {self.untrimmed_growth_mb:+.1f}); "
                   f"fds {'constant' if self.fds_constant else 'CHANGED'}, GL contexts "
                   f"{'constant' if self.gl_constant else 'CHANGED'}, at most {self.max_mjr} MuJoCo "
                   f"rendering contexts; steps with NaN/inf state: "
                   f"{self.non_finite_steps}; MuJoCo warnings: {self.warnings or 'none'}")
        return out


def _make(kind: str, size: int, house_pool: list[int] | None, env_id: str = ENV_ID):
    """(env, reset, step, world) for the single-agent or the PettingZoo env of ``env_id``."""
    import gymnasium as gym

    import legent_gym  # noqa: F401  (registers the ids, picks EGL)

    if kind == "single":
        env = gym.make(env_id, width=size, height=size, house_pool=house_pool)

        def step(rng):
            _, _, terminated, truncated, _ = env.step(random_action(rng))
            return terminated or truncated

        return env, lambda seed: env.reset(seed=seed), step, lambda: env.unwrapped.episode.world
    from legent_gym.multiagent import parallel_env
    from legent_gym.multiagent.registration import id_kwargs

    penv = parallel_env(**id_kwargs(env_id), width=size, height=size, house_pool=house_pool)

    def pstep(rng):
        actions = {agent: random_action(rng) for agent in penv.agents}
        if "user" in actions and rng.random() < 0.2:
            actions["user"] = None  # the user may pass
        _, _, terminations, truncations, _ = penv.step(actions)
        return any(terminations.values()) or any(truncations.values()) or not penv.agents

    return penv, lambda seed: penv.reset(seed=seed), pstep, lambda: penv.episode.world


def _check_state(world, report: SoakReport) -> None:
    import mujoco

    data = world.data
    if not (np.isfinite(data.qpos).all() and np.isfinite(data.qvel).all()):
        report.non_finite_steps += 1
    for i in range(len(data.warning)):
        count = int(data.warning[i].number)
        if count:
            name = mujoco.mjtWarning(i).name
            report.warnings[name] = report.warnings.get(name, 0) + count
            data.warning[i].number = 0  # counted once; the next count is new warnings


def fill_model_caches() -> int:
    """Make every model the house generator draws (each built-in type's
    ``registry.GENERATED_VARIANTS``, the shelved books' ``BOOK_VARIANTS``) and its links'
    merged geometry, as the builder asks for it; returns how many models."""
    from legent_gym.world.assets import registry
    from legent_gym.world.generation.dressing import BOOK_VARIANTS
    from legent_gym.world.meshing import prepare_link_geometry

    models = [registry.make(asset, variant) for asset in registry.asset_ids(builtin=True)
              for variant in range(BOOK_VARIANTS if asset == "shelved_book" else registry.GENERATED_VARIANTS)]
    prepare_link_geometry([(link, model.pickupable or link.joint is not None) for model in models for link in model.links])
    return len(models)


def soak(kind: str = "single", steps: int = 2_000, resets: int = 100, cycles: int = 30, *, size: int = 96,
         samples: int = 10, seed: int = 0, house_pool: list[int] | None = None, log=None, env_id: str = ENV_ID,
         warmup_resets: int | None = None, trim: bool = True, fill_models: bool = False) -> SoakReport:
    """Run the soak (see the module docstring) and return its report. ``house_pool``: the
    houses come from these generation seeds, in turn, rather than from a new seed each
    time, so the asset and geometry caches fill within the warm-up; with more seeds than
    the env keeps built houses (``legent_gym.envs.episode.HOUSE_CACHE_SIZE``), every reset
    still builds its house. ``warmup_resets``: the baseline is the sample taken when the
    env has reset that many times (else after a tenth of the steps). ``trim``: hand the
    free heap back at each sample (``Sample.rss_mb`` is then the memory in use); without
    it, both figures are what the process holds, as it would hold it unsampled.
    ``fill_models``: first make every model the house generator draws, with its links'
    geometry (:func:`fill_model_caches`), so that what grows after the baseline is not the
    asset registry still filling up to its bound."""
    from legent_gym.utils.gl_backend import live_contexts

    if fill_models:
        fill_model_caches()

    rng = np.random.default_rng(seed)
    report = SoakReport(f"{kind} {env_id}")
    env, reset, step, world = _make(kind, size, house_pool, env_id)
    episode_len = max(1, steps // max(1, resets))
    warmup = max(1, steps // 10)
    sample_every = max(1, (steps - warmup) // max(1, samples))
    cycle_every = max(1, steps // max(1, cycles)) if cycles else 0
    start = last_time = time.perf_counter()
    last_steps = 0

    def sample() -> None:
        nonlocal last_time, last_steps
        now = time.perf_counter()
        rate = (report.steps - last_steps) / (now - last_time) if report.steps > last_steps else 0.0
        gc.collect()
        untrimmed = rss_mb()
        if trim:
            trim_heap()
        report.samples.append(Sample(report.steps, report.resets, report.cycles, now - start, rss_mb(), untrimmed,
                                     open_fds(), live_contexts(), rate))
        now = time.perf_counter()  # the rate leaves out the sampling
        last_time, last_steps = now, report.steps
        if log is not None:
            log(report.lines()[-2] if len(report.samples) > 1 else report.lines()[-3])

    try:
        reset(int(rng.integers(2**31)))
        report.resets += 1
        sample()
        in_episode = 0
        while report.steps < steps:
            done = step(rng)
            report.steps += 1
            in_episode += 1
            _check_state(world(), report)
            if done or in_episode >= episode_len:
                reset(None)  # the env's own generator draws the next house
                report.resets += 1
                in_episode = 0
            if cycle_every and report.steps % cycle_every == 0 and report.cycles < cycles:
                other, other_reset, other_step, other_world = _make(kind, size, house_pool, env_id)
                other_reset(int(rng.integers(2**31)))
                other_step(rng)
                _check_state(other_world(), report)
                other.close()
                del other, other_reset, other_step, other_world
                report.cycles += 1
            if (report.steps == warmup if warmup_resets is None
                    else report.resets >= warmup_resets and report.baseline == 0):
                sample()
                report.baseline = len(report.samples) - 1
                warmup = report.steps
            elif (report.baseline and (report.steps - warmup) % sample_every == 0) or report.steps == steps:
                sample()
    finally:
        env.close()
    return report


@dataclass
class VectorSample:
    steps: int
    seconds: float
    rss_mb: list[float]  # resident memory of each process: the parent first, then its children
    pss_mb: float  # proportional set size of them all (shared pages counted once in total)


def vector_soak(env_id: str, workers: int, steps: int = 2_000, *, size: int = 96, samples: int = 10,
                seed: int = 0, log=None) -> list[VectorSample]:
    """Step Gymnasium's async vector env of ``workers`` copies of ``env_id`` (each in its own
    process, started by forkserver) with random text actions for ``steps`` vector steps (the
    workers reset themselves when an episode ends: a new generated house each), sampling the
    resident memory of this process and of every process under it."""
    import gymnasium as gym
    import psutil

    import legent_gym  # noqa: F401

    if workers < 1:
        raise ValueError(f"workers must be at least 1, got {workers}")
    rng = np.random.default_rng(seed)
    out: list[VectorSample] = []
    start = time.perf_counter()
    env = gym.make_vec(env_id, num_envs=workers, vectorization_mode="async", width=size, height=size,
                       vector_kwargs={"context": "forkserver"})

    def sample(done: int) -> None:
        procs = [psutil.Process()] + psutil.Process().children(recursive=True)
        rss, pss = [], 0.0
        for proc in procs:
            try:
                info = proc.memory_full_info()
            except psutil.Error:  # a process gone between the listing and the read
                continue
            rss.append(info.rss / 2**20)
            pss += info.pss / 2**20
        out.append(VectorSample(done, time.perf_counter() - start, rss, pss))
        if log is not None:
            log(f"{env_id} x{workers}: {done:>8} steps {out[-1].seconds:>8.1f} s  total RSS {sum(rss):8.1f} MiB  "
                f"PSS {pss:8.1f} MiB  per process " + " ".join(f"{r:.0f}" for r in rss))

    try:
        env.reset(seed=seed)
        sample(0)
        every = max(1, steps // max(1, samples))
        for done in range(1, steps + 1):
            env.step(tuple(random_action(rng) for _ in range(workers)))
            if done % every == 0 or done == steps:
                sample(done)
    finally:
        env.close()
    return out


LAYOUTS = ("OneRoom", "TwoRoom", "FourRoom")


def _mapped_mb() -> tuple[float, float]:
    """(resident MiB in file-backed mappings: shared libraries and other files, the rest)."""
    import psutil

    files = other = 0.0
    for m in psutil.Process().memory_maps(grouped=True):
        if m.path.startswith("/") and not m.path.startswith("/dev/"):
            files += m.rss / 2**20
        else:
            other += m.rss / 2**20
    return files, other


def budget(env_id: str, resets: int = 200, *, size: int = 96, seed: int = 0) -> list[tuple[str, float]]:
    """What one env process's resident memory is made of after ``resets`` new houses with 20
    random steps each: each component is what taking it away gives back (resident size before
    and after; every step ends with ``gc.collect`` and ``malloc_trim``, but the first)."""
    before_import = rss_mb()
    import gymnasium as gym

    import legent_gym  # noqa: F401
    from legent_gym.world import meshing
    from legent_gym.world.assets import registry

    imported = rss_mb()
    rng = np.random.default_rng(seed)
    env = gym.make(env_id, width=size, height=size)
    env.reset(seed=seed)
    for _ in range(resets):
        for _ in range(20):
            _, _, terminated, truncated, _ = env.step(random_action(rng))
            if terminated or truncated:
                break
        env.reset()
    gc.collect()
    rows = [("resident, as held after the run", rss_mb())]

    def freed(name: str) -> None:
        gc.collect()
        trim_heap()
        now = rss_mb()
        rows.append((name, rows[-1][1] - now if len(rows) == 1 else last[0] - now))
        last[0] = now

    last = [rows[0][1]]
    freed("free heap pages glibc kept (malloc_trim)")
    models, links = registry.make.cache_info().currsize, meshing.cached_links()
    registry.make.cache_clear()
    freed(f"asset models kept by registry.make ({models}) and their link geometry ({links} links)")
    env.close()
    del env
    freed("the env: current house (MuJoCo model and data, navigation grids, task), renderer, "
          "per-env caches")
    files, other = _mapped_mb()
    rows.append(("left: file-backed mappings (shared libraries: LLVM for llvmpipe, OpenCV, NumPy, "
                 "MuJoCo, ...; shared between processes)", files))
    rows.append((f"left: heap and anonymous memory (interpreter and modules: {before_import:.0f} MiB "
                 f"before importing legent_gym, {imported:.0f} after; GL driver state; module caches)", other))
    return rows


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--env", choices=("single", "multi", "both"), default="both")
    parser.add_argument("--steps", type=int, default=100_000)
    parser.add_argument("--resets", type=int, default=5_000)
    parser.add_argument("--cycles", type=int, default=500)
    parser.add_argument("--size", type=int, default=96)
    parser.add_argument("--samples", type=int, default=20)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--layouts", nargs="+", choices=LAYOUTS, default=list(LAYOUTS),
                        help="soak Legent/ComeHere-<layout>-v0 for each")
    parser.add_argument("--warmup-resets", type=int, default=400,
                        help="the baseline sample is taken at this many resets")
    parser.add_argument("--no-trim", action="store_true",
                        help="never malloc_trim at a sample: every figure is what the process holds")
    parser.add_argument("--vector", type=int, default=0, metavar="N",
                        help="also step an async vector env of N workers per layout and report its total memory")
    parser.add_argument("--budget", type=int, default=0, metavar="RESETS",
                        help="instead of soaking: after RESETS new houses, what each component of the "
                             "resident memory gives back when taken away, per layout")
    args = parser.parse_args(argv)
    if args.budget:
        for layout in args.layouts:
            print(f"Legent/ComeHere-{layout}-v0, {args.budget} resets, {args.size} x {args.size}:")
            for name, mb in budget(f"Legent/ComeHere-{layout}-v0", args.budget, size=args.size, seed=args.seed):
                print(f"  {mb:8.1f} MiB  {name}", flush=True)
        return 0
    from benchmarks_common import pin_to_one_core

    every_core = os.sched_getaffinity(0) if hasattr(os, "sched_getaffinity") else None
    pin_to_one_core()
    kinds = ("single", "multi") if args.env == "both" else (args.env,)
    for layout in args.layouts:
        env_id = f"Legent/ComeHere-{layout}-v0"
        for kind in kinds:
            report = soak(kind, args.steps, args.resets, args.cycles, size=args.size, samples=args.samples,
                          seed=args.seed, log=lambda line: print(line, flush=True), env_id=env_id,
                          warmup_resets=args.warmup_resets, trim=not args.no_trim)
            print("\n".join(report.lines()), flush=True)
        if args.vector:
            if every_core is not None:  # the workers inherit it: one core each where there are enough
                os.sched_setaffinity(0, every_core)
            vector_soak(env_id, args.vector, args.steps // args.vector, size=args.size, samples=args.samples,
                        seed=args.seed, log=lambda line: print(line, flush=True))
    return 0


if __name__ == "__main__":
    sys.exit(main())

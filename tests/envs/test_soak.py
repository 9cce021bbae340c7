"""Long runs do not grow: steps, resets over generated houses and make/close cycles in one
process, for the single-agent env and the PettingZoo env (``benchmarks/soak.py`` does the
run and reports the figures). After the warm-up, resident memory grows by less than 50 MB,
open file descriptors and OpenGL contexts stay constant, at most two MuJoCo rendering
contexts live (the soaking env's and the one kept for the next renderer), MuJoCo's state
never holds NaN or infinity and MuJoCo's warning counters stay at zero."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

from legent_gym.envs.episode import HOUSE_CACHE_SIZE
from legent_gym.utils import heap

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "benchmarks"))

from soak import SoakReport  # noqa: E402
from soak import soak as soak_here  # noqa: E402


def soak(*args, **kwargs) -> SoakReport:
    """``benchmarks/soak.py``'s run in a fresh process: the figures are the soaking env's
    alone, not those of renderers and caches other tests left in this worker."""
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    with ProcessPoolExecutor(1, mp_context=multiprocessing.get_context("spawn"), initializer=_unnumbered) as pool:
        return pool.submit(soak_here, *args, **kwargs).result()


def _unnumbered() -> None:
    """Name the soak's process without a number: a numbered multiprocessing child is taken
    for a vector env's worker and pinned to core ``number % cores``
    (``legent_gym.envs.vector.settle_worker``), so soaks run side by side by pytest-xdist
    would share one core."""
    import multiprocessing

    multiprocessing.current_process().name = "soak"

KINDS = ["single", "multi"]


def check(report: SoakReport, steps: int, resets: int, cycles: int, growth_mb: float) -> None:
    text = "\n".join(report.lines())
    assert report.steps == steps and report.resets >= resets and report.cycles == cycles, text
    assert report.non_finite_steps == 0, text
    assert report.warnings == {}, text
    assert report.fds_constant, text
    assert report.gl_constant and report.samples[-1].contexts["gl"] == 1, text
    assert report.max_mjr <= 2, text
    assert report.growth_mb < growth_mb, text
    assert all(s.steps_per_s > 0 for s in report.samples[1:]), text


@pytest.mark.parametrize("kind", KINDS)
def test_short_soak(kind):
    """2,000 steps, 100 resets, 30 make/close cycles. The houses come from a pool of
    generation seeds larger than the env keeps built, in turn: every reset builds its house,
    and the asset and geometry caches are full after the warm-up, so that a leak of 0.2 MB
    a reset would show."""
    pool = list(range(HOUSE_CACHE_SIZE + 4))
    report = soak(kind, steps=2_000, resets=100, cycles=30, samples=5, house_pool=pool)
    check(report, 2_000, 100, 30, growth_mb=20.0)


@pytest.mark.slow
@pytest.mark.parametrize("kind", KINDS)
def test_long_soak(kind):
    """100,000 steps, 5,000 resets (a new generated house each), 500 make/close cycles."""
    report = soak(kind, steps=100_000, resets=5_000, cycles=500, samples=20)
    print("\n".join(report.lines()))
    check(report, 100_000, 5_000, 500, growth_mb=50.0)


LAYOUTS = ["OneRoom", "TwoRoom", "FourRoom"]


def test_link_geometry_lives_with_its_link():
    """The link-geometry cache holds no link: a link's merged mesh goes when the link does
    (a variant the asset registry's cache let go), so it cannot fill with past houses."""
    import gc

    from legent_gym.world import meshing
    from legent_gym.world.assets.model import Link, box_part

    gc.collect()
    before = meshing.cached_links()
    links = [Link("base", [box_part((0, 0, 0.1 * i), (0.2, 0.2, 0.2), (0.5, 0.5, 0.5, 1.0))]) for i in range(50)]
    meshing.prepare_link_geometry([(link, False) for link in links])
    first = meshing.link_geometry(links[0], False)
    assert meshing.link_geometry(links[0], False) is first  # cached while the link lives
    assert meshing.cached_links() == before + 50
    del links, first
    gc.collect()
    assert meshing.cached_links() == before


def test_dropped_house_freed_without_collection():
    """A world the env no longer holds is freed at the reset that drops it, not at Python's
    next full garbage collection (no reference cycle through ``world.derived``), so the heap
    trim after a house finds its memory free."""
    import gc
    import weakref

    import gymnasium as gym

    env = gym.make("Legent/ComeHere-TwoRoom-v0", width=32, height=32)
    try:
        env.reset(seed=1)
        for text in ("move_forward(1)", "rotate_right(30)", "move_forward(0.5)"):
            env.step(text)  # the body's clearance map is made and kept in world.derived
        world = weakref.ref(env.unwrapped.episode.house.world)
        gc.disable()
        try:
            env.reset(seed=2)
            assert world() is None
        finally:
            gc.enable()
    finally:
        env.close()


def test_models_kept_bounded():
    """The asset registry keeps at most MODELS_KEPT made models, whatever the houses ask."""
    from legent_gym.world.assets import registry

    for variant in range(registry.MODELS_KEPT + 40):
        registry.make("chair", variant)
    assert registry.make.cache_info().currsize == registry.MODELS_KEPT


def test_short_soak_two_rooms_flat():
    """TwoRoom at 96 x 96, a new generated house at every reset, nothing trimmed by the run:
    with every model the generator draws made first and after 60 resets (the caches filled)
    the resident memory the process holds grows by less than TRIM_GROWTH + 8 MiB over the
    next 100 houses. The env hands free heap
    pages back only once it has grown by TRIM_GROWTH (legent_gym.utils.heap), so what it
    holds swings by up to that much between two samples; caches that keep past houses'
    models and geometry, or a heap that keeps their pages, grow by more."""
    report = soak("single", steps=320, resets=160, cycles=0, samples=4, env_id="Legent/ComeHere-TwoRoom-v0",
                  warmup_resets=60, trim=False, fill_models=True)
    text = "\n".join(report.lines())
    assert report.resets >= 160 and report.samples[report.baseline].resets >= 60, text
    assert report.untrimmed_growth_mb < heap.TRIM_GROWTH / 2**20 + 8.0, text


@pytest.mark.slow
@pytest.mark.parametrize("layout", LAYOUTS)
def test_memory_acceptance(layout):
    """One env process, 96 x 96, 100,000 steps of random text with a new generated house at
    every reset (every 20 steps or sooner), nothing trimmed by the run: at most 350 MiB
    resident at the end, and at most 30 MiB more than at reset 400."""
    report = soak("single", steps=100_000, resets=5_000, cycles=0, samples=20,
                  env_id=f"Legent/ComeHere-{layout}-v0", warmup_resets=400, trim=False)
    text = "\n".join(report.lines())
    print(text)
    assert report.samples[report.baseline].resets >= 400, text
    assert report.samples[-1].untrimmed_mb <= 350.0, text
    assert report.untrimmed_growth_mb <= 30.0, text

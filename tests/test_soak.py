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

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))

from soak import SoakReport, soak  # noqa: E402

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

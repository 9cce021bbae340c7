"""Generated houses are physically stable: small objects stay on their receptacles."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from legent_gym.world.builder import build_world
from legent_gym.world.generation import generate_house


def _worst_drift(seed: int, preset: str) -> tuple[float, str]:
    scene = generate_house(seed, preset)
    world = build_world(scene)
    start = {i: world.object_position(i) for i in world.free_objects}
    for _ in range(int(2.0 / world.model.opt.timestep)):
        mujoco.mj_step(world.model, world.data)
    worst, what = 0.0, ""
    for i, p0 in start.items():
        moved = float(np.linalg.norm(world.object_position(i) - p0))
        if moved > worst:
            worst, what = moved, f"house {preset}/{seed}: object {i} ({scene.object(i).asset} on {scene.object(i).on})"
    return worst, what


@pytest.mark.parametrize("seed", range(5))
def test_small_objects_stay_put(seed):
    worst, what = _worst_drift(seed, "TwoRoom")
    assert worst < 0.02, f"{what} moved {worst:.3f} m in 2 s"


@pytest.mark.slow
def test_small_objects_stay_put_in_100_houses():
    failures = []
    for seed in range(100):
        preset = ("OneRoom", "TwoRoom", "FourRoom")[seed % 3]
        worst, what = _worst_drift(1000 + seed, preset)
        if worst >= 0.02:
            failures.append(f"{what} moved {worst:.3f} m")
    assert not failures, "\n".join(failures)

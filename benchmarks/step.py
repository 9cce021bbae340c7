"""Env step and reset speed, next to the raw render rate of the same scene.

    python benchmarks/step.py [--ids Legent/ComeHere-TwoRoom-v0,...] [--steps 1000] [--size 96]

For each env id, on one core: steps/s with random actions (a random move, turn and tilt
each step, as text actions), the raw render rate of the same house measured in the same
run (the agent camera put at each pose the steps produced and rendered by MuJoCo's own
``mujoco.Renderer`` with the env renderer's options, the same image, with nothing of ours
in it; our renderer leaves out unseen geoms, so a step can cost less), their ratio, and the
median time of a reset with a new house (generation + build + navigation grid + task +
first frame).

Steps and raw renders are timed in alternating blocks of ``--block`` steps, each block of
renders replaying the poses of the block of steps just before it, so that other load on a
shared machine weighs on both alike. ``cpu ratio`` is the same ratio in process CPU time
(what this process itself spent, rendering threads included), steadier still.
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import time

import gymnasium as gym
import numpy as np
from benchmarks_common import StockRender, pin_to_one_core, place_agent_camera, write_report

import legent_gym


def random_actions(n: int, seed: int) -> list[str]:
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(n):
        out.append(f"move_forward({rng.uniform(0, 1):.2f}), rotate_right({rng.uniform(-90, 90):.1f}), "
                   f"rotate_down({rng.uniform(-10, 10):.1f})")
    return out


def bench(env_id: str, steps: int, size: int, resets: int, block: int = 50) -> dict:
    env = gym.make(env_id, width=size, height=size)
    env.reset(seed=0)
    base = env.unwrapped
    reset_ms = []
    for i in range(resets):
        start = time.perf_counter()
        env.reset(seed=100 + i)
        reset_ms.append((time.perf_counter() - start) * 1e3)

    actions = random_actions(steps, 1)
    env.reset(seed=1)
    for a in actions[:20]:
        env.step(a)
    world = base.episode.world
    reference = StockRender(base.episode.renderer)
    step_wall = step_cpu = render_wall = render_cpu = 0.0
    for first in range(0, steps, block):
        poses = []
        wall, cpu = time.perf_counter(), time.process_time()
        for a in actions[first:first + block]:
            _, _, terminated, truncated, info = env.step(a)
            poses.append(info["agent_pose"])
            if terminated or truncated:
                # Keep the house: a reset here would measure generation, not stepping.
                base.episode.ctx.finished = False
        step_wall += time.perf_counter() - wall
        step_cpu += time.process_time() - cpu
        # The reference: the raw render of the same house from the same camera poses (it
        # ends at the last pose, where the env's agent stands: the env is left as it was).
        wall, cpu = time.perf_counter(), time.process_time()
        for x, y, yaw, pitch in poses:
            place_agent_camera(world, x, y, yaw, pitch)
            reference.rgb()
        render_wall += time.perf_counter() - wall
        render_cpu += time.process_time() - cpu
    reference.close()
    env.close()
    return {"steps_per_s": steps / step_wall, "render_per_s": steps / render_wall,
            "ratio": render_wall / step_wall, "cpu_ratio": render_cpu / step_cpu,
            "reset_ms": statistics.median(reset_ms), "resets_per_s": 1000 / statistics.median(reset_ms)}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--ids", default=",".join(legent_gym.ENV_IDS))
    parser.add_argument("--steps", type=int, default=1000)
    parser.add_argument("--resets", type=int, default=20)
    parser.add_argument("--size", type=int, default=96)
    parser.add_argument("--block", type=int, default=50, help="steps per timed block (steps and renders alternate)")
    parser.add_argument("--json", metavar="OUT", help="also write the figures to this JSON file")
    args = parser.parse_args(argv)
    load_before = os.getloadavg()[0]
    pin_to_one_core()
    rows = {}
    print(f"{'env id':36s} {'steps/s':>8} {'render/s':>9} {'ratio':>6} {'cpu ratio':>9} {'reset ms':>9} "
          f"{'resets/s':>9}")
    for env_id in args.ids.split(","):
        r = bench(env_id, args.steps, args.size, args.resets, args.block)
        print(f"{env_id:36s} {r['steps_per_s']:>8.0f} {r['render_per_s']:>9.0f} {r['ratio']:>6.2f} "
              f"{r['cpu_ratio']:>9.2f} {r['reset_ms']:>9.1f} {r['resets_per_s']:>9.1f}")
        rows[env_id] = r
    if args.json:
        write_report(args.json, args, rows, load_before)
    return 0


if __name__ == "__main__":
    sys.exit(main())

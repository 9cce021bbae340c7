"""Two-agent step speed against the single-agent env in the same house, in the same run.

    python benchmarks/multiagent.py [--ids Legent/ComeHere-TwoRoom-v0,...] [--steps 1000] [--size 96]
                                    [--repeats 3] [--user random|still] [--distance-info]

For each env id, on one core: steps/s of the single-agent ``HouseholdEnv`` (one egocentric
render per step) and of ``HouseholdParallelEnv`` (the user acts too: two egocentric renders
per step), both in the house of seed 1, with random moves, turns and tilts as text actions
(the agent's sequence is the same in both; ``--user still``: the user passes None, so
the second render is the only extra work; ``--distance-info``: both envs measure
``info["distance_to_goal"]`` every step, the multi-agent env's opt-in). As in
``benchmarks/step.py``, an episode that ends (the task done by chance) goes on in the same house: a reset would measure house
generation, not stepping. The two are timed in alternating chunks of 50 steps (a busy
machine slows both alike), ``--repeats`` rounds; the table gives the medians and the ratio
of the medians (the target
is >= 0.45: a second render costs about as much as the first).
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time

import numpy as np
from benchmarks_common import pin_to_one_core

from legent_gym.envs.household import HouseholdEnv
from legent_gym.multiagent import HouseholdParallelEnv
from legent_gym.multiagent.registration import id_kwargs

DEFAULT_IDS = "Legent/ComeHere-OneRoom-v0,Legent/ComeHere-TwoRoom-v0,Legent/PickUp-TwoRoom-v0"
HOUSE_SEED = 1
WARMUP = 20


def random_actions(n: int, seed: int) -> list[str]:
    rng = np.random.default_rng(seed)
    return [f"move_forward({rng.uniform(0, 1):.2f}), rotate_right({rng.uniform(-90, 90):.1f}), "
            f"rotate_down({rng.uniform(-10, 10):.1f})" for _ in range(n)]


def bench_round(kwargs: dict, agent_actions: list[str], user_actions: list, chunk: int) -> tuple[float, float]:
    """(single-agent steps/s, two-agent steps/s), the two timed in alternating chunks so
    that a busy machine slows both alike."""
    single = HouseholdEnv(**kwargs)
    double = HouseholdParallelEnv(**kwargs, max_cycles=len(agent_actions) + 1)
    single.reset(seed=HOUSE_SEED)
    double.reset(seed=HOUSE_SEED)
    for action, user_action in zip(agent_actions[:WARMUP], user_actions[:WARMUP]):
        single.step(action)
        _step_on(double, action, user_action)
    times = [0.0, 0.0]
    for lo in range(WARMUP, len(agent_actions), chunk):
        start = time.perf_counter()
        for action in agent_actions[lo:lo + chunk]:
            single.step(action)  # goes on after the end of an episode, in the same house
        times[0] += time.perf_counter() - start
        start = time.perf_counter()
        for action, user_action in zip(agent_actions[lo:lo + chunk], user_actions[lo:lo + chunk]):
            _step_on(double, action, user_action)
        times[1] += time.perf_counter() - start
    single.close()
    double.close()
    n = len(agent_actions) - WARMUP
    return n / times[0], n / times[1]


def _step_on(env: HouseholdParallelEnv, action: str, user_action: str | None) -> None:
    env.step({"user": user_action, "agent": action})
    if not env.agents:  # the episode ended: go on in the same house, as the single-agent loop does
        env.agents = list(env.possible_agents)


def bench(env_id: str, steps: int, size: int, repeats: int, user: str = "random", chunk: int = 50,
          distance_info: bool | None = None) -> dict:
    """``distance_info`` None: each env's default (on in the single-agent env, off in the
    multi-agent env); True or False: that, in both."""
    kwargs = {**id_kwargs(env_id), "width": size, "height": size}
    if distance_info is not None:
        kwargs["distance_info"] = distance_info
    agent_actions = random_actions(steps + WARMUP, 1)
    user_actions = random_actions(steps + WARMUP, 2) if user == "random" else [None] * (steps + WARMUP)
    rounds = [bench_round(kwargs, agent_actions, user_actions, chunk) for _ in range(repeats)]
    s, d = statistics.median(r[0] for r in rounds), statistics.median(r[1] for r in rounds)
    return {"single": s, "two": d, "ratio": d / s, "rounds": [b / a for a, b in rounds]}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--ids", default=DEFAULT_IDS)
    parser.add_argument("--steps", type=int, default=1000)
    parser.add_argument("--size", type=int, default=96)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--user", choices=("random", "still"), default="random")
    parser.add_argument("--distance-info", action="store_true",
                        help="both envs measure info['distance_to_goal'] every step (default: each env's default)")
    args = parser.parse_args(argv)
    if args.steps < 1 or args.repeats < 1:
        parser.error("--steps and --repeats must be positive")
    pin_to_one_core()
    print(f"{'env id':36s} {'1-agent/s':>10} {'2-agent/s':>10} {'ratio':>6}  per round")
    for env_id in args.ids.split(","):
        r = bench(env_id, args.steps, args.size, args.repeats, args.user, distance_info=args.distance_info or None)
        rounds = " ".join(f"{x:.2f}" for x in r["rounds"])
        print(f"{env_id:36s} {r['single']:>10.0f} {r['two']:>10.0f} {r['ratio']:>6.2f}  {rounds}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""What the people cost a step: the animation (poses written every step) and the arm's IK.

    python benchmarks/people.py [--episodes 20]

Runs expert episodes (ComeHere-TwoRoom and BringMe-OneRoom, which reaches for, carries and
hands over an object) on one core, and times what the people add to them: the poses
(:meth:`Animator.show`, :meth:`Body.keyframe`, which makes the carrying pose) and the
arm's reach (:meth:`ArmIK.towards`), with the IK (:meth:`ArmIK.solve`) inside them,
counted once.
Prints the milliseconds per env step of all of it and of the IK alone, next to the whole
step's time, and the IK's time per solve.
"""

from __future__ import annotations

import argparse
import time
from collections import defaultdict

import gymnasium as gym
from benchmarks_common import pin_to_one_core

import legent_gym  # noqa: F401
from legent_gym.agent.body import Body
from legent_gym.agent.motion import Animator, ArmIK
from legent_gym.wrappers import ExpertInfo

SPENT: dict[str, float] = defaultdict(float)
CALLS: dict[str, int] = defaultdict(int)
#: Timed calls in progress, per key: a call inside another of the same key is not counted
#: twice (the IK runs inside the animation's carrying pose, for one).
_DEPTH: dict[str, int] = defaultdict(int)


def _timed(owner, name: str, key: str) -> None:
    inner = getattr(owner, name)

    def wrapper(*args, **kwargs):
        _DEPTH[key] += 1
        start = time.perf_counter()
        try:
            return inner(*args, **kwargs)
        finally:
            _DEPTH[key] -= 1
            if _DEPTH[key] == 0:
                SPENT[key] += time.perf_counter() - start
                CALLS[key] += 1

    setattr(owner, name, wrapper)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--episodes", type=int, default=20)
    args = parser.parse_args()
    pin_to_one_core()
    # "people": everything the people add to a step (poses, the carrying pose, the arm's
    # reach towards what an interaction aims at, the IK inside them); "ik": the IK alone.
    for owner, name in ((Animator, "show"), (Body, "keyframe"), (ArmIK, "towards")):
        _timed(owner, name, "people")
    _timed(ArmIK, "solve", "ik")
    print(f"{'env id':34} {'steps':>6} {'step ms':>8} {'people ms/step':>15} {'ik ms/step':>11} "
          f"{'ik ms/solve':>12}")
    for env_id in ("Legent/ComeHere-TwoRoom-v0", "Legent/BringMe-OneRoom-v0"):
        env = ExpertInfo(gym.make(env_id))
        SPENT.clear()
        CALLS.clear()
        steps, stepping = 0, 0.0
        for seed in range(args.episodes):
            _, info = env.reset(seed=seed)
            done = False
            while not done:
                start = time.perf_counter()
                _, _, term, trunc, info = env.step(info["expert_action"])
                stepping += time.perf_counter() - start
                steps += 1
                done = term or trunc
        env.close()
        ik_calls = max(CALLS["ik"], 1)
        print(f"{env_id:34} {steps:6d} {stepping / steps * 1e3:8.3f} {SPENT['people'] / steps * 1e3:15.4f} "
              f"{SPENT['ik'] / steps * 1e3:11.4f} {SPENT['ik'] / ik_calls * 1e3:12.3f}")


if __name__ == "__main__":
    main()

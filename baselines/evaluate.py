"""The shared evaluation loop: a policy, an environment id, a number of episodes, a seed.

A policy is any object with ``reset(instruction)`` (a new episode begins) and
``act(observation) -> str`` (the next step as action code, e.g. ``"move_forward(1.5)"``);
see :class:`Policy`. Episode ``i`` resets the environment with seed ``seed + i``, so the
houses, goals and instructions depend on the seed only, and a policy whose own randomness
is seeded (through an optional ``seed(seed)`` method, called once before the first
episode) gives the same result every run::

    from baselines.evaluate import RandomPolicy, evaluate
    evaluate(RandomPolicy(), "Legent/ComeHere-OneRoom-v0", episodes=100, seed=0)  # the success rate

Success is the environment's own rule (``info["success"]`` when the episode ends), under
its step cap (25 actions, the paper's). From the shell::

    python baselines/evaluate.py --policy random --env Legent/ComeHere-OneRoom-v0 --episodes 100
    python baselines/evaluate.py --policy vlm:runs/vlm/final --episodes 100   # a fine-tuned VLM (baselines/vlm)

The command runs the episodes in seeded chunks (:func:`baselines.vla.evaluate.evaluate_many`:
the random policy is seeded per chunk of 10) on ``--workers`` worker processes or, with
``--backend ray`` (``--ray-address auto|HOST:PORT``; default: a Ray started on this
machine), as Ray tasks; the results do not depend on either (see ``docs/scale.md``).
"""

from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Sequence
from dataclasses import asdict
from pathlib import Path

if __package__ in (None, ""):  # run as a script: make `baselines` importable
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from baselines.episodes import (  # noqa: E402
    EpisodeResult,
    ExpertBaseline,
    Policy,
    RandomPolicy,
    check_counts,
    evaluate,
    expert_takeover,
    run_episodes,
)
from baselines.vla.evaluate import evaluate_many  # noqa: E402
from legent_gym.utils.scale import Backend, BackendUnavailable  # noqa: E402

__all__ = ["EpisodeResult", "ExpertBaseline", "Policy", "RandomPolicy", "evaluate", "expert_takeover", "main",
           "run_episodes"]


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description="Evaluate a baseline policy (success rate over seeded episodes).")
    parser.add_argument("--policy", default="random",
                        help="'random', or vlm:PATH: a fine-tuned Hugging Face VLM folder (baselines/vlm)")
    parser.add_argument("--env", default="Legent/ComeHere-OneRoom-v0")
    parser.add_argument("--episodes", type=int, default=100)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--width", type=int, default=None)
    parser.add_argument("--height", type=int, default=None)
    parser.add_argument("--json", action="store_true", help="print every episode as JSON")
    parser.add_argument("--workers", type=int, default=1, help="worker processes (with --backend ray: 2 K tasks in flight; a local Ray gets K CPUs)")
    parser.add_argument("--backend", choices=["process", "ray"], default="process",
                        help="worker processes on this machine or Ray tasks (the scale extra)")
    parser.add_argument("--ray-address", help="with --backend ray: 'auto' or HOST:PORT (default: start a local Ray)")
    args = parser.parse_args(argv)
    env_kwargs = {k: v for k, v in (("width", args.width), ("height", args.height)) if v is not None}

    try:
        if args.policy != "random" and not args.policy.startswith("vlm:"):
            raise ValueError(f"--policy must be 'random' or vlm:PATH, got {args.policy!r}")
        if args.policy.startswith("vlm:") and not env_kwargs:  # the view size the model was trained on
            from baselines.vlm.policy import view_size  # imports torch: only for a VLM

            env_kwargs = view_size(args.policy)
        backend = Backend(args.backend, args.ray_address)
        backend.check()
        check_counts(args.episodes, args.seed)
        (results,) = evaluate_many([(args.policy, args.env)], args.episodes, args.seed, env_kwargs, args.workers,
                                   backend)
    except (ValueError, BackendUnavailable) as err:
        print(f"evaluate: error: {err}", file=sys.stderr)
        return 2
    if args.json:
        for r in results:
            print(json.dumps(asdict(r)))
    rate = sum(r.success for r in results) / len(results)
    print(f"{args.policy} on {args.env}: success {rate:.3f} over {len(results)} episodes (seed {args.seed})")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

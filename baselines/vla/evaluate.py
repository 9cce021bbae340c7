"""Success rates of the VLA (and of the random and expert bounds) on seeded episodes.

Episode ``i`` of an evaluation resets the env with seed ``seed + i`` (as
:func:`baselines.evaluate.run_episodes` does), in chunks of :data:`CHUNK` episodes that
worker processes share out. Each chunk is a ``run_episodes`` call of its own, so a policy
with its own randomness (the random baseline) is seeded per chunk and the result does not
depend on the number of workers::

    python -m baselines.vla.evaluate --policy runs/vla/come1/model.pt \\
        --env Legent/ComeHere-OneRoom-v0 --episodes 100 --seed 0 --workers 2

``--policy`` is a checkpoint, ``random``, ``expert`` (the task expert, privileged) or
``vlm:PATH``, a fine-tuned Hugging Face VLM folder (:mod:`baselines.vlm`).
``--env-kwargs`` passes further ``gym.make`` arguments as JSON, e.g. LEGENT's Where Is
questions: ``--env-kwargs '{"task_options": {"objects": ["orange"], "receptacles": ["sofa"]}}'``.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
from collections.abc import Sequence
from dataclasses import asdict

import gymnasium as gym

import legent_gym  # noqa: F401  (registers the environments)
from baselines.episodes import EpisodeResult, ExpertBaseline, RandomPolicy, run_episodes
from legent_gym.cli import parse_env_kwargs
from legent_gym.errors import UserError
from legent_gym.utils.scale import Backend
from legent_gym.utils.workers import map_ordered

CHUNK = 10
RANDOM, EXPERT = "random", "expert"
VLM = "vlm:"  # vlm:PATH, a model folder of baselines/vlm


def run_expert(env_id: str, episodes: int, seed: int, env_kwargs: dict | None = None) -> list[EpisodeResult]:
    """The task expert on the seeds ``run_episodes`` would use."""
    return run_episodes(ExpertBaseline(), env_id, episodes, seed, env_kwargs)


_policies: dict[str, object] = {}


def _policy(spec: str):
    """One policy object per spec and process (a checkpoint is loaded once per worker)."""
    if spec not in _policies:
        if spec == RANDOM:
            _policies[spec] = RandomPolicy()
        else:
            # torch (the baselines extra) takes seconds to import: only when a model runs
            from baselines.vla.policy import VLAPolicy

            _policies[spec] = VLAPolicy(spec)
    return _policies[spec]


def _init_worker() -> None:
    # torch (the baselines extra) takes seconds to import: only when a model runs
    import torch

    torch.set_num_threads(1)  # the workers are the parallelism


def run_chunk(spec: str, env_id: str, seed: int, episodes: int, env_kwargs: dict) -> list[EpisodeResult]:
    if spec.startswith(VLM):  # a fine-tuned Hugging Face VLM (baselines/vlm): batched decoding
        # transformers (the vlm extra): only for a vlm:PATH policy
        from baselines.vlm.policy import run_chunk as run_vlm_chunk

        return run_vlm_chunk(spec, env_id, seed, episodes, env_kwargs)
    if spec == EXPERT:
        return run_expert(env_id, episodes, seed, env_kwargs)
    return run_episodes(_policy(spec), env_id, episodes, seed, env_kwargs)


def _chunks(episodes: int, seed: int) -> list[tuple[int, int]]:
    return [(seed + start, min(CHUNK, episodes - start)) for start in range(0, episodes, CHUNK)]


def check_policy(spec: str) -> str:
    if spec in (RANDOM, EXPERT):
        return spec
    if spec.startswith(VLM):
        # transformers (the vlm extra): only for a vlm:PATH policy
        from baselines.vlm.policy import check_spec

        return check_spec(spec)
    if not os.path.isfile(spec):
        raise FileNotFoundError(f"policy {spec!r} is neither 'random', 'expert' nor a checkpoint file")
    return os.path.abspath(spec)


def evaluate_many(jobs: Sequence[tuple[str, str]], episodes: int, seed: int, env_kwargs: dict,
                  workers: int = 1, backend: Backend | str | None = None) -> list[list[EpisodeResult]]:
    """Episode results for each ``(policy spec, env id)`` job, in the order given.

    All jobs use the seeds ``seed .. seed + episodes - 1``, so every policy meets the same
    houses, goals and instructions. ``backend`` (``"process"``, ``"ray"`` or a
    :class:`legent_gym.utils.scale.Backend`) says where the chunks run; the results do not
    depend on it."""
    if isinstance(episodes, bool) or not isinstance(episodes, int) or episodes < 1:
        raise ValueError(f"episodes must be a positive integer, got {episodes!r}")
    if workers < 1:
        raise ValueError(f"workers must be >= 1, got {workers}")
    jobs = [(check_policy(spec), env_id) for spec, env_id in jobs]
    for _, env_id in jobs:
        if env_id not in gym.registry:
            raise ValueError(f"unknown environment id {env_id!r}")
    calls = [(j, (spec, env_id, s, n, env_kwargs)) for j, (spec, env_id) in enumerate(jobs)
             for s, n in _chunks(episodes, seed)]
    results: list[list[EpisodeResult]] = [[] for _ in jobs]
    chunks = map_ordered(run_chunk, [args for _, args in calls], workers=workers, initializer=_init_worker,
                         backend=backend)
    for chunk, (j, _) in zip(chunks, calls, strict=True):
        results[j] += chunk
    return results


def success_rate(results: Sequence[EpisodeResult]) -> float:
    return sum(r.success for r in results) / len(results)


def main(argv: Sequence[str] | None = None) -> int:
    p = argparse.ArgumentParser(description="Success rate of a VLA checkpoint, 'random' or 'expert'.")
    p.add_argument("--policy", required=True, help="a checkpoint (model.pt), 'random', 'expert' or vlm:PATH")
    p.add_argument("--env", action="append", required=True, help="environment id; repeat for several")
    p.add_argument("--episodes", type=int, default=100)
    p.add_argument("--seed", type=int, default=0, help="episode i resets with seed + i")
    p.add_argument("--image-size", type=int, help="view size for random/expert (a checkpoint knows its own)")
    p.add_argument("--workers", type=int, default=1)
    p.add_argument("--env-kwargs", help="JSON object of further gym.make arguments (e.g. task_options)")
    p.add_argument("--json", action="store_true", help="print every episode as JSON")
    args = p.parse_args(argv)
    try:
        spec = check_policy(args.policy)
        if spec in (RANDOM, EXPERT) or spec.startswith(VLM):
            size = args.image_size
        else:
            # torch (the baselines extra) takes seconds to import: only when a model runs
            from baselines.vla.checkpoint import read_checkpoint

            size = read_checkpoint(spec)["config"]["image_size"]
        env_kwargs = {"width": size, "height": size} if size else {}
        if spec.startswith(VLM) and not size:  # the view size the model was trained on
            # transformers (the vlm extra): only for a vlm:PATH policy
            from baselines.vlm.policy import view_size

            env_kwargs = view_size(spec)
        env_kwargs.update(parse_env_kwargs(args.env_kwargs))
        all_results = evaluate_many([(spec, e) for e in args.env], args.episodes, args.seed, env_kwargs,
                                    args.workers)
    except (FileNotFoundError, ValueError, UserError) as err:
        print(f"evaluate: error: {err}", file=sys.stderr)
        return 2
    for env_id, results in zip(args.env, all_results):
        if args.json:
            for r in results:
                print(json.dumps(asdict(r)))
        print(f"{args.policy} on {env_id}: success {success_rate(results):.3f} over {len(results)} episodes "
              f"(seeds {args.seed}..{args.seed + args.episodes - 1})")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

"""DAgger for the VLA: the trained model drives, the expert labels every state it reaches.

Behaviour cloning only sees states on the expert's own paths. A cloned policy drifts off
them (it walks into a bed the expert would have gone round; it answers "where is" before
the object is in view) and then meets states no demonstration shows. DAgger (Ross et al.,
2011) rolls the learner out, labels each state it visits with the expert's action, and
trains on the union of the demonstrations and these labelled states::

    python -m baselines.vla.dagger --policy runs/vla/come1/model.pt \\
        --env Legent/ComeHere-OneRoom-v0 --episodes 3000 --seed 20000000 \\
        --out runs/data/ComeHere-OneRoom-dagger1 --workers 2
    python -m baselines.vla.train --data runs/data/ComeHere-OneRoom \\
        --data runs/data/ComeHere-OneRoom-dagger1 --out runs/vla/come1-dagger1

Every rollout is kept, failed ones most of all: their states are the ones the learner
gets stuck in. The output is the LEGENT format of ``legent-gym collect`` (``legent/``
with ``interleaved.jsonl``): each step records what the learner executed and, as its
target, what the expert would have done. Rollout ``k`` resets with seed ``seed + k``; the
learner decodes greedily, so the data depends on the checkpoint and the seeds alone, not
on the number of workers. The folder is written whole or not at all (a temporary folder
renamed into place); a finished folder is not collected again.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import sys
import time
from collections.abc import Iterator, Sequence
from dataclasses import asdict, dataclass, field
from pathlib import Path

import gymnasium as gym
from tqdm import tqdm

import legent_gym  # noqa: F401  (registers the environments)
from legent_gym.cli import parse_env_kwargs
from legent_gym.data.legent_format import LegentWriter, episode_pngs
from legent_gym.data.rollout import Episode, make_env, record_episode
from legent_gym.errors import UserError
from legent_gym.experts.planners import FIND_STRATEGIES
from legent_gym.utils.workers import map_ordered

#: Rollouts per task handed to a worker at a time.
CHUNK = 25
SUMMARY = "dagger.json"


class DaggerError(ValueError):
    """Bad arguments for a DAgger collection (the message names the argument)."""


class LearnerDriver:
    """A :class:`~baselines.vla.policy.VLAPolicy` as the ``(obs, info) -> action`` callable
    that :func:`~legent_gym.data.rollout.record_episode` plays: it starts a new episode
    (the policy's window and instruction) when the env reports no actions yet."""

    def __init__(self, checkpoint: str):
        # torch (the baselines extra) takes seconds to import: only when a model runs
        from baselines.vla.policy import VLAPolicy

        self.policy = VLAPolicy(checkpoint)

    def __call__(self, obs: dict, info: dict) -> str:
        if int(info.get("n_actions", 0)) == 0:
            self.policy.reset(str(obs["instruction"]))
        return self.policy.act(obs)


@dataclass(frozen=True)
class DaggerConfig:
    policy: str
    env_id: str
    out: str
    episodes: int
    seed: int
    workers: int = 1
    find_strategy: str = "direct"
    #: Further ``gym.make`` arguments of the rollouts' env, as ``legent-gym collect
    #: --env-kwargs`` takes them (e.g. ``task_options``: roll out on the task the data asks).
    env_kwargs: dict = field(default_factory=dict)

    def __post_init__(self) -> None:
        if not os.path.isfile(self.policy):
            raise DaggerError(f"--policy {self.policy!r} is not a checkpoint file")
        if self.env_id not in gym.registry:
            raise DaggerError(f"unknown environment id {self.env_id!r}")
        if self.episodes < 1:
            raise DaggerError(f"--episodes must be >= 1, got {self.episodes}")
        if self.workers < 1:
            raise DaggerError(f"--workers must be >= 1, got {self.workers}")
        if self.find_strategy not in FIND_STRATEGIES:
            raise DaggerError(f"--find-strategy must be one of {', '.join(FIND_STRATEGIES)}, "
                              f"got {self.find_strategy!r}")
        if not isinstance(self.env_kwargs, dict):
            raise DaggerError(f"--env-kwargs must be a JSON object, got {self.env_kwargs!r}")
        fixed = sorted({"width", "height"} & set(self.env_kwargs))
        if fixed:
            raise DaggerError(f"--env-kwargs may not set {', '.join(fixed)}: the views are the "
                              "checkpoint's image size")
        try:
            json.dumps(self.env_kwargs)
        except (TypeError, ValueError) as err:
            raise DaggerError(f"--env-kwargs must be JSON values (they are stored with the data): {err}") from None


_worker: tuple | None = None


def _init_worker(config: DaggerConfig) -> None:
    # torch (the baselines extra) takes seconds to import: only when a model runs
    import torch

    # torch (the baselines extra) takes seconds to import: only when a model runs
    from baselines.vla.checkpoint import read_checkpoint

    torch.set_num_threads(1)  # the workers are the parallelism
    global _worker
    size = read_checkpoint(config.policy)["config"]["image_size"]
    env = make_env(config.env_id, {**config.env_kwargs, "width": size, "height": size}, expert=True,
                   find_strategy=config.find_strategy)
    _worker = (env, LearnerDriver(config.policy), config.env_id)


def _close_worker() -> None:
    global _worker
    _worker[0].close()
    _worker = None  # and let the model go


def _roll_out(start: int, count: int, seed: int) -> list[tuple[Episode, list[bytes]]]:
    env, driver, env_id = _worker
    done = []
    for k in range(start, start + count):
        episode = record_episode(env, driver, seed=seed + k, attempt=k, env_id=env_id, expert_labels=True)
        pngs = episode_pngs(episode)
        episode.observations = []  # the images travel as PNGs
        done.append((episode, pngs))
    return done


def _rollouts(config: DaggerConfig) -> Iterator[tuple[Episode, list[bytes]]]:
    chunks = [(s, min(CHUNK, config.episodes - s), config.seed) for s in range(0, config.episodes, CHUNK)]
    if config.workers == 1:
        _init_worker(config)
        try:
            for chunk in chunks:
                yield from _roll_out(*chunk)
        finally:
            _close_worker()
        return
    for done in map_ordered(_roll_out, chunks, workers=config.workers, initializer=_init_worker, initargs=(config,)):
        yield from done


def _template(text: str) -> str | None:
    """Which action a step is, numbers aside (None for text that does not parse)."""
    # torch (the baselines extra) takes seconds to import: only when a model runs
    from baselines.vla.codec import ActionCodec

    decomposed = ActionCodec.encode(text)
    return None if decomposed is None else decomposed.template


def _data_arguments(config: dict) -> dict:
    # Everything the rollouts depend on: the worker count does not change them. A summary
    # written before env_kwargs existed rolled out with none.
    return {"env_kwargs": {}, **{k: v for k, v in config.items() if k != "workers"}}


def collect_dagger(config: DaggerConfig, show_progress: bool = True) -> dict:
    """Roll out ``config.policy`` and write the expert-labelled rollouts to
    ``config.out/legent``; returns the summary (also ``config.out/dagger.json``). A folder
    that already holds this collection (the same arguments, whatever the worker count) is
    left as it is."""
    out = Path(config.out)
    summary_path = out / SUMMARY
    if summary_path.is_file():
        summary = json.loads(summary_path.read_text())
        if _data_arguments(summary.get("config") or {}) == _data_arguments(asdict(config)):
            return summary
        raise DaggerError(f"{out} holds a DAgger collection with other arguments "
                          f"({summary.get('config')}): use a new --out")
    if out.exists() and any(out.iterdir()):
        raise DaggerError(f"{out} exists and is not a finished DAgger collection: use a new --out")
    temp = out.with_name(f".{out.name}.tmp")
    shutil.rmtree(temp, ignore_errors=True)
    writer = LegentWriter(temp / "legent")
    writer.resume(0)
    began = time.monotonic()
    successes = steps = disagreements = 0
    with tqdm(total=config.episodes, desc=f"dagger {config.env_id}", disable=not show_progress) as bar:
        for index, (episode, pngs) in enumerate(_rollouts(config)):
            writer.write(episode, index, pngs)
            successes += episode.success
            steps += episode.steps
            disagreements += sum(_template(a) != _template(b) for a, b in zip(episode.action_texts, episode.labels))
            bar.update(1)
    writer.checkpoint()
    # steps_unlike_expert: steps whose template (which action, numbers aside) is not the expert's.
    summary = {"config": asdict(config), "episodes": config.episodes, "learner_success": successes / config.episodes,
               "steps": steps, "steps_unlike_expert": disagreements,
               "seconds": round(time.monotonic() - began, 1)}
    (temp / SUMMARY).write_text(json.dumps(summary, indent=1))
    if out.exists():
        out.rmdir()  # empty (checked above)
    os.rename(temp, out)
    return summary


def main(argv: Sequence[str] | None = None) -> int:
    p = argparse.ArgumentParser(description="Roll out a VLA checkpoint and label every state with the expert (DAgger).")
    p.add_argument("--policy", required=True, help="the learner: a checkpoint (model.pt)")
    p.add_argument("--env", required=True, help="environment id, e.g. Legent/ComeHere-OneRoom-v0")
    p.add_argument("--episodes", type=int, required=True, help="rollouts (all kept, failed or not)")
    p.add_argument("--seed", type=int, required=True, help="rollout k resets with seed + k (use training seeds)")
    p.add_argument("--out", required=True, help="output folder (LEGENT format under legent/)")
    p.add_argument("--workers", type=int, default=1)
    p.add_argument("--find-strategy", default="direct", help="the labelling expert's find(a): direct or scan")
    p.add_argument("--env-kwargs", help="further gym.make arguments as a JSON object, as for legent-gym collect "
                                        "(e.g. '{\"task_options\": {\"objects\": [\"apple\"]}}')")
    p.add_argument("--quiet", action="store_true")
    args = p.parse_args(argv)
    try:
        env_kwargs = parse_env_kwargs(args.env_kwargs)
        summary = collect_dagger(DaggerConfig(args.policy, args.env, args.out, args.episodes, args.seed,
                                              args.workers, args.find_strategy, env_kwargs),
                                 show_progress=not args.quiet)
    except (DaggerError, UserError) as err:
        print(f"dagger: error: {err}", file=sys.stderr)
        return 2
    print(f"dagger {args.env}: {summary['episodes']} rollouts, learner success {summary['learner_success']:.2f}, "
          f"{summary['steps_unlike_expert']} of {summary['steps']} steps not the expert's kind of action, "
          f"{summary['seconds']:.0f} s -> {args.out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

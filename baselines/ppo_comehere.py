"""stable-baselines3 PPO on ComeHere: images + instruction tokens in, continuous actions out,
the dense reward, seeded; a learning curve against a random policy on the same envs.

The env is ``Legent/ComeHere-OneRoom-v0`` with ``action_type="continuous"`` and
``reward="dense"`` (progress along the geodesic distance to the user, -0.01 a step, +10 on
success), seen through our SB3 wrappers: :class:`~legent_gym.wrappers.InstructionTokens`
(the instruction as word ids) and :class:`~legent_gym.wrappers.FlatActions` (a ``Box(4)``:
move, turn, tilt, interact). The policy reads the image with SB3's NatureCNN and the
instruction with a bag of word embeddings (:class:`ImageInstructionExtractor`).

Written to ``--out`` (default ``out/ppo_comehere``):

* ``ppo_curve.csv``: one row per rollout: ``policy,timesteps,episodes,success_rate,mean_return``
  over the training episodes that ended in it, and a ``random`` row: uniformly random actions
  on the same envs (same seeds, same wrappers) before training;
* ``ppo_curve.png``: both, success rate and return against timesteps;
* ``ppo_summary.json``: the configuration, wall time, and a final evaluation of the trained
  policy (greedy and sampled) and of :class:`~baselines.evaluate.RandomPolicy` on the same
  held-out seeds, through :func:`baselines.evaluate.run_episodes`.

Run (the figures in ``docs/results.md`` came from the command given there)::

    python baselines/ppo_comehere.py --timesteps 250000 --out out/ppo_comehere
"""

from __future__ import annotations

import argparse
import csv
import io
import json
import sys
import time
from collections.abc import Sequence
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

if __package__ in (None, ""):  # run as a script: make `baselines` importable
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import gymnasium as gym  # noqa: E402
import numpy as np  # noqa: E402

import legent_gym  # noqa: F401, E402  (registers the environments)
from baselines.episodes import RandomPolicy, run_episodes  # noqa: E402
from legent_gym.agent.actions import ActionLimits  # noqa: E402
from legent_gym.utils.atomic import atomic_write_bytes, atomic_write_text  # noqa: E402
from legent_gym.wrappers import FlatActions, InstructionTokens  # noqa: E402
from legent_gym.wrappers.sb3 import flat_action_text, tokenize  # noqa: E402

try:
    import torch
    from stable_baselines3 import PPO
    from stable_baselines3.common.base_class import BaseAlgorithm
    from stable_baselines3.common.callbacks import BaseCallback
    from stable_baselines3.common.env_util import make_vec_env
    from stable_baselines3.common.torch_layers import BaseFeaturesExtractor, NatureCNN
    from stable_baselines3.common.vec_env import DummyVecEnv, VecEnv
except ImportError as err:  # pragma: no cover - depends on the installed extras
    raise ImportError(f"the PPO baseline needs the 'baselines' extra ({err.name} is missing): "
                      "pip install -e '.[baselines]'") from None

ENV_ID = "Legent/ComeHere-OneRoom-v0"
CSV_FIELDS = ("policy", "timesteps", "episodes", "success_rate", "mean_return")
#: Rollouts per point of the plotted trend line.
SMOOTH = 10
#: Reset seeds of the final evaluation start here, far from the training envs' seeds.
EVAL_SEED_OFFSET = 100_000


@dataclass(frozen=True)
class Config:
    env_id: str = ENV_ID
    timesteps: int = 250_000
    seed: int = 0
    width: int = 48
    height: int = 48
    n_envs: int = 8
    n_steps: int = 128
    batch_size: int = 256
    n_epochs: int = 4
    learning_rate: float = 3e-4
    gamma: float = 0.99
    ent_coef: float = 0.0
    vocab_size: int = 1024
    max_tokens: int = 16
    random_episodes: int = 300
    eval_episodes: int = 200
    threads: int = 1

    def __post_init__(self) -> None:
        for name in ("timesteps", "n_envs", "n_steps", "batch_size", "n_epochs", "threads", "width", "height"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, int) or value < 1:
                raise ValueError(f"{name} must be a positive integer, got {value!r}")
        if min(self.width, self.height) < 36:
            raise ValueError(f"NatureCNN needs images of at least 36 x 36 pixels, got {self.width} x {self.height}")
        if self.seed < 0 or self.random_episodes < 0 or self.eval_episodes < 0:
            raise ValueError("seed, random_episodes and eval_episodes must be non-negative")

    def env_kwargs(self) -> dict[str, Any]:
        return {"width": self.width, "height": self.height, "reward": "dense"}


def make_env(config: Config) -> gym.Env:
    """The training env: continuous actions, dense reward; image and instruction tokens only
    (in ComeHere the ``message`` observation repeats the instruction)."""
    env = gym.make(config.env_id, action_type="continuous", **config.env_kwargs())
    env = gym.wrappers.FilterObservation(env, ["rgb", "instruction"])
    return FlatActions(InstructionTokens(env, config.vocab_size, config.max_tokens))


def make_vec(config: Config) -> VecEnv:
    return make_vec_env(lambda: make_env(config), n_envs=config.n_envs, seed=config.seed, vec_env_cls=DummyVecEnv)


class ImageInstructionExtractor(BaseFeaturesExtractor):
    """NatureCNN features of the image, joined with the mean embedding of the instruction's
    word ids (raw ids fed to an MLP, SB3's default for a Box, would be meaningless numbers)."""

    def __init__(self, observation_space: gym.spaces.Dict, cnn_dim: int = 256, embed_dim: int = 32):
        super().__init__(observation_space, features_dim=cnn_dim + embed_dim)
        self.cnn = NatureCNN(observation_space["rgb"], features_dim=cnn_dim)
        vocab = int(observation_space["instruction"].high.max()) + 1
        self.embed = torch.nn.EmbeddingBag(vocab, embed_dim, mode="mean", padding_idx=0)

    def forward(self, observations: dict[str, torch.Tensor]) -> torch.Tensor:
        return torch.cat([self.cnn(observations["rgb"]), self.embed(observations["instruction"].long())], dim=1)


@dataclass(frozen=True)
class CurvePoint:
    policy: str
    timesteps: int
    episodes: int
    success_rate: float
    mean_return: float


def _point(policy: str, timesteps: int, episodes: list[tuple[float, bool]]) -> CurvePoint:
    returns = [r for r, _ in episodes]
    return CurvePoint(policy, timesteps, len(episodes), float(np.mean([s for _, s in episodes])),
                      float(np.mean(returns)))


class CurveLogger(BaseCallback):
    """One :class:`CurvePoint` per rollout, over the training episodes that ended in it;
    the CSV and the plot are rewritten (atomically) after every rollout."""

    def __init__(self, out: Path, baseline: CurvePoint | None):
        super().__init__()
        self.out, self.baseline = out, baseline
        self.points: list[CurvePoint] = []
        self._ended: list[tuple[float, bool]] = []

    def _on_step(self) -> bool:
        for info in self.locals["infos"]:
            if "episode" in info:  # set by SB3's Monitor when an episode ends
                self._ended.append((float(info["episode"]["r"]), bool(info.get("success", False))))
        return True

    def _on_rollout_end(self) -> None:
        if self._ended:
            self.points.append(_point("ppo", self.num_timesteps, self._ended))
            self._ended = []
            write_curve(self.out, self.points, self.baseline)


def random_baseline(config: Config) -> CurvePoint:
    """Uniformly random actions on the training envs (same construction, same seeds)."""
    vec = make_vec(config)
    vec.action_space.seed(config.seed)
    vec.reset()
    ended: list[tuple[float, bool]] = []
    steps = 0
    while len(ended) < config.random_episodes:
        actions = np.stack([vec.action_space.sample() for _ in range(vec.num_envs)])
        _, _, dones, infos = vec.step(actions)
        steps += vec.num_envs
        ended += [(float(i["episode"]["r"]), bool(i.get("success", False))) for i, d in zip(infos, dones) if d]
    vec.close()
    return _point("random", steps, ended[:config.random_episodes])


class SB3Policy:
    """A trained model as a :class:`baselines.evaluate.Policy` (text actions, any env of the
    same image size): tokenises the instruction and maps the flat action to action code."""

    def __init__(self, model: BaseAlgorithm, config: Config, deterministic: bool = True):
        self.model, self.config, self.deterministic = model, config, deterministic
        self.limits = ActionLimits()
        self._tokens: np.ndarray | None = None

    def seed(self, seed: int) -> None:
        torch.manual_seed(seed)  # sampled actions come from torch's generator

    def reset(self, instruction: str) -> None:
        self._tokens = tokenize(instruction, self.config.vocab_size, self.config.max_tokens)

    def act(self, observation: dict[str, Any]) -> str:
        action, _ = self.model.predict({"rgb": observation["rgb"], "instruction": self._tokens},
                                       deterministic=self.deterministic)
        return flat_action_text(action, self.limits)


def final_evaluation(model: BaseAlgorithm, config: Config) -> dict[str, Any]:
    seed = EVAL_SEED_OFFSET + config.seed
    out = {"seeds": [seed, seed + config.eval_episodes - 1]}
    policies = {"ppo_greedy": SB3Policy(model, config, True), "ppo_sampled": SB3Policy(model, config, False),
                "random": RandomPolicy()}
    for name, policy in policies.items():
        results = run_episodes(policy, config.env_id, config.eval_episodes, seed, config.env_kwargs())
        out[name] = {"success_rate": float(np.mean([r.success for r in results])),
                     "mean_return": float(np.mean([r.episode_return for r in results])),
                     "mean_steps": float(np.mean([r.steps for r in results]))}
    return out


def write_curve(out: Path, points: list[CurvePoint], baseline: CurvePoint | None) -> None:
    rows = ([baseline] if baseline else []) + points
    buffer = io.StringIO()
    writer = csv.DictWriter(buffer, fieldnames=CSV_FIELDS, lineterminator="\n")
    writer.writeheader()
    for p in rows:
        writer.writerow({**asdict(p), "success_rate": f"{p.success_rate:.4f}", "mean_return": f"{p.mean_return:.4f}"})
    atomic_write_text(out / "ppo_curve.csv", buffer.getvalue())
    atomic_write_bytes(out / "ppo_curve.png", plot_curve(points, baseline))


def plot_curve(points: list[CurvePoint], baseline: CurvePoint | None, title: str = ENV_ID) -> bytes:
    """PNG bytes: success rate and mean return per rollout, the random policy dashed."""
    # start-up time: matplotlib only for the learning curve
    import matplotlib

    matplotlib.use("Agg")  # headless; no display here
    from matplotlib.figure import Figure

    fig = Figure(figsize=(9, 3.6), dpi=110)
    steps = [p.timesteps for p in points]
    for ax, key, label in zip(fig.subplots(1, 2), ("success_rate", "mean_return"),
                              ("episode success rate", "episode return (dense)")):
        values = np.array([getattr(p, key) for p in points])
        ax.plot(steps, values, color="C0", alpha=0.3, label="PPO, per rollout")
        if len(values) >= SMOOTH:  # a trailing mean over rollouts: the trend through the noise
            trend = np.convolve(values, np.ones(SMOOTH) / SMOOTH, mode="valid")
            ax.plot(steps[SMOOTH - 1:], trend, color="C0", label=f"PPO, mean of {SMOOTH} rollouts")
        if baseline is not None:
            ax.axhline(getattr(baseline, key), color="grey", linestyle="--", label="random policy")
        ax.set_xlabel("timesteps")
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
    fig.axes[0].set_ylim(0, 1)
    fig.axes[0].legend(loc="lower right")
    fig.suptitle(f"PPO on {title}")
    fig.tight_layout()
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png")
    return buffer.getvalue()


def train(config: Config, out: Path, save_model: Path | None = None) -> dict[str, Any]:
    """Train, log the curve, evaluate; returns (and writes) the summary."""
    torch.set_num_threads(config.threads)
    started = time.monotonic()
    baseline = random_baseline(config) if config.random_episodes else None
    vec = make_vec(config)
    model = PPO("MultiInputPolicy", vec, n_steps=config.n_steps, batch_size=config.batch_size,
                n_epochs=config.n_epochs, learning_rate=config.learning_rate, gamma=config.gamma,
                ent_coef=config.ent_coef, seed=config.seed, device="cpu",
                policy_kwargs={"features_extractor_class": ImageInstructionExtractor})
    logger = CurveLogger(out, baseline)
    model.learn(total_timesteps=config.timesteps, callback=logger)
    vec.close()
    if save_model is not None:
        model.save(save_model)
    write_curve(out, logger.points, baseline)  # also when no episode ended (a very short run)
    trained_s = time.monotonic() - started
    summary = {"config": asdict(config), "train_wall_s": round(trained_s, 1),
               "random_baseline": asdict(baseline) if baseline else None,
               "last_rollout": asdict(logger.points[-1]) if logger.points else None}
    if config.eval_episodes:
        summary["evaluation"] = final_evaluation(model, config)
    summary["total_wall_s"] = round(time.monotonic() - started, 1)
    atomic_write_text(out / "ppo_summary.json", json.dumps(summary, indent=2) + "\n")
    return summary


def main(argv: Sequence[str] | None = None) -> int:
    defaults = Config()
    parser = argparse.ArgumentParser(description="PPO on ComeHere with a learning curve against a random policy.")
    parser.add_argument("--timesteps", type=int, default=defaults.timesteps)
    parser.add_argument("--out", type=Path, default=Path("out/ppo_comehere"))
    parser.add_argument("--save-model", type=Path, default=None, help="also save the trained model (.zip)")
    for name in ("env_id", "seed", "width", "height", "n_envs", "n_steps", "batch_size", "n_epochs",
                 "learning_rate", "gamma", "ent_coef", "random_episodes", "eval_episodes", "threads"):
        default = getattr(defaults, name)
        parser.add_argument("--" + name.replace("_", "-"), type=type(default), default=default)
    args = parser.parse_args(argv)
    if __package__ in (None, ""):  # run as a file: make the repository root importable
        sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
    options = {k: v for k, v in vars(args).items() if k not in ("out", "save_model")}
    try:
        config = Config(**options)
    except ValueError as err:
        print(f"error: {err}", file=sys.stderr)
        return 2
    summary = train(config, args.out, args.save_model)
    print(json.dumps({k: summary[k] for k in ("random_baseline", "last_rollout", "evaluation", "total_wall_s")
                      if k in summary}, indent=2))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

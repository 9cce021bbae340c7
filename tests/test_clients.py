"""The third-party RL clients, driven as their users call them: stable-baselines3's
``check_env``, RL Baselines3 Zoo (its own command lines), SuperSuit + SB3 on the PettingZoo
envs, TorchRL's ``GymEnv``/``GymWrapper`` + ``check_env_specs``. The recipes of
docs/train-ppo.md and docs/multiagent.md are these (tests/test_docs_examples.py runs them as
written, RL Zoo's train and enjoy commands at a small step count)."""

from __future__ import annotations

import subprocess
import sys
import warnings

import gymnasium as gym
import numpy as np
import pytest
import yaml

import legent_gym  # noqa: F401  (registers the ids)
from legent_gym.wrappers import FlatActions, InstructionTokens, for_sb3

ENV_ID = "Legent/ComeHere-OneRoom-v0"
SMALL = {"width": 48, "height": 48}  # NatureCNN's smallest is 36 x 36


# -- stable-baselines3's check_env -------------------------------------------------------------
@pytest.mark.parametrize("action_type", ["text", "continuous"])
def test_sb3_check_env_passes_on_for_sb3(action_type):
    from stable_baselines3.common.env_checker import check_env

    env = for_sb3(gym.make(ENV_ID, action_type=action_type, **SMALL))
    assert isinstance(env, FlatActions) and isinstance(env.env, InstructionTokens)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a warning of check_env (an unsupported space...) fails
        check_env(env, warn=True)
    assert set(env.observation_space.spaces) == {"rgb", "instruction", "message"}
    assert all(isinstance(s, gym.spaces.Box) for s in env.observation_space.spaces.values())


def test_sb3_check_env_fails_on_the_raw_env():
    """The raw env is not SB3's: its Text observations are strings (what for_sb3 is for)."""
    from stable_baselines3.common.env_checker import check_env

    with pytest.raises(AssertionError, match="key=instruction"):
        check_env(gym.make(ENV_ID, **SMALL), warn=False)


# -- RL Baselines3 Zoo -------------------------------------------------------------------------
def test_rl_zoo_reads_the_shipped_hyperparameters():
    """The module RL Zoo's --conf-file imports holds the shipped YAML, whose wrapper RL Zoo
    resolves to a stack check_env passes."""
    from rl_zoo3.utils import get_wrapper_class
    from stable_baselines3.common.env_checker import check_env

    from legent_gym import hyperparams
    from legent_gym.hyperparams import ppo

    with open(hyperparams.path("ppo")) as f:
        assert ppo.hyperparams == yaml.safe_load(f)
    default = ppo.hyperparams["default"]
    assert default["policy"] == "MultiInputPolicy"
    wrapped = get_wrapper_class(default)(gym.make(ENV_ID, **SMALL))  # as RL Zoo wraps each env
    assert isinstance(wrapped, FlatActions) and isinstance(wrapped.env, InstructionTokens)
    check_env(wrapped, warn=False)
    with pytest.raises(ValueError, match="no hyperparameters for 'sac'"):
        hyperparams.path("sac")
    printed = subprocess.run([sys.executable, "-m", "legent_gym.hyperparams", "ppo"], capture_output=True,
                             text=True, check=True).stdout.strip()
    assert printed == str(hyperparams.path("ppo"))


def _zoo(module: str, *args: str, timeout: float = 600) -> str:
    """``python -m rl_zoo3.<module> ...`` (or a ``python -c`` program when ``module`` is
    code); the run's output, after checking it exited 0."""
    command = [sys.executable, "-m", f"rl_zoo3.{module}"] if "." not in module else [sys.executable, "-c", module]
    run = subprocess.run([*command, *args], capture_output=True, text=True, timeout=timeout)
    assert run.returncode == 0, f"{' '.join(command)} failed:\n{run.stdout[-3000:]}\n{run.stderr[-3000:]}"
    return run.stdout + run.stderr


def _train(folder, *extra: str) -> str:
    return _zoo("train", "--algo", "ppo", "--env", ENV_ID, "--gym-packages", "legent_gym",
                "--conf-file", "legent_gym.hyperparams.ppo", "-f", str(folder), "--seed", "0", "--device", "cpu",
                *extra)


def _trained(folder):
    run = folder / "ppo" / "Legent-ComeHere-OneRoom-v0_1"
    with open(run / "Legent-ComeHere-OneRoom-v0" / "config.yml") as f:
        config = dict(yaml.load(f, Loader=yaml.UnsafeLoader))
    return run, config


@pytest.mark.slow
def test_rl_zoo_trains_with_evaluation_and_records_a_video(tmp_path):
    """A few hundred steps with the file's env_kwargs (dense reward) and RL Zoo's evaluation
    env, then rl_zoo3.enjoy and rl_zoo3.record_video (which takes no --gym-packages: the
    documented python -c line imports legent_gym first)."""
    _train(tmp_path, "-n", "256", "--eval-freq", "128", "--eval-episodes", "2",
           "-params", "n_envs:2", "n_steps:64", "batch_size:64", "n_epochs:1")
    run, config = _trained(tmp_path)
    assert config["env_kwargs"] == {"reward": "dense"}
    evaluations = np.load(run / "evaluations.npz")
    assert evaluations["timesteps"].tolist() == [128, 256] and evaluations["results"].shape == (2, 2)
    out = _zoo("enjoy", "--algo", "ppo", "--env", ENV_ID, "--gym-packages", "legent_gym", "-f", str(tmp_path),
               "--no-render", "-n", "60", "--device", "cpu")
    assert "Episode Length" in out and "Mean reward" in out
    video = tmp_path / "videos"
    _zoo("import legent_gym, runpy; runpy.run_module('rl_zoo3.record_video', run_name='__main__')",
         "--algo", "ppo", "--env", ENV_ID, "-f", str(tmp_path), "-n", "30", "-o", str(video))
    assert [p.suffix for p in video.iterdir()] == [".mp4"]


# -- SuperSuit + stable-baselines3 on the PettingZoo envs ----------------------------------------
def _supersuit_vec(seed: int):
    ss = pytest.importorskip("supersuit")
    from legent_gym.multiagent import for_sb3 as ma_for_sb3
    from legent_gym.multiagent import parallel_env

    env = ma_for_sb3(parallel_env(task="ComeHere", layout="OneRoom", reward="dense", **SMALL))
    env.reset(seed=seed)  # SuperSuit's vec env cannot take a seed from SB3: seed the PettingZoo env
    vec = ss.concat_vec_envs_v1(ss.pettingzoo_env_to_vec_env_v1(env), 1, num_cpus=0, base_class="stable_baselines3")
    return env, vec


def test_supersuit_vec_env_trains_ppo():
    from stable_baselines3 import PPO
    from stable_baselines3.common.utils import set_random_seed

    env, vec = _supersuit_vec(seed=0)
    assert vec.num_envs == 2  # the user and the agent, one policy
    assert vec.observation_space == env.observation_space("agent") == env.observation_space("user")
    assert env.limits == env.unwrapped.episode.limits and env.limits.max_move > 0
    set_random_seed(0)
    model = PPO("MultiInputPolicy", vec, n_steps=16, batch_size=32, n_epochs=1, device="cpu")
    model.learn(32)
    assert model.num_timesteps == 32
    assert np.abs(model.rollout_buffer.rewards).sum() > 0  # the dense rewards reached the learner
    # The seeded PettingZoo env makes the vec env's episodes (SB3 resets it without a seed).
    a, b, c = (_supersuit_vec(seed)[1].reset() for seed in (3, 3, 4))
    assert all(np.array_equal(a[k], b[k]) for k in a) and not np.array_equal(a["rgb"], c["rgb"])


# -- TorchRL ----------------------------------------------------------------------------------
def test_torchrl_check_env_specs():
    torchrl_envs = pytest.importorskip("torchrl.envs")
    from torchrl.envs.utils import check_env_specs

    env = torchrl_envs.GymWrapper(for_sb3(gym.make(ENV_ID, **SMALL)))
    check_env_specs(env, seed=0)
    rollout = env.rollout(3)
    assert rollout["rgb"].shape[1:] == (48, 48, 3) and rollout["instruction"].shape[1:] == (16,)
    raw = torchrl_envs.GymEnv(ENV_ID, **SMALL)  # the raw env too: Text as non-tensor data
    check_env_specs(raw, seed=0)
    raw.set_seed(5)  # TorchRL resets the env with the seed here; its next reset goes on from it
    plain = gym.make(ENV_ID, **SMALL)
    plain.reset(seed=5)
    expected, _ = plain.reset()
    got = raw.reset()
    assert got["instruction"] == expected["instruction"] and got["message"] == expected["message"]
    assert np.array_equal(got["rgb"].numpy(), expected["rgb"])

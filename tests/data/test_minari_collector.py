"""Minari's own ``DataCollector`` on our envs, called as Minari's users call it.

The collector records with ``record_infos=True`` over several episodes (Minari's loop:
reset again after an episode ends, and once in the middle of one), including steps that
fail or do not parse; ``create_dataset``, ``recover_environment`` (the wrapper stack is
rebuilt from its recorded constructor arguments), and a replay of every episode from its
recorded seed and actions gives the recorded observations, rewards and infos exactly.
Also: the expert driving a collector (``ExpertPolicy`` outside it), and the one info
schema every env has at reset and after every step (what the collector needs).
"""

from __future__ import annotations

import gymnasium as gym
import jax
import minari
import numpy as np
import pytest

import legent_gym  # noqa: F401  (registers the ids)
from legent_gym.multiagent import make_single_agent
from legent_gym.wrappers import (
    ExpertInfo,
    ExpertPolicy,
    FlatActions,
    InstructionTokens,
    InterleavedHistory,
)
from tests.conftest import EXAMPLES

ENV_ID = "Legent/ComeHere-OneRoom-v0"
SIZE = 32
#: Actions mixed into the expert's: a failing grab, an unparsable string, a plain turn.
OTHER_ACTIONS = ("grab()", "jump(", "rotate_right(30)")
INFO_KEYS = {"agent_pose", "user_pose", "held", "task", "success", "distance_to_goal", "distance_to_user",
             "action_text", "action_ok", "action_results", "action_error", "attempts", "house_seed", "scene_name",
             "n_actions", "expert_action", "expert_problem", "goal_view"}


@pytest.fixture
def datasets(tmp_path, monkeypatch):
    monkeypatch.setenv("MINARI_DATASETS_PATH", str(tmp_path))
    return tmp_path


def _episodes(dataset):
    seeds = [int(m["seed"]) for m in dataset.storage.get_episode_metadata(range(dataset.total_episodes))]
    return list(zip(dataset.iterate_episodes(), seeds))


def _leaf(values, n):
    """Entry ``n`` of a recorded info column (hdf5 gives arrays, arrow arrays of bytes or str)."""
    value = values[n]
    return value.decode() if isinstance(value, bytes) else value


def _replay(env, episode, seed, *, compare_infos: bool):
    """Reset ``env`` with the episode's seed and step its actions: everything recorded comes back."""
    obs, info = env.reset(seed=seed)
    for n in range(len(episode.actions) + 1):
        if n > 0:
            obs, reward, terminated, _, info = env.step(_leaf(episode.actions, n - 1))
            assert reward == episode.rewards[n - 1] and terminated == episode.terminations[n - 1]
        assert np.array_equal(obs["rgb"], episode.observations["rgb"][n]), f"step {n}: other pixels"
        assert obs["instruction"] == _leaf(episode.observations["instruction"], n)
        assert obs["message"] == _leaf(episode.observations["message"], n)
        if compare_infos:
            for key in ("success", "held", "n_actions", "action_text", "action_ok", "action_results",
                        "action_error", "expert_action", "attempts", "house_seed"):
                assert info[key] == _leaf(episode.infos[key], n), (key, n)
            assert info["distance_to_goal"] == pytest.approx(float(episode.infos["distance_to_goal"][n]))


@pytest.mark.parametrize("data_format", ["hdf5", "arrow"])
def test_data_collector_records_infos_recovers_the_env_and_replays_exactly(datasets, data_format):
    env = minari.DataCollector(ExpertInfo(gym.make(ENV_ID, width=SIZE, height=SIZE)), record_infos=True,
                               data_format=data_format, jpeg_encoding=False)
    obs, info = env.reset(seed=7)
    episodes = steps = 0
    while episodes < 4:
        action = OTHER_ACTIONS[steps % len(OTHER_ACTIONS)] if steps % 3 == 1 else info["expert_action"]
        obs, _, terminated, truncated, info = env.step(action)
        steps += 1
        if terminated or truncated or steps == 2:  # the second step: an episode cut short by a reset
            episodes += 1
            obs, info = env.reset()  # Minari draws a seed and records it
    dataset = env.create_dataset("legent/ComeHere-OneRoom/collector-v0", algorithm_name="expert")
    env.close()

    assert dataset.total_episodes == 4
    recovered = dataset.recover_environment()
    assert [w.name for w in recovered.spec.additional_wrappers] == ["ExpertInfo"]
    assert isinstance(recovered, ExpertInfo) and recovered.spec.kwargs["width"] == SIZE
    recorded = _episodes(dataset)
    assert recorded[0][0].truncations[-1] and not recorded[0][0].terminations[-1]  # cut short by the reset
    assert all(e.terminations[-1] for e, _ in recorded[1:])
    failed = [e for e, _ in recorded if not np.asarray(e.infos["action_ok"]).all()]
    assert failed and any(_leaf(e.infos["action_error"], n) for e in failed for n in range(len(e.actions) + 1))
    for episode, seed in recorded:
        assert set(episode.infos) == INFO_KEYS
        _replay(recovered, episode, seed, compare_infos=True)
    recovered.close()


def test_expert_policy_outside_a_collector_records_the_experts_demonstrations(datasets):
    collector = minari.DataCollector(gym.make("Legent/PickUp-OneRoom-v0", width=SIZE, height=SIZE),
                                     record_infos=True, jpeg_encoding=False)
    demo = ExpertPolicy(collector)
    taken = []
    for seed in (3, 4):
        _, info = demo.reset(seed=seed)
        taken.append([])
        while True:
            _, _, terminated, truncated, info = demo.step(None)
            taken[-1].append(info["action_taken"])
            if terminated or truncated:
                break
        assert info["success"]
    dataset = collector.create_dataset("legent/PickUp-OneRoom/expert-demos-v0")
    recovered = dataset.recover_environment()
    for (episode, seed), actions in zip(_episodes(dataset), taken, strict=True):
        assert [_leaf(episode.actions, n) for n in range(len(episode.actions))] == actions
        assert episode.infos["success"][-1]
        _replay(recovered, episode, seed, compare_infos=False)
    recovered.close()


def test_recover_environment_rebuilds_our_wrapper_stack_with_its_arguments(datasets):
    stack = FlatActions(InstructionTokens(InterleavedHistory(ExpertInfo(gym.make(ENV_ID, width=SIZE, height=SIZE),
                                                                        "scan"), k=2), max_tokens=8))
    env = minari.DataCollector(stack, jpeg_encoding=False)
    env.reset(seed=6)
    for action in ([0.5, -0.2, 0.0, 0.0], [0.1, 0.9, 0.1, 1.0]):
        env.step(np.asarray(action, np.float32))
    dataset = env.create_dataset("legent/ComeHere-OneRoom/stack-v0")
    env.close()
    recovered = dataset.recover_environment()
    assert [(w.name, w.kwargs) for w in recovered.spec.additional_wrappers] == [
        ("ExpertInfo", {"find_strategy": "scan"}), ("InterleavedHistory", {"k": 2, "max_text": 4000}),
        ("InstructionTokens", {"vocab_size": 1024, "max_tokens": 8}), ("FlatActions", {})]
    (episode, seed), = _episodes(dataset)
    obs, _ = recovered.reset(seed=seed)
    for n in range(len(episode.actions)):
        obs, *_ = recovered.step(episode.actions[n])
        assert np.array_equal(obs["history_rgb"], episode.observations["history_rgb"][n + 1])
        assert np.array_equal(obs["instruction"], episode.observations["instruction"][n + 1])
    recovered.close()


def test_minari_default_jpeg_images_differ_from_a_replay(datasets):
    """Why the docs say ``jpeg_encoding=False``: Minari's default stores JPEG images, which a
    replay of the same episode does not give back."""
    env = minari.DataCollector(ExpertInfo(gym.make(ENV_ID, width=SIZE, height=SIZE)))
    obs, info = env.reset(seed=1)
    frames = [obs["rgb"]]
    while True:
        obs, _, terminated, truncated, info = env.step(info["expert_action"])
        frames.append(obs["rgb"])
        if terminated or truncated:
            break
    dataset = env.create_dataset("legent/ComeHere-OneRoom/jpeg-v0")
    (episode, _), = _episodes(dataset)
    stored = episode.observations["rgb"]
    assert stored.shape == np.shape(frames)
    assert np.abs(stored.astype(int) - np.asarray(frames, dtype=int)).max() > 0
    env.close()


def _signature(info):
    """The info's pytree structure and leaf types: what Minari's collector needs to stay the same."""
    leaves, tree = jax.tree_util.tree_flatten(info, is_leaf=lambda x: x is None)
    return tree, [(type(x).__name__, getattr(x, "shape", None)) for x in leaves]


def _same_schema(make, policy, seeds, steps=6, autoreset=False):
    env = make()
    signature = None
    for seed in seeds:
        _, info = env.reset(seed=seed)
        for n in range(steps + 1):
            if signature is None:
                signature = _signature(info)
            assert _signature(info) == signature, (seed, n, sorted(info))
            assert all(v is not None for v in jax.tree_util.tree_leaves(info, is_leaf=lambda x: x is None))
            if n < steps:
                _, _, terminated, truncated, info = env.step(policy(info, n))
                if (terminated or truncated) and not autoreset:
                    break
    env.close()


def _mixed(info, n):
    return OTHER_ACTIONS[n % len(OTHER_ACTIONS)] if n % 2 else info["expert_action"]


@pytest.mark.parametrize("env_id", ["Legent/ComeHere-OneRoom-v0", "Legent/GoTo-OneRoom-v0",
                                    "Legent/PickUp-OneRoom-v0", "Legent/BringMe-OneRoom-v0",
                                    "Legent/WhereIs-OneRoom-v0", "Legent/PutOn-OneRoom-v0"])
def test_one_info_schema_at_reset_and_every_step_of_every_episode(env_id):
    """The same keys, nesting and types at reset, after every step (also an autoreset one) and in
    every episode; no None anywhere. Text actions and continuous ones; distances off; frames."""
    _same_schema(lambda: ExpertInfo(gym.wrappers.Autoreset(gym.make(env_id, width=SIZE, height=SIZE))), _mixed,
                 seeds=(0, 1, 2), steps=8, autoreset=True)
    _same_schema(lambda: ExpertPolicy(gym.make(env_id, width=SIZE, height=SIZE, action_type="continuous",
                                               distance_info=False, frames_per_step=2)),
                 lambda info, n: None, seeds=(0, 1))


def test_one_info_schema_in_a_custom_env_of_several_tasks():
    """Legent/Custom-v0 draws another kind of task each episode: still the same keys and types."""
    tasks = [{"kind": "come", "instruction": "Come here.", "code": "goto_user()"},
             {"kind": "where", "instruction": "Where is the apple?", "code": "find(26) speak('It is on the bed.')",
              "target": 26, "receptacle": 0},
             {"kind": "take", "instruction": "Take the book.", "code": "goto(35) target(35) interact()", "target": 35}]
    _same_schema(lambda: ExpertInfo(gym.make("Legent/Custom-v0", scene=str(EXAMPLES / "two_room_furnished.json"),
                                             tasks=tasks, task_options={"order": "sequential"},
                                             width=SIZE, height=SIZE)),
                 _mixed, seeds=(0, 1, 2), steps=3)


@pytest.mark.parametrize("learner", ["agent", "user"])
def test_one_info_schema_for_both_sides_of_the_multiagent_env(learner):
    _same_schema(lambda: make_single_agent("Legent/BringMe-TwoRoom-v0", partner="wander", learner=learner,
                                           width=SIZE, height=SIZE),
                 lambda info, n: ("grab()", "jump(", "move_forward(0.5), rotate_right(40)")[n % 3],
                 seeds=(0, 1), steps=4)

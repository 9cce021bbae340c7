"""Every registered environment, checked the way users and the ecosystem use them."""

from __future__ import annotations

import pickle

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import legent_gym
from legent_gym.envs.action_spaces import actions_to_dict
from legent_gym.tasks import TASKS

ENV_IDS = legent_gym.ENV_IDS
SMALL = {"width": 48, "height": 48}


def test_ids_are_registered():
    assert len(TASKS) >= 6 and len(ENV_IDS) == 3 * len(TASKS)
    for task in TASKS:
        for layout in ("OneRoom", "TwoRoom", "FourRoom"):
            spec = gym.spec(f"Legent/{task}-{layout}-v0")
            assert spec.max_episode_steps == 25
            assert isinstance(spec.entry_point, str)


@pytest.mark.parametrize("env_id", ENV_IDS)
@pytest.mark.parametrize("action_type", ["text", "continuous"])
def test_check_env(env_id, action_type):
    env = gym.make(env_id, action_type=action_type, **SMALL)
    check_env(env.unwrapped, skip_render_check=False)
    env.close()


def _policy_actions(env, n, seed):
    """A fixed sequence of sampled actions (text actions built from sampled dicts)."""
    rng = np.random.default_rng(seed)
    space = gym.make("Legent/ComeHere-OneRoom-v0", action_type="continuous").action_space
    space.seed(int(rng.integers(1 << 30)))
    out = []
    for _ in range(n):
        d = space.sample()
        d["finish"] = 0
        d["speak"] = ""
        out.append(d)
    if env.unwrapped.action_type == "text":
        from legent_gym.agent.actions import format_actions
        from legent_gym.envs.action_spaces import dict_to_actions

        return [format_actions(dict_to_actions(d)) or "rotate_right(0)" for d in out]
    return out


def _rollout(env_id, action_type, seed, steps=50):
    env = gym.make(env_id, action_type=action_type, **SMALL)
    obs, _ = env.reset(seed=seed)
    frames = [obs["rgb"]]
    infos = []
    for action in _policy_actions(env, steps, seed):
        obs, reward, terminated, truncated, info = env.step(action)
        frames.append(obs["rgb"])
        infos.append((reward, terminated, truncated, info["agent_pose"], info["held"], info["success"]))
        if terminated or truncated:
            obs, _ = env.reset()
            frames.append(obs["rgb"])
    env.close()
    return frames, infos


@pytest.mark.parametrize("env_id", ENV_IDS)
def test_seeded_rollouts_are_identical(env_id):
    action_type = ("text", "continuous")[ENV_IDS.index(env_id) % 2]
    a_frames, a_infos = _rollout(env_id, action_type, seed=7)
    b_frames, b_infos = _rollout(env_id, action_type, seed=7)
    assert a_infos == b_infos
    assert all((x == y).all() for x, y in zip(a_frames, b_frames))
    c_frames, _ = _rollout(env_id, action_type, seed=8, steps=1)
    assert not (c_frames[0] == a_frames[0]).all()  # another seed: another house


@pytest.mark.parametrize("env_id", ENV_IDS[::3])
def test_pickle_and_spec_round_trip(env_id):
    env = gym.make(env_id, **SMALL)
    env.reset(seed=1)
    clone = pickle.loads(pickle.dumps(env))
    obs_a, _ = env.reset(seed=3)
    obs_b, _ = clone.reset(seed=3)
    assert (obs_a["rgb"] == obs_b["rgb"]).all() and obs_a["instruction"] == obs_b["instruction"]
    spec = gym.envs.registration.EnvSpec.from_json(env.spec.to_json())
    assert spec == env.spec
    remade = gym.make(spec)
    assert remade.reset(seed=3)[0]["instruction"] == obs_a["instruction"]


def test_invalid_text_action_is_a_documented_noop():
    env = gym.make("Legent/ComeHere-OneRoom-v0", **SMALL)
    obs, info = env.reset(seed=2)
    obs2, reward, terminated, truncated, info2 = env.step("move_forward(1.0")
    assert "action_error" in info2 and "position" in info2["action_error"]
    assert info2["agent_pose"] == info["agent_pose"] and not terminated
    strict = gym.make("Legent/ComeHere-OneRoom-v0", strict=True, **SMALL)
    strict.reset(seed=2)
    from legent_gym.agent.actions import ActionParseError

    with pytest.raises(ActionParseError):
        strict.step("dance()")


def test_continuous_and_text_agree():
    text = gym.make("Legent/GoTo-TwoRoom-v0", **SMALL)
    cont = gym.make("Legent/GoTo-TwoRoom-v0", action_type="continuous", **SMALL)
    text.reset(seed=4)
    cont.reset(seed=4)
    for step in ["move_forward(1.2), rotate_right(-35)", "rotate_down(20)", "move_forward(0.5), rotate_right(90)"]:
        from legent_gym.agent.actions import parse_actions

        o1, *_, i1 = text.step(step)
        o2, *_, i2 = cont.step(actions_to_dict(parse_actions(step)))
        assert i1["agent_pose"] == pytest.approx(i2["agent_pose"], abs=1e-4)
        assert (o1["rgb"] == o2["rgb"]).mean() > 0.99


def test_observation_options_and_render_modes():
    env = gym.make("Legent/PickUp-TwoRoom-v0", depth=True, segmentation=True, render_mode="rgb_array", **SMALL)
    obs, info = env.reset(seed=5)
    assert obs["depth"].shape == (48, 48) and obs["depth"].dtype == np.float32
    assert obs["segmentation"].dtype == np.int32
    assert env.observation_space.contains(obs)
    assert env.render().shape == (256, 256, 3)
    paper = gym.make("Legent/ComeHere-OneRoom-v0", camera="paper")
    assert paper.reset(seed=0)[0]["rgb"].shape == (448, 448, 3)
    assert paper.unwrapped.episode.world.model.cam_fovy[paper.unwrapped.episode.world.model.camera("agent_camera").id] == 120


def test_fixed_house_options(example_scene_paths):
    path = next(p for p in example_scene_paths if p.stem == "two_room_furnished")
    env = gym.make("Legent/ComeHere-TwoRoom-v0", scene=str(path), **SMALL)
    _, info = env.reset(seed=0)
    assert info["scene_name"].startswith("two rooms")
    fixed = gym.make("Legent/ComeHere-OneRoom-v0", house_seed=11, **SMALL)
    seeds = {fixed.reset(seed=s)[1]["house_seed"] for s in range(3)}
    assert seeds == {11}
    pool = gym.make("Legent/ComeHere-OneRoom-v0", house_pool=[1, 2], **SMALL)
    assert [pool.reset(seed=s)[1]["house_seed"] for s in range(4)] == [1, 2, 1, 2]
    fresh = gym.make("Legent/ComeHere-OneRoom-v0", **SMALL)
    fresh.reset(seed=0)
    assert len({fresh.reset()[1]["house_seed"] for _ in range(3)}) == 3  # a new house every reset


@pytest.mark.parametrize("mode", ["sync", "async"])
def test_vector_envs(mode):
    kwargs = {"vectorization_mode": mode}
    if mode == "async":
        kwargs["vector_kwargs"] = {"context": "forkserver"}
    envs = gym.make_vec("Legent/ComeHere-OneRoom-v0", num_envs=2, **kwargs, **SMALL)
    obs, info = envs.reset(seed=3)
    assert obs["rgb"].shape == (2, 48, 48, 3)
    assert len(obs["instruction"]) == 2
    obs, reward, terminated, truncated, info = envs.step(("rotate_right(30)", "move_forward(1)"))
    assert obs["rgb"].shape == (2, 48, 48, 3)
    envs.close()


def test_episode_truncates_at_25_actions():
    env = gym.make("Legent/GoTo-FourRoom-v0", **SMALL)
    env.reset(seed=0)
    for _ in range(25):
        _, _, terminated, truncated, info = env.step("rotate_right(10)")
        if terminated:
            pytest.skip("the goal happened to come into view")
    assert truncated and info["n_actions"] == 25


def test_env_docs_are_generated_from_the_docstring():
    """docs/envs/household.md is what docs/gen_env_docs.py writes (regenerate after edits)."""
    import importlib.util
    from pathlib import Path

    path = Path(__file__).resolve().parents[2] / "docs" / "gen_env_docs.py"
    spec = importlib.util.spec_from_file_location("gen_env_docs", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    text = module.page()
    for section in ("Description", "Action Space", "Observation Space", "Rewards", "Episode End",
                    "Arguments", "Version History"):
        assert f"## {section}" in text
    for name, make in module.PAGES.items():
        assert (path.parent / "envs" / name).read_text() == make(), f"docs/envs/{name} is stale"


def test_env_docstrings_list_arguments_one_per_line():
    """Each env's ``## Arguments`` section is a list, one argument (or group) an item."""
    from legent_gym.envs.household import HouseholdEnv
    from legent_gym.multiagent.household import HouseholdParallelEnv

    for cls in (HouseholdEnv, HouseholdParallelEnv):
        section = cls.__doc__.split("## Arguments", 1)[1].split("##", 1)[0]
        items = [line.strip() for line in section.strip().splitlines() if line.strip().startswith("* ")]
        assert len(items) >= 8, cls.__name__
        assert all(item.startswith("* ``") or item.startswith("* every") for item in items), items


def test_geodesic_cache_is_bounded_as_the_goal_moves():
    from legent_gym.tasks.base import FIELD_CACHE_SIZE

    env = gym.make("Legent/ComeHere-TwoRoom-v0", **SMALL)
    env.reset(seed=0)
    ctx = env.unwrapped.episode.ctx
    walkable = np.argwhere(ctx.nav.walkable)[:: max(1, int(ctx.nav.walkable.sum()) // 60)]
    here = ctx.nav.to_cell(ctx.nav.nearest_walkable(tuple(ctx.agent.position)))
    for cell in walkable:
        goal = ctx.nav.to_world(cell)
        assert ctx.geodesic_to(goal) == ctx.nav.distance_field(goal)[here]
        assert len(ctx._fields) <= FIELD_CACHE_SIZE
    assert len(walkable) > FIELD_CACHE_SIZE
    env.close()


@pytest.mark.parametrize("env_id", ["Legent/ComeHere-TwoRoom-v0", "Legent/PickUp-OneRoom-v0"])
def test_dense_reward_is_progress_along_the_geodesic(env_id):
    env = gym.make(env_id, reward="dense", distance_info=False, **SMALL)  # dense measures it anyway
    _, info = env.reset(seed=5)
    before = info["distance_to_goal"]
    for action in ("rotate_right(20), move_forward(1.0)", "move_forward(0.8)", "rotate_right(-45)"):
        _, reward, terminated, _, info = env.step(action)
        after = info["distance_to_goal"]
        assert np.isfinite(after)
        assert reward == pytest.approx(before - after - 0.01 + (10.0 if info["success"] else 0.0))
        if terminated:
            break
        before = after
    sparse = gym.make(env_id, distance_info=False, **SMALL)
    _, info = sparse.reset(seed=5)
    assert info["distance_to_goal"] == -1.0
    assert sparse.step("move_forward(0.5)")[4]["distance_to_goal"] == -1.0


def test_where_is_asks_legents_objects_on_legents_receptacles():
    from legent_gym.experts import Expert
    from legent_gym.tasks.where_is import (
        PAPER_WHERE_IS,
        PAPER_WHERE_IS_OBJECTS,
        PAPER_WHERE_IS_RECEPTACLES,
    )

    for layout in ("OneRoom", "TwoRoom"):
        env = gym.make(f"Legent/WhereIs-{layout}-v0", task_options=PAPER_WHERE_IS, **SMALL)
        expert = Expert(env)
        asked = set()
        for seed in range(6):
            env.reset(seed=seed)
            world, goal = env.unwrapped.episode.world, env.unwrapped.episode.goal
            asked.add(world.assets[goal.target].category)
            assert world.assets[goal.target].category in PAPER_WHERE_IS_OBJECTS
            assert world.assets[goal.receptacle].category in PAPER_WHERE_IS_RECEPTACLES
            while True:  # the expert still answers every question
                _, _, terminated, truncated, info = env.step(expert.action())
                if terminated or truncated:
                    break
            assert info["success"], (layout, seed)
        assert len(asked) > 1
    # The same seed gives the same house and question.
    twin = gym.make("Legent/WhereIs-TwoRoom-v0", task_options=PAPER_WHERE_IS, **SMALL)
    a, b = env.reset(seed=4)[0], twin.reset(seed=4)[0]
    assert a["instruction"] == b["instruction"] and np.array_equal(a["rgb"], b["rgb"])


def test_no_task_options_leaves_every_episode_as_it_was():
    # Conditions drawn for a restricted WhereIs come from the house seed, not the env's
    # stream, so without options (or with none given) every task draws exactly as without
    # task_options: these houses and questions were recorded so (the house seeds before
    # task_options existed; the questions again at GENERATOR_VERSION 5, whose houses hold
    # other objects).
    recorded = {("WhereIs", 3): (1742692731, "Where is the laptop?"), ("WhereIs", 8): (1545220601, "Where is the toy?"),
                ("ComeHere", 8): (1545220601, "Come to me.")}
    for (task, seed), expected in recorded.items():
        for options in (None, {}):
            env = gym.make(f"Legent/{task}-OneRoom-v0", task_options=options, **SMALL)
            obs, info = env.reset(seed=seed)
            assert (info["house_seed"], obs["instruction"]) == expected


def test_task_options_are_checked_by_name():
    with pytest.raises(ValueError, match="no asset has the category 'unicorn'"):
        gym.make("Legent/WhereIs-OneRoom-v0", task_options={"objects": ["apple", "unicorn"]})
    with pytest.raises(ValueError, match="non-empty list"):
        gym.make("Legent/WhereIs-OneRoom-v0", task_options={"receptacles": "sofa"})
    with pytest.raises(ValueError, match="ComeHere does not take the options"):
        gym.make("Legent/ComeHere-OneRoom-v0", task_options={"objects": ["apple"]})

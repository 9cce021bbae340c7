"""The episode engine (legent_gym/envs/episode.py): kept houses, restored state, spawns."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import legent_gym  # noqa: F401
from legent_gym.envs.episode import Episode
from legent_gym.world.scene import save_scene

SIZE = 32


def make(env_id="Legent/PickUp-OneRoom-v0", **kwargs):
    return gym.make(env_id, width=SIZE, height=SIZE, depth=True, segmentation=True, **kwargs)


def views_equal(a: dict, b: dict) -> bool:
    return all(np.array_equal(a[k], b[k]) for k in ("rgb", "depth", "segmentation"))


def test_episodes_per_house_keeps_the_house_and_draws_new_spawns_and_goals():
    env = make("Legent/ComeHere-TwoRoom-v0", episodes_per_house=4)
    infos = [env.reset(seed=8)[1]] + [env.reset()[1] for _ in range(4)]  # seed 8: the first of its block
    episode: Episode = env.unwrapped.episode
    seeds = [i["house_seed"] for i in infos]
    assert seeds[0] == seeds[1] == seeds[2] == seeds[3] != seeds[4]  # 4 episodes, then a new house
    assert len({i["agent_pose"][:2] for i in infos[:4]}) == 4  # new spawns each episode
    for info in infos:  # ComeHere's condition holds at drawn spawns too
        (ax, ay), (ux, uy) = info["agent_pose"][:2], info["user_pose"][:2]
        assert np.hypot(ax - ux, ay - uy) >= 3.0
    assert episode.house.episodes == 1
    env.close()


def test_same_seed_same_episodes_whatever_came_before():
    def run(env, warm_up):
        for _ in range(warm_up):
            env.reset()
        out = [env.reset(seed=11)]
        out += [env.reset() for _ in range(4)]
        return out

    first = run(make(episodes_per_house=3), 0)
    second = run(make(episodes_per_house=3), 2)
    for (obs_a, info_a), (obs_b, info_b) in zip(first, second):
        assert views_equal(obs_a, obs_b)
        assert obs_a["instruction"] == obs_b["instruction"]
        assert info_a["agent_pose"] == info_b["agent_pose"] and info_a["task"] == info_b["task"]


def test_seeds_of_one_block_share_a_house_and_depend_on_nothing_else():
    env = make(episodes_per_house=4)
    _, first = env.reset(seed=8)
    obs_9, ninth = env.reset(seed=9)
    assert first["house_seed"] == ninth["house_seed"] and first["agent_pose"] != ninth["agent_pose"]
    alone = make(episodes_per_house=4)
    obs, info = alone.reset(seed=9)  # seed 9 with nothing before it
    assert views_equal(obs, obs_9) and info["agent_pose"] == ninth["agent_pose"] and info["task"] == ninth["task"]
    _, other = env.reset(seed=13)  # another block, another house
    assert other["house_seed"] != first["house_seed"]


def _play(env, actions):
    out = []
    for a in actions:
        obs, _, terminated, truncated, info = env.step(a)
        out.append((obs, info["action_results"]))
        if terminated or truncated:
            break
    return out


def test_a_kept_house_episode_equals_one_in_a_freshly_built_house():
    env = make(episodes_per_house=2)
    env.reset(seed=3)
    _play(env, ["rotate_right(40), move_forward(1)", "grab()", "rotate_down(30)", "interact()"])
    obs, _ = env.reset()  # the second episode: same house, restored, new spawns and goal
    episode = env.unwrapped.episode
    scene, goal = episode.ctx.scene, episode.goal
    fresh = make(scene=scene)
    fresh_episode = fresh.unwrapped.episode
    fresh.reset(seed=0)
    fresh_episode.set_up(scene)  # a new world built from the scene the kept house shows now
    fresh_episode.goal = goal
    assert views_equal(obs, fresh_episode.views())
    actions = ["rotate_right(-60), move_forward(0.8)", "rotate_down(35)", "grab()", "open()",
               "rotate_down(-35), move_forward(2)", "put()", 'speak("on the table")']
    kept_steps, fresh_steps = _play(env, actions), _play(fresh, actions)
    assert len(kept_steps) == len(fresh_steps)
    for (a, ra), (b, rb) in zip(kept_steps, fresh_steps):
        assert ra == rb
        assert views_equal(a, b)


def test_nothing_leaks_from_the_last_episode():
    env = make("Legent/PickUp-TwoRoom-v0", episodes_per_house=2)
    obs, info = env.reset(seed=8)
    episode = env.unwrapped.episode
    world = episode.world
    built_qpos = world.data.qpos.copy()
    target = info["task"]["target"]
    # Hold an object, open a door, move objects with physics, speak and finish.
    ctx = episode.ctx
    ctx.agent.place(*world.object_position(target)[:2], 0.0)
    assert ctx.agent.grab(target).ok
    for door in world.door_joint:
        world.data.qpos[world.model.jnt_qposadr[world.door_joint[door]]] = 0.3
    env.step('speak("hello"), finish()')
    assert ctx.speech and ctx.finished and ctx.agent.state.held == target
    obs, info = env.reset()
    assert episode.world is world  # the same compiled house
    ctx = episode.ctx
    assert ctx.agent.state.held is None and ctx.user.state.held is None
    assert ctx.speech == [] and not ctx.finished
    assert np.array_equal(world.data.qpos, built_qpos)  # objects, doors, drawers as built
    model = world.model
    body = world.object_body[target]
    geoms = range(model.body_geomadr[body], model.body_geomadr[body] + model.body_geomnum[body])
    assert any(model.geom_contype[g] for g in geoms)  # the held object collides again


def test_a_fixed_house_is_built_once():
    env = make(house_seed=4)
    env.reset(seed=0)
    world = env.unwrapped.episode.world
    obs1, info1 = env.reset(seed=1)
    assert env.unwrapped.episode.world is world
    fresh = make(house_seed=4)
    obs2, info2 = fresh.reset(seed=1)
    assert views_equal(obs1, obs2) and info1["task"] == info2["task"]


def test_houses_from_a_folder(tmp_path):
    from legent_gym.world.generation import generate_house

    for seed in (1, 2, 3):
        save_scene(generate_house(seed, "OneRoom"), tmp_path / f"OneRoom_{seed:06d}.json")
    env = make("Legent/ComeHere-OneRoom-v0", houses=tmp_path)
    names = set()
    for i in range(8):
        _, info = env.reset(seed=i)
        names.add(info["house_seed"])
        (ax, ay), (ux, uy) = info["agent_pose"][:2], info["user_pose"][:2]
        assert np.hypot(ax - ux, ay - uy) >= 3.0  # spawns drawn under the task's condition
    assert names <= {1, 2, 3} and len(names) >= 2
    assert env.unwrapped.episode.kept_houses <= 3  # each file built once


def test_houses_kept_bounds_the_built_houses(tmp_path):
    env = make("Legent/ComeHere-OneRoom-v0", house_pool=[1, 2, 3, 4], houses_kept=2)
    worlds = []
    for _ in range(8):
        env.reset()
        worlds.append(env.unwrapped.episode.world)
        assert env.unwrapped.episode.kept_houses <= 2
    assert len({id(w) for w in worlds}) > 4  # the pool of 4 is built again, only 2 kept
    env = make("Legent/ComeHere-OneRoom-v0", house_pool=[1, 2, 3, 4], houses_kept=4)
    worlds = []
    for _ in range(8):
        env.reset()
        worlds.append(env.unwrapped.episode.world)
    ids = [id(w) for w in worlds]
    assert len(set(ids)) == 4 and ids[:4] == ids[4:]  # each house built once
    with pytest.raises(ValueError, match="houses_kept"):
        make(houses_kept=0)


def test_houses_folder_errors_name_the_folder(tmp_path):
    with pytest.raises(ValueError, match="holds no"):
        make(houses=tmp_path)
    with pytest.raises(ValueError, match="is not a folder"):
        make(houses=tmp_path / "missing")


@pytest.mark.parametrize("bad", [0, -1, 1.5, True])
def test_episodes_per_house_must_be_a_positive_integer(bad):
    with pytest.raises(ValueError, match="episodes_per_house"):
        make(episodes_per_house=bad)


def test_check_env_with_kept_houses():
    check_env(make(episodes_per_house=8).unwrapped, skip_render_check=True)


def _unseeded_run(actions, *, between=None, **kwargs):
    """Observations and rewards of a seeded reset followed by unseeded resets (autoreset's)."""
    env = make("Legent/ComeHere-OneRoom-v0", **kwargs)
    try:
        obs, info = env.reset(seed=5)
        frames, houses = [obs["rgb"]], [info["house_seed"]]
        for action in actions:
            obs, reward, terminated, truncated, info = env.step(action)
            frames.append(obs["rgb"])
            if terminated or truncated:
                if between is not None:
                    between(env)
                obs, info = env.reset()
                frames.append(obs["rgb"])
                houses.append(info["house_seed"])
        return frames, houses, env.unwrapped.episode.houses_taken_ahead
    finally:
        env.close()


@pytest.mark.parametrize("episodes_per_house", [1, 2])
def test_a_house_made_ahead_gives_the_same_episodes(episodes_per_house):
    actions = ["rotate_right(90)", "move_forward(1)", "rotate_down(20)"] * 30
    inline, houses, taken = _unseeded_run(actions, prepare_ahead=False, episodes_per_house=episodes_per_house)
    ahead, houses_ahead, taken_ahead = _unseeded_run(actions, prepare_ahead=True, episodes_per_house=episodes_per_house)
    assert taken == 0 and taken_ahead >= 1
    assert houses == houses_ahead and len(set(houses)) >= 3
    assert len(inline) == len(ahead) and all(np.array_equal(a, b) for a, b in zip(inline, ahead))


def test_a_house_made_ahead_that_is_not_the_one_drawn_is_not_used():
    # Drawing from the env's generator between episodes changes the next house (the seed of
    # the next block): the house made ahead is not that one, and the episode is the one a
    # run without it gives.
    actions = ["rotate_right(90)", "move_forward(1)"] * 40
    moved = _unseeded_run(actions, between=lambda env: env.unwrapped.np_random.integers(2), prepare_ahead=True)
    inline = _unseeded_run(actions, between=lambda env: env.unwrapped.np_random.integers(2), prepare_ahead=False)
    assert moved[2] == 0 and moved[1] == inline[1]
    assert all(np.array_equal(a, b) for a, b in zip(moved[0], inline[0]))


def test_close_waits_for_a_house_made_ahead_and_pickling_drops_it():
    import pickle

    env = make("Legent/ComeHere-OneRoom-v0", prepare_ahead=True)
    env.reset(seed=1)
    episode = env.unwrapped.episode
    copy = pickle.loads(pickle.dumps(episode))
    assert copy.prepare_ahead and copy.ctx is None
    env.close()
    assert all(t.name != "legent-house-ahead" for t in __import__("threading").enumerate())

"""Built houses on disk (legent_gym/envs/house_store.py, ``house_cache=DIR``): each house
given again is built once, stored in two files, and loaded by later envs, their helpers and
their vector env workers, with the same episodes as a house built anew."""

from __future__ import annotations

import warnings
from pathlib import Path

import gymnasium as gym
import pytest

import legent_gym  # noqa: F401
from legent_gym.world.generation import generate_house
from legent_gym.world.scene import load_scene, save_scene
from tests.envs.test_factory import _assert_same, _run

ENV = "Legent/GoTo-OneRoom-v0"
#: Seeded resets, each followed by unseeded episodes: with houses_kept=1 nearly every
#: episode of three files builds (or loads) its house again.
PLAY = {"seeds": (4, 9), "unseeded": 4, "houses_kept": 1}


@pytest.fixture(scope="module")
def folder(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("houses")
    for seed in (1, 2, 3):
        save_scene(generate_house(seed, "OneRoom"), out / f"OneRoom_{seed:06d}.json")
    return out


def _store(env):
    return env.unwrapped.episode.house_store


def _files(cache: Path) -> list[str]:
    return sorted(p.name for p in cache.iterdir() if not p.name.startswith("."))


def test_a_house_is_built_once_and_loaded_after_with_the_same_episodes(folder, tmp_path):
    cache = tmp_path / "cache"
    built, _ = _run(ENV, houses=str(folder), **PLAY)
    first, _ = _run(ENV, houses=str(folder), house_cache=str(cache), **PLAY)
    stored = _files(cache)
    # one model and one .house file per house of the folder, nothing else left behind
    assert len(stored) == 6 and {Path(n).suffix for n in stored} == {".mjb", ".house"}, stored
    env = gym.make(ENV, width=32, height=32, houses=str(folder), house_cache=str(cache), houses_kept=1)
    try:
        for seed in range(6):
            env.reset(seed=seed)
        # a house drawn again in a row is the one kept in memory; every other one is loaded
        assert _store(env).loaded >= 2 and _store(env).stored == 0
    finally:
        env.close()
    again, _ = _run(ENV, houses=str(folder), house_cache=str(cache), **PLAY)
    _assert_same(built, first)
    _assert_same(built, again)
    assert _files(cache) == stored


def test_helpers_load_and_store_the_same_houses(folder, tmp_path):
    cache = tmp_path / "cache"
    built, _ = _run(ENV, houses=str(folder), **PLAY)
    helped, taken = _run(ENV, houses=str(folder), house_cache=str(cache), helpers=1, **PLAY)
    assert taken >= 3 and len(_files(cache)) == 6  # the helper built and stored them
    helped_again, _ = _run(ENV, houses=str(folder), house_cache=str(cache), helpers=1, **PLAY)
    _assert_same(built, helped)
    _assert_same(built, helped_again)


def test_a_changed_scene_file_is_a_new_house(folder, tmp_path):
    houses, cache = tmp_path / "houses", tmp_path / "cache"
    houses.mkdir()
    path = houses / "one.json"
    save_scene(load_scene(folder / "OneRoom_000001.json"), path)
    env = gym.make(ENV, width=32, height=32, houses=str(houses), house_cache=str(cache))
    try:
        env.reset(seed=0)
        before = _files(cache)
        scene = load_scene(path)
        save_scene(scene.model_copy(update={"objects": scene.objects[:-1]}), path)  # one object less
        env2 = gym.make(ENV, width=32, height=32, houses=str(houses), house_cache=str(cache))
        env2.reset(seed=0)
        assert _store(env2).stored == 1 and _store(env2).loaded == 0
        assert len(env2.unwrapped.episode.world.scene.objects) == len(scene.objects) - 1
        assert len(_files(cache)) == 2 * len(before)
        env2.close()
    finally:
        env.close()


def test_a_damaged_file_is_named_and_the_house_built_again(folder, tmp_path):
    cache = tmp_path / "cache"
    built, _ = _run(ENV, houses=str(folder), **PLAY)
    _run(ENV, houses=str(folder), house_cache=str(cache), **PLAY)
    damaged = sorted(cache.glob("*.house"))[0]
    damaged.write_bytes(damaged.read_bytes()[:100])  # cut short
    with pytest.warns(RuntimeWarning, match=damaged.name):
        again, _ = _run(ENV, houses=str(folder), house_cache=str(cache), **PLAY)
    _assert_same(built, again)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # stored whole again: no warning now
        _run(ENV, houses=str(folder), house_cache=str(cache), **PLAY)


def test_fixed_seeds_are_stored_and_new_random_houses_are_not(tmp_path):
    cache = tmp_path / "cache"
    env = gym.make("Legent/ComeHere-OneRoom-v0", width=32, height=32, house_cache=str(cache))
    try:
        for seed in range(3):
            env.reset(seed=seed)
        assert _files(cache) == [] and _store(env).stored == 0  # never asked for again: not stored
    finally:
        env.close()
    pool, _ = _run("Legent/ComeHere-OneRoom-v0", seeds=(0,), unseeded=3, house_pool=[5, 6])
    stored, _ = _run("Legent/ComeHere-OneRoom-v0", seeds=(0,), unseeded=3, house_pool=[5, 6], house_cache=str(cache))
    loaded, _ = _run("Legent/ComeHere-OneRoom-v0", seeds=(0,), unseeded=3, house_pool=[5, 6], house_cache=str(cache))
    assert len(_files(cache)) == 4  # the pool's two houses
    _assert_same(pool, stored)
    _assert_same(pool, loaded)


def test_a_cache_that_cannot_be_a_folder_is_an_error_naming_it(tmp_path):
    not_a_folder = tmp_path / "file"
    not_a_folder.write_text("x")
    with pytest.raises(ValueError, match="house_cache=.*file"):
        gym.make(ENV, house_cache=str(not_a_folder))

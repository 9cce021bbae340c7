"""The user-plus-agent PettingZoo envs: PettingZoo's own test suite on every id, speech
between the two, scripted users, the single-agent wrapper against the single-agent env."""

from __future__ import annotations

import functools
import math
import re
import warnings
from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest

pettingzoo = pytest.importorskip("pettingzoo", reason="install the 'multiagent' extra: pip install -e '.[multiagent]'")

from gymnasium.utils.env_checker import check_env  # noqa: E402
from pettingzoo.test import (  # noqa: E402
    api_test,
    max_cycles_test,
    parallel_api_test,
    parallel_seed_test,
    render_test,
    seed_test,
)

import legent_gym.multiagent as ma  # noqa: E402

IDS = ma.MULTIAGENT_ENV_IDS
SMALL = {"width": 32, "height": 32}
CYCLES = 30  # > the 25-step cap, so every test also sees the truncation
DOCS = Path(__file__).resolve().parents[2] / "docs" / "multiagent.md"


@pytest.fixture(autouse=True)
def _quiet_pettingzoo():
    # PettingZoo's checks warn about Dict/Text spaces and agent names ("player_0"); both
    # are deliberate here (LEGENT's observations hold text; the agents are "user", "agent").
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        yield


def _parallel(env_id, **kwargs):
    return pettingzoo.make("parallel", env_id, **SMALL, **kwargs)


def _aec(env_id, **kwargs):
    return pettingzoo.make("aec", env_id, **SMALL, **kwargs)


def _dist(info):
    (ax, ay, *_), (ux, uy, *_) = info["agent_pose"], info["user_pose"]
    return math.hypot(ax - ux, ay - uy)


# -- registration ---------------------------------------------------------------------------
def test_every_id_is_registered_in_both_forms():
    assert len(IDS) == 18
    for env_id in IDS:
        for kind in ("parallel", "aec"):
            spec = pettingzoo.spec(kind, env_id)
            assert spec.max_cycles == 25 and isinstance(spec.entry_point, str)
    env = pettingzoo.make("parallel", "Legent/WhereIs-TwoRoom-v0", **SMALL)
    assert isinstance(env, ma.HouseholdParallelEnv)
    assert (env.task_name, env.layout, env.max_cycles) == ("WhereIs", "TwoRoom", 25)
    assert env.possible_agents == ["user", "agent"]
    assert isinstance(pettingzoo.make("aec", "Legent/WhereIs-TwoRoom-v0"), pettingzoo.AECEnv)


def test_module_functions():
    assert isinstance(ma.parallel_env(task="GoTo"), ma.HouseholdParallelEnv)
    assert isinstance(ma.raw_env().unwrapped, ma.HouseholdParallelEnv)
    assert isinstance(ma.env(), pettingzoo.AECEnv)
    module = ma.env_module("Legent/PutOn-FourRoom-v0")
    assert module.parallel_env().task_name == "PutOn" and module.env().unwrapped.layout == "FourRoom"
    with pytest.raises(ValueError, match="unknown env id"):
        ma.env_module("Legent/Dance-OneRoom-v0")


def test_bad_arguments_are_named():
    with pytest.raises(ValueError, match="rewards"):
        ma.parallel_env(rewards="selfish")
    with pytest.raises(ValueError, match="max_cycles"):
        ma.parallel_env(max_cycles=0)
    with pytest.raises(ValueError, match="render_mode"):
        ma.parallel_env(render_mode="ansi")
    with pytest.raises(ValueError, match="unknown task"):
        ma.parallel_env(task="Dance")


# -- PettingZoo's test suite, every id --------------------------------------------------------
@pytest.mark.parametrize("env_id", IDS)
def test_parallel_api(env_id):
    parallel_api_test(_parallel(env_id), num_cycles=CYCLES)


@pytest.mark.parametrize("env_id", IDS)
def test_aec_api(env_id):
    api_test(_aec(env_id), num_cycles=CYCLES)


@pytest.mark.parametrize("env_id", IDS)
def test_seeds(env_id):
    seed_test(lambda: _aec(env_id), num_cycles=CYCLES)
    parallel_seed_test(lambda: _parallel(env_id), num_cycles=CYCLES)


@pytest.fixture
def _no_window(monkeypatch):
    """Human mode on SDL's dummy driver even where the tests run with a display: no window
    and no pacing at render_fps."""
    monkeypatch.setenv("SDL_VIDEODRIVER", "dummy")


@pytest.mark.parametrize("env_id", IDS)
def test_render_and_max_cycles(env_id, _no_window):
    # A plain factory: render_test makes the env with render_mode="human" first, then renders
    # every mode the env lists.
    render_test(functools.partial(_aec, env_id, render_size=64))
    max_cycles_test(_seeded_module(env_id))


def test_render_test_with_the_registered_factory(_no_window):
    render_test(ma.env_module("Legent/ComeHere-OneRoom-v0").env)


def test_human_mode_shows_the_rgb_array_frame(monkeypatch):
    """Without a display, human mode warns and draws into SDL's dummy driver: the window
    holds exactly the frame rgb_array mode returns, at every step."""
    pygame = pytest.importorskip("pygame")
    for name in ("DISPLAY", "WAYLAND_DISPLAY"):
        monkeypatch.delenv(name, raising=False)
    monkeypatch.setenv("SDL_VIDEODRIVER", "")  # restored (unset) after the test
    monkeypatch.delenv("SDL_VIDEODRIVER")
    human = ma.parallel_env(render_mode="human", render_size=64, **SMALL)
    frames = ma.parallel_env(render_mode="rgb_array", render_size=64, **SMALL)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        human.reset(seed=0)
    assert any("dummy video driver" in str(w.message) for w in caught)
    frames.reset(seed=0)
    assert pygame.display.get_driver() == "dummy"
    for _ in range(2):
        shown = pygame.surfarray.array3d(pygame.display.get_surface()).swapaxes(0, 1)
        np.testing.assert_array_equal(shown, frames.render())
        assert human.render() is None
        actions = {"user": "rotate_right(30)", "agent": "move_forward(0.5), rotate_right(-40)"}
        human.step(actions)
        frames.step(actions)
    human.close()
    assert not pygame.display.get_init()
    frames.close()


def _seeded_module(env_id):
    """``env_module(env_id)`` whose envs reset with seed 0 when given none, and whose action
    spaces sample from seeded generators: max_cycles_test resets and samples unseeded, and
    a random episode that happens to end early (a random action that completes the task)
    must not make the test flaky."""
    from types import SimpleNamespace

    module = ma.env_module(env_id)

    def seeded(factory):
        def make(**kwargs):
            env = factory(**kwargs)
            reset = env.reset
            env.reset = lambda seed=None, options=None: reset(seed=0 if seed is None else seed, options=options)
            for i, agent in enumerate(env.possible_agents):
                env.action_space(agent).seed(i)
            return env
        return make

    return SimpleNamespace(parallel_env=seeded(module.parallel_env), env=seeded(module.env))


def test_continuous_actions_pass_the_parallel_api():
    parallel_api_test(_parallel("Legent/PickUp-OneRoom-v0", action_type="continuous"), num_cycles=CYCLES)


# -- the single-agent wrapper is the single-agent env --------------------------------------------
def _scripted_actions(n, seed):
    rng = np.random.default_rng(seed)
    out = []
    for i in range(n):
        step = f"move_forward({rng.uniform(0, 1.5):.2f}), rotate_right({rng.uniform(-90, 90):.1f})"
        if i % 4 == 3:
            step += ", rotate_down(20), interact(), rotate_down(-20)"
        out.append(step)
    out[n // 2] = "jump()"  # an unparsable step: a no-op with action_error in both
    return out


def _run(env, seed, actions):
    obs, info = env.reset(seed=seed)
    trace = [(obs, info)]
    for action in actions:
        obs, reward, terminated, truncated, info = env.step(action)
        trace.append((obs, reward, terminated, truncated, info))
        if terminated or truncated:
            trace.append(env.reset())
    env.close()
    return trace


def _same(a, b):
    if isinstance(a, dict):
        return a.keys() == b.keys() and all(_same(a[k], b[k]) for k in a)
    if isinstance(a, list | tuple):
        return len(a) == len(b) and all(_same(x, y) for x, y in zip(a, b))
    if isinstance(a, np.ndarray):
        return a.dtype == b.dtype and a.shape == b.shape and bool((a == b).all())
    return type(a) is type(b) and a == b


@pytest.mark.parametrize("env_id", ["Legent/ComeHere-TwoRoom-v0", "Legent/PickUp-OneRoom-v0",
                                    "Legent/WhereIs-OneRoom-v0"])
def test_still_user_wrapper_equals_single_agent_env(env_id):
    actions = _scripted_actions(40, 3)
    single = _run(gym.make(env_id, **SMALL), 11, actions)
    # distance_info: the single-agent env's default (the multi-agent env's is off)
    wrapped = _run(ma.make_single_agent(env_id, partner="still", distance_info=True, **SMALL), 11, actions)
    assert len(single) == len(wrapped) > 40
    for step, (a, b) in enumerate(zip(single, wrapped)):
        assert _same(a, b), f"step {step} differs"


@pytest.mark.slow
@pytest.mark.parametrize("env_id", IDS)
def test_still_user_wrapper_equals_single_agent_env_every_id(env_id):
    actions = _scripted_actions(60, 5)
    for seed in (0, 1):
        single = _run(gym.make(env_id, **SMALL), seed, actions)
        wrapped = _run(ma.make_single_agent(env_id, partner="still", distance_info=True, **SMALL), seed, actions)
        assert len(single) == len(wrapped) and all(_same(a, b) for a, b in zip(single, wrapped))


def test_wrapper_passes_gymnasiums_checker_on_both_sides():
    env = ma.SingleAgentEnv(ma.parallel_env(render_mode="rgb_array", render_size=48, **SMALL), partner="wander")
    check_env(env, skip_render_check=False)
    user_side = ma.SingleAgentEnv(ma.parallel_env(**SMALL), partner=lambda obs: "rotate_right(10)", learner="user")
    check_env(user_side)
    with pytest.raises(ValueError, match="learner"):
        ma.SingleAgentEnv(ma.parallel_env(**SMALL), learner="dog")
    with pytest.raises(ValueError, match="unknown user policy"):
        ma.SingleAgentEnv(ma.parallel_env(**SMALL), partner="dance")


# -- speech, actions and bodies ------------------------------------------------------------------
def test_speech_reaches_the_other_side():
    env = ma.parallel_env(**SMALL)
    obs, _ = env.reset(seed=4)
    instruction = env.episode.goal.instruction
    assert obs["agent"]["instruction"] == obs["agent"]["message"] == instruction
    assert obs["user"]["instruction"] == instruction and obs["user"]["message"] == ""
    obs, *_ = env.step({"user": 'speak("Over here, by the window.")', "agent": 'speak("Where are you?")'})
    assert obs["agent"]["message"] == "Over here, by the window."
    assert obs["agent"]["instruction"] == instruction
    assert obs["user"]["message"] == "Where are you?"
    # A tab can be spoken in action code but a Text observation cannot hold it.
    obs, *_ = env.step({"user": 'speak("a\\tb")', "agent": "rotate_right(5)"})
    assert obs["agent"]["message"] == "a b"
    assert env.observation_space("agent").contains(obs["agent"])
    # Silence keeps the last words.
    obs, *_ = env.step({"user": None, "agent": "rotate_right(5)"})
    assert obs["agent"]["message"] == "a b" and obs["user"]["message"] == "Where are you?"


def test_instruction_from_user():
    env = ma.parallel_env(instruction_from_user=True, **SMALL)
    obs, _ = env.reset(seed=4)
    assert obs["agent"]["instruction"] == obs["agent"]["message"] == ""
    assert obs["user"]["instruction"] == env.episode.goal.instruction
    obs, *_ = env.step({"user": "rotate_right(10)", "agent": "rotate_right(10)"})
    assert obs["agent"]["instruction"] == ""
    obs, *_ = env.step({"user": 'speak("Come to the kitchen.")', "agent": "rotate_right(10)"})
    assert obs["agent"]["instruction"] == obs["agent"]["message"] == "Come to the kitchen."
    obs, *_ = env.step({"user": 'speak("Hurry!")', "agent": "rotate_right(10)"})
    assert obs["agent"]["instruction"] == "Come to the kitchen." and obs["agent"]["message"] == "Hurry!"


def test_the_user_acts_with_the_same_grammar():
    env = ma.parallel_env(**SMALL)
    obs, info = env.reset(seed=2)
    before = info["user"]["user_pose"]
    obs2, rewards, terms, truncs, infos = env.step({"user": "rotate_right(90), rotate_down(15)",
                                                    "agent": "rotate_right(0)"})
    x, y, yaw, pitch = infos["user"]["user_pose"]
    assert (x, y) == before[:2] and yaw == pytest.approx((before[2] - 90) % 360) and pitch == 15
    assert infos["user"]["action_text"] == "rotate_right(90), rotate_down(15)"
    assert infos["user"]["action_ok"] and infos["user"]["action_error"] == ""
    assert infos["user"]["action_results"] == "rotate_right(90): ok; rotate_down(15): ok"
    assert not (obs2["user"]["rgb"] == obs["user"]["rgb"]).all()  # the user's camera turned
    assert (obs2["agent"]["rgb"] == obs["agent"]["rgb"]).all()  # the agent's did not
    _, _, terms, _, infos = env.step({"user": "finish(), move_forward(0.3), dance()", "agent": "rotate_right(0)"})
    assert infos["user"]["action_error"] and not infos["user"]["action_ok"] and not terms["agent"]
    _, _, terms, _, infos = env.step({"user": "finish()", "agent": "rotate_right(0)"})
    assert not terms["user"] and not infos["user"]["action_ok"]
    assert infos["user"]["action_results"].startswith("finish(): failed (") and "only the agent" in \
        infos["user"]["action_results"]
    with pytest.raises(ValueError, match="missing"):
        env.step({"agent": "rotate_right(0)"})
    with pytest.raises(ValueError, match="unknown agents"):
        env.step({"agent": "rotate_right(0)", "user": None, "dog": None})
    _, _, terms, _, _ = env.step({"user": None, "agent": "finish()"})
    assert terms == {"user": True, "agent": True} and env.agents == []
    with pytest.raises(RuntimeError, match="reset"):
        env.step({"agent": "rotate_right(0)", "user": None})


def test_strict_raises_for_the_user_too():
    env = ma.parallel_env(strict=True, **SMALL)
    env.reset(seed=0)
    with pytest.raises(ValueError, match="unknown action"):
        env.step({"user": "dance()", "agent": "rotate_right(0)"})


def test_episode_truncates_for_both_after_max_cycles():
    env = ma.parallel_env(max_cycles=3, **SMALL)
    env.reset(seed=0)
    for _ in range(2):
        _, _, _, truncs, _ = env.step({"user": None, "agent": "rotate_right(1)"})
        assert truncs == {"user": False, "agent": False}
    _, _, _, truncs, _ = env.step({"user": None, "agent": "rotate_right(1)"})
    assert truncs == {"user": True, "agent": True} and env.agents == []


def test_objects_pass_between_hands():
    env = ma.parallel_env(task="PickUp", **SMALL)
    env.reset(seed=1)
    ctx = env.episode.ctx
    target = env.episode.goal.target
    x, y, _ = ctx.world.object_position(target)
    stand = ctx.nav.standing_point(target, reach=1.0)
    yaw = math.degrees(math.atan2(y - stand[1], x - stand[0]))
    ctx.agent.place(-50, -50, 0)  # out of the way
    ctx.user.place(stand[0], stand[1], yaw)
    _, _, _, _, infos = env.step({"user": f"grab({target})", "agent": "rotate_right(0)"})
    assert infos["user"]["held"] == target and infos["user"]["action_ok"]
    # The agent, beside the user, takes it and puts it back in one step: the user's hands are empty.
    host = ctx.scene.object(target).on
    ctx.agent.place(stand[0] + 0.1, stand[1], yaw)
    _, _, terms, _, infos = env.step({"user": None, "agent": f"grab({target}), put({host})"})
    assert infos["agent"]["action_ok"] and infos["agent"]["action_results"].count(": ok") == 2
    assert infos["agent"]["held"] == -1 and infos["user"]["held"] == -1 and not terms["agent"]
    ctx.agent.place(-50, -50, 0)
    _, _, _, _, infos = env.step({"user": f"grab({target})", "agent": "rotate_right(0)"})
    assert infos["user"]["held"] == target
    # The user walks off with it: the object stays in the user's hands.
    env.step({"user": "rotate_right(180), move_forward(0.5)", "agent": "rotate_right(0)"})
    ux, uy, uyaw, _ = ctx.user.state.x, ctx.user.state.y, ctx.user.state.yaw, 0
    held_at = ctx.world.object_position(target)
    assert math.hypot(held_at[0] - ux, held_at[1] - uy) < 0.5
    # The agent, in front of the user, takes it from the user's hands and succeeds.
    ax, ay = ux + 1.0 * math.cos(math.radians(uyaw)), uy + 1.0 * math.sin(math.radians(uyaw))
    ctx.agent.place(ax, ay, uyaw + 180.0)
    _, rewards, terms, _, infos = env.step({"user": None, "agent": f"grab({target})"})
    assert infos["agent"]["held"] == target and infos["user"]["held"] == -1
    assert terms["agent"] and rewards == {"user": 1.0, "agent": 1.0}


def test_per_agent_rewards_credit_each_sides_progress():
    kwargs = {"task": "ComeHere", "layout": "OneRoom", "reward": "dense", **SMALL}
    team, split = ma.parallel_env(**kwargs), ma.parallel_env(rewards="per_agent", **kwargs)
    for env in (team, split):
        env.reset(seed=6)
    policy_team, policy_split = ma.ComeTowards(speed=0.5), ma.ComeTowards(speed=0.5)
    policy_team.reset(team, np.random.default_rng(0))
    policy_split.reset(split, np.random.default_rng(0))
    user_total = 0.0
    for _ in range(4):  # the user walks to the agent, the agent only turns
        a = team.step({"user": policy_team.act(team, None), "agent": "rotate_right(10)"})
        b = split.step({"user": policy_split.act(split, None), "agent": "rotate_right(10)"})
        if a[2]["agent"]:
            break
        assert a[1]["user"] == a[1]["agent"]  # the team shares one reward
        assert b[1]["user"] == pytest.approx(a[1]["user"])  # the user made all the progress
        assert b[1]["agent"] == pytest.approx(-0.01)  # the agent made none: only the step cost
        user_total += b[1]["user"]
    assert user_total > 0.5


def test_render_frames_both_bodies():
    env = ma.parallel_env(render_mode="rgb_array", render_size=64, **SMALL)
    assert env.render() is None  # nothing before reset
    env.reset(seed=0)
    frame = env.render()
    assert frame.shape == (64, 64, 3) and frame.dtype == np.uint8 and frame.std() > 0
    env.close()


# -- scripted users -------------------------------------------------------------------------------
def _episode(partner, seed=0, steps=20, task="ComeHere", layout="TwoRoom"):
    env = ma.SingleAgentEnv(ma.parallel_env(task=task, layout=layout, max_cycles=steps, **SMALL), partner=partner)
    obs, info = env.reset(seed=seed)
    infos, messages = [info], [obs["message"]]
    for _ in range(steps):
        obs, _, _, truncated, info = env.step("rotate_right(0)")  # the agent only stands
        infos.append(info)
        messages.append(obs["message"])
        if truncated or info["success"]:
            break
    return infos, messages


def test_wander_walks_and_is_seeded():
    a, _ = _episode("wander", seed=3, task="PickUp")
    b, _ = _episode("wander", seed=3, task="PickUp")
    c, _ = _episode("wander", seed=4, task="PickUp")
    path = [i["user_pose"] for i in a]
    assert path == [i["user_pose"] for i in b] and path != [i["user_pose"] for i in c]
    walked = sum(math.dist(p[:2], q[:2]) for p, q in zip(path, path[1:]))
    assert walked > 3.0
    assert all(math.dist(p[:2], q[:2]) <= 0.5 + 1e-6 for p, q in zip(path, path[1:]))  # its speed


def test_walk_away_and_come_towards():
    # A house where the user starts far enough from its walls to walk 2 m further away.
    away, _ = _episode(ma.WalkAway(speed=0.5), seed=1, task="PickUp")
    assert _dist(away[-1]) > _dist(away[0]) + 2.0
    near, _ = _episode(ma.ComeTowards(speed=0.5, stop_distance=1.0), seed=1, task="PickUp", steps=40)
    assert _dist(near[-1]) < 1.6 < _dist(near[0])


def test_repeat_instruction_reaches_the_agent():
    env = ma.SingleAgentEnv(ma.parallel_env(instruction_from_user=True, **SMALL),
                            partner=ma.RepeatInstruction(every=3))
    obs, _ = env.reset(seed=2)
    assert obs["instruction"] == ""
    obs, _, _, _, _ = env.step("rotate_right(0)")
    assert obs["instruction"] == obs["message"] == env.episode.goal.instruction
    with pytest.raises(ValueError, match="every"):
        ma.RepeatInstruction(every=0)
    with pytest.raises(ValueError, match="speed"):
        ma.Wander(speed=0)


@pytest.mark.slow
def test_docs_example_trains_both_sides():
    pytest.importorskip("stable_baselines3")
    code = re.search(r"```python\n(# train both sides.*?)```", DOCS.read_text(), re.S)
    assert code, "docs/multiagent.md lost its training example"
    namespace: dict = {}
    exec(compile(code.group(1), str(DOCS), "exec"), namespace)
    assert namespace["agent_model"].num_timesteps > 0 and namespace["user_model"].num_timesteps > 0


def test_benchmark_script_runs(capsys, monkeypatch):
    monkeypatch.syspath_prepend(str(Path(__file__).resolve().parents[2] / "benchmarks"))
    monkeypatch.setattr("os.sched_setaffinity", lambda *args: None, raising=False)  # leave the test's cores be
    import multiagent as bench

    assert bench.main(["--ids", "Legent/PickUp-OneRoom-v0", "--steps", "20", "--size", "32", "--repeats", "1"]) == 0
    row = capsys.readouterr().out.splitlines()[-1].split()
    assert row[0] == "Legent/PickUp-OneRoom-v0" and float(row[1]) > 0 and float(row[2]) > 0


def expert_with_wandering_user(episodes: int) -> int:
    """Successes of the task expert acting for the agent while the user wanders."""
    from legent_gym.wrappers import ExpertPolicy

    env = ExpertPolicy(ma.make_single_agent("Legent/ComeHere-TwoRoom-v0", partner="wander", width=32, height=32))
    wins = 0
    for seed in range(episodes):
        env.reset(seed=seed)
        for _ in range(25):
            _, _, terminated, truncated, info = env.step(None)
            if terminated or truncated:
                break
        wins += bool(info["success"])
    env.close()
    return wins


def test_expert_with_a_wandering_user():
    assert expert_with_wandering_user(5) >= 4


@pytest.mark.slow
def test_expert_with_a_wandering_user_acceptance():
    wins = expert_with_wandering_user(200)
    print(f"expert with a wandering user, ComeHere-TwoRoom: {wins}/200")
    assert wins >= 190  # >= 95%


def test_distance_to_goal_is_measured_only_on_request():
    actions = {"user": "move_forward(0.5), rotate_right(30)", "agent": "move_forward(0.5)"}
    env = ma.parallel_env(task="ComeHere", layout="TwoRoom", **SMALL)
    _, infos = env.reset(seed=3)
    assert infos["agent"]["distance_to_goal"] == -1.0 and infos["user"]["distance_to_goal"] == -1.0
    _, rewards, _, _, infos = env.step(actions)
    assert infos["agent"]["distance_to_goal"] == -1.0
    for kwargs in ({"distance_info": True}, {"reward": "dense"}):
        env = ma.parallel_env(task="ComeHere", layout="TwoRoom", **kwargs, **SMALL)
        _, infos = env.reset(seed=3)
        before = infos["agent"]["distance_to_goal"]
        _, rewards, _, _, infos = env.step(actions)
        after = infos["agent"]["distance_to_goal"]
        assert 0 < after < math.inf and 0 < before < math.inf
        if "reward" in kwargs:  # the dense reward is the progress along that distance
            assert rewards["agent"] == pytest.approx(before - after - 0.01)

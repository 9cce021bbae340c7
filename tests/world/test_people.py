"""The people: humanoid bodies, their motion, the arm's IK, and how cameras see them."""

from __future__ import annotations

import math
import os
import subprocess
import sys

import gymnasium as gym
import mujoco
import numpy as np
import pytest

import legent_gym  # noqa: F401
from legent_gym.agent.body import Body
from legent_gym.agent.motion import ArmIK, Keyframe, joint_angles
from legent_gym.world.builder import (
    GROUP_AGENT,
    GROUP_HANDS,
    GROUP_USER,
    PERSON_SEGMENTATION_ID,
    build_world,
)
from legent_gym.world.humanoid import (
    ARM_JOINTS,
    JOINT_HIGH,
    JOINT_LOW,
    JOINTS,
    PARTS,
    appearance_for,
)
from legent_gym.world.render import FreeCamera, Renderer
from legent_gym.world.scene import validate_scene
from legent_gym.world.topdown_map import draw_topdown_map
from legent_gym.wrappers import ExpertInfo

ROOM = {"rooms": [{"id": "r", "type": "bedroom", "name": "room", "polygon": [[0, 0], [8, 0], [8, 4], [0, 4]]}]}


def _scene(agent=(1.0, 2.0, 0.0), user=(4.0, 2.0, 180.0), seed=0):
    return validate_scene({**ROOM, "seed": seed, "agent": {"position": agent[:2], "yaw": agent[2]},
                           "user": {"position": user[:2], "yaw": user[2]}})


@pytest.fixture(scope="module")
def world():
    return build_world(_scene())


def test_people_have_named_parts_joints_and_hand_sites(world):
    model = world.model
    for who in ("agent", "user"):
        for part in PARTS:
            assert model.body(f"{who}/{part}").id >= 0
        for side in ("right", "left"):
            site = model.site(f"{who}/{side}_hand")
            assert model.site_bodyid[site.id] == model.body(f"{who}/{side}_hand").id
        for joint in JOINTS:
            jid = model.joint(f"{who}/{joint.name}").id
            assert model.jnt_type[jid] == mujoco.mjtJoint.mjJNT_HINGE and model.jnt_limited[jid]
        geoms = np.flatnonzero(world.geom_segment == PERSON_SEGMENTATION_ID[who])
        # One merged mesh per body that carries geometry: the user's hands are drawn with its
        # forearms, the agent's apart (its own camera shows them).
        assert len(geoms) == (12 if who == "agent" else 10)
        assert (model.geom_contype[geoms] == 0).all() and (model.geom_conaffinity[geoms] == 0).all()
        hands = [g for g in geoms if model.geom(g).name.endswith("_hand")]
        assert len(hands) == (2 if who == "agent" else 0)
        assert (model.geom_group[hands] == GROUP_HANDS).all()
        own = {GROUP_AGENT: "agent", GROUP_USER: "user"}
        assert {own[int(model.geom_group[g])] for g in geoms if g not in hands} == {who}


def test_people_are_person_sized_and_the_look_comes_from_the_seed():
    world = build_world(_scene(seed=5))
    data = world.data
    for who, height in (("agent", 1.6), ("user", 1.7)):
        head = data.xpos[world.model.body(f"{who}/head").id]
        foot = data.xpos[world.model.body(f"{who}/right_foot").id]
        assert 0.8 * height < head[2] < height and foot[2] < 0.1 * height
    # The same seed gives the same look in a fresh process (with another string hash seed).
    code = "from legent_gym.world.humanoid import appearance_for; print([repr(appearance_for('user', s)) for s in range(12)])"
    fresh = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120, check=True,
                           env={**os.environ, "PYTHONHASHSEED": "123"})
    assert fresh.stdout.strip() == str([repr(appearance_for("user", s)) for s in range(12)])
    looks = {appearance_for("user", s) for s in range(12)}
    assert len(looks) > 6 and appearance_for("agent", 5) == appearance_for("agent", 6)
    assert all(look.silhouette != "robot" for look in looks)


def test_ik_reaches_500_random_reachable_targets_within_2cm_and_keeps_the_limits():
    ik = ArmIK(1.6, appearance_for("agent", 0))
    rng = np.random.default_rng(0)
    errors = []
    for i in range(500):
        side = ("right", "left")[i % 2]
        low, high = JOINT_LOW[list(ARM_JOINTS[side])], JOINT_HIGH[list(ARM_JOINTS[side])]
        pose = rng.uniform(low, high)
        pose[3] = rng.uniform(math.radians(15), high[3])  # a bent elbow: inside the workspace
        target = ik.hand(side, pose)
        found = ik.solve(side, target)
        assert found.ok, found.reason
        assert (found.angles >= low - 1e-9).all() and (found.angles <= high + 1e-9).all()
        errors.append(float(np.linalg.norm(ik.hand(side, found.angles) - target)))
    assert max(errors) <= 0.02


def test_ik_refuses_a_target_out_of_reach_with_the_reason_and_shows_the_attempt():
    ik = ArmIK(1.6, appearance_for("agent", 0))
    far = ik.solve("right", (1.5, -0.2, 1.0))
    assert not far.ok and "out of the arm's reach" in far.reason
    attempt = ik.towards("right", (1.5, -0.2, 1.0))
    assert not attempt.ok and attempt.reason == far.reason
    shoulder = ik.proportions.shoulder("right")
    reach = np.linalg.norm(attempt.hand - shoulder)
    assert reach > 0.9 * ik.proportions.arm_length  # the arm is stretched out towards it
    direction = (np.array([1.5, -0.2, 1.0]) - shoulder) / np.linalg.norm(np.array([1.5, -0.2, 1.0]) - shoulder)
    assert (attempt.hand - shoulder) @ direction / reach > 0.99


def test_walking_swings_the_legs_by_distance_and_standing_is_idle(world):
    body = Body(world, "agent", other="user")
    hip = world.model.jnt_qposadr[world.model.joint("agent/right_hip").id]
    body.begin_batch()
    body.move_forward(0.4)
    body.end_batch()
    walking = world.data.qpos[hip]
    assert abs(walking) > math.radians(5)
    body.begin_batch()
    body.rotate_right(30)
    body.end_batch()
    assert world.data.qpos[hip] == 0.0
    # The phase is a function of the distance walked: the same distance, the same pose.
    a = joint_angles(Keyframe(0, 0, 0, 0, walked=0.4, walking=True), 1.6)
    b = joint_angles(Keyframe(3, 1, 90, 0, walked=0.4, walking=True), 1.6)
    assert np.array_equal(a, b)
    neck = world.model.jnt_qposadr[world.model.joint("agent/neck").id]
    body.rotate_down(40)
    assert world.data.qpos[neck] > math.radians(15)


def test_a_reach_points_the_hand_at_the_target_and_a_far_one_fails_with_the_arm_out():
    world = build_world(validate_scene({**ROOM, "agent": {"position": [1, 2], "yaw": 0},
                                        "user": {"position": [6, 3], "yaw": 180},
                                        "objects": [{"id": 1, "asset": "apple", "kind": "interactable", "position": [1.5, 2.0, 0.0]},
                                                    {"id": 2, "asset": "apple", "kind": "interactable", "position": [3.5, 2.0, 0.0]}]}))
    body = Body(world, "agent", other="user")
    site = world.model.site("agent/right_hand").id
    far = body.grab(2)
    assert not far.ok and "out of reach" in far.reason
    hand = world.data.site_xpos[site]
    assert hand[0] > 1.35  # the arm is stretched forward, towards the far apple
    ok = body.grab(1)
    assert ok.ok and body.state.held == 1
    # Carrying: the object is between the hands.
    left = world.data.site_xpos[world.model.site("agent/left_hand").id]
    right = world.data.site_xpos[site]
    centre = world.object_centre(1)
    assert np.linalg.norm((left + right) / 2 - centre) < 0.08
    for jid in range(world.model.njnt):
        if world.model.jnt_limited[jid] and world.model.joint(jid).name.startswith("agent/"):
            value = world.data.qpos[world.model.jnt_qposadr[jid]]
            low, high = world.model.jnt_range[jid]
            assert low - 1e-9 <= value <= high + 1e-9


def test_handing_over_holds_the_object_out_to_the_user():
    world = build_world(validate_scene({**ROOM, "agent": {"position": [1, 2], "yaw": 0},
                                        "user": {"position": [2.5, 2], "yaw": 180},
                                        "objects": [{"id": 1, "asset": "apple", "kind": "interactable", "position": [1.5, 2.0, 0.0]}]}))
    body = Body(world, "agent", other="user")
    assert body.grab(1).ok
    near = world.object_centre(1)[0] - body.state.x
    body.rotate_right(180)  # facing away: carried close
    away = abs(world.object_centre(1)[0] - body.state.x)
    assert near > away + 0.1


def test_the_agent_sees_its_hands_and_what_it_holds_but_not_its_body():
    world = build_world(validate_scene({**ROOM, "agent": {"position": [1, 2], "yaw": 0},
                                        "user": {"position": [6, 3], "yaw": 180},
                                        "objects": [{"id": 1, "asset": "apple", "kind": "interactable", "position": [1.5, 2.0, 0.0]}]}))
    body = Body(world, "agent", other="user")
    assert body.grab(1).ok
    body.rotate_down(60)
    r = Renderer(world, 96, 96)
    seg = r.segmentation("agent")
    names = {world.model.geom(g).name for g in np.unique(r.geom_ids("agent")) if g >= 0}
    assert any(n in ("agent/right_hand", "agent/left_hand") for n in names)
    assert not any(n.startswith("agent/") and not n.endswith("_hand") for n in names)
    assert (seg == PERSON_SEGMENTATION_ID["agent"]).any() and (seg == 1).any()
    r.close()


def test_every_part_of_a_person_carries_its_segmentation_id(world):
    body = Body(world, "agent", other="user")
    body.place(1.0, 2.0, 0.0)
    r = Renderer(world, 96, 96)
    seg, ids = r.segmentation("agent"), r.geom_ids("agent")
    user = seg == PERSON_SEGMENTATION_ID["user"]
    assert user.sum() > 20
    names = {world.model.geom(g).name for g in np.unique(ids[user])}
    assert all(n.startswith("user/") for n in names) and len(names) > 5
    assert not (seg == PERSON_SEGMENTATION_ID["agent"]).any()
    # A free camera sees both whole people, and the ceilings are left out of it.
    both = r.segmentation(FreeCamera((2.5, 2.0, 0.9), 6.0, azimuth=90, elevation=-20))
    assert (both == PERSON_SEGMENTATION_ID["agent"]).sum() > 20 and (both == PERSON_SEGMENTATION_ID["user"]).sum() > 20
    r.close()


def test_frames_per_step_show_the_walk_and_put_the_world_back():
    env = ExpertInfo(gym.make("Legent/BringMe-OneRoom-v0", width=48, height=48, frames_per_step=4,
                              render_mode="rgb_array_list", render_size=64))
    plain = ExpertInfo(gym.make("Legent/BringMe-OneRoom-v0", width=48, height=48))
    obs, info = env.reset(seed=3)
    obs2, info2 = plain.reset(seed=3)
    assert len(env.render()) == 1
    done = False
    while not done:
        action = info["expert_action"]
        obs, _, term, trunc, info = env.step(action)
        obs2, _, _, _, info2 = plain.step(action)
        frames = env.render()
        assert len(info["frames"]) == 3 and len(frames) == 4
        assert all(f.shape == (48, 48, 3) for f in info["frames"]) and frames[0].shape == (64, 64, 3)
        assert np.array_equal(obs["rgb"], obs2["rgb"])  # the frames between change no observation
        if "move_forward" in info["action_text"]:
            assert not np.array_equal(info["frames"][0], obs["rgb"])
        done = term or trunc
    assert info["success"]
    with pytest.raises(ValueError, match="frames_per_step"):
        gym.make("Legent/ComeHere-OneRoom-v0", frames_per_step=0)
    env.close()
    plain.close()


def test_the_same_seed_gives_the_same_people():
    def views():
        env = gym.make("Legent/ComeHere-TwoRoom-v0", width=64, height=64, segmentation=True)
        obs, _ = env.reset(seed=11)
        out = [obs["rgb"]]
        for action in ("move_forward(0.6)", "rotate_right(40)", "rotate_down(20)", "grab()"):
            obs, *_ = env.step(action)
            out.append(obs["rgb"])
        env.close()
        return out
    assert all(np.array_equal(a, b) for a, b in zip(views(), views()))


def test_the_map_draws_people_with_their_heading():
    scene = _scene()
    a = draw_topdown_map(scene, size=400, labels=False, people={"agent": (1.0, 2.0, 0.0), "user": (4.0, 2.0, 180.0)})
    b = draw_topdown_map(scene, size=400, labels=False, people={"agent": (1.0, 2.0, 90.0), "user": (4.0, 2.0, 180.0)})
    assert np.array_equal(a, draw_topdown_map(scene, size=400, labels=False))  # the spawns by default
    changed = np.argwhere((a != b).any(axis=2))
    assert len(changed) > 50
    # Only around the agent, whose heading changed.
    centre = changed.mean(axis=0)
    assert abs(centre[1] - a.shape[1] * (1.0 / 8.0)) < a.shape[1] * 0.1


def test_the_scripted_user_walks_and_looks_at_the_agent_when_spoken_to():
    pytest.importorskip("pettingzoo")
    import legent_gym.multiagent as ma
    from legent_gym.multiagent.single_agent import SingleAgentEnv

    for partner in ("still", "wander"):
        env = SingleAgentEnv(ma.parallel_env(task="ComeHere", layout="TwoRoom", width=32, height=32), partner=partner)
        env.reset(seed=5)  # a house where the wandering user does not reach the agent in these steps
        ctx = env.episode.require()
        user, agent = ctx.user, ctx.agent
        user.place(*user.xy, (math.degrees(math.atan2(agent.xy[1] - user.xy[1], agent.xy[0] - user.xy[0])) + 180))
        hip = ctx.world.model.jnt_qposadr[ctx.world.model.joint("user/right_hip").id]
        env.step('speak("over here")')
        env.step("rotate_down(1)")  # the user hears it at its next turn
        bearing = math.degrees(math.atan2(agent.xy[1] - user.xy[1], agent.xy[0] - user.xy[0]))
        off = (bearing - user.state.yaw + 180) % 360 - 180
        assert abs(off) < 91  # turned towards the agent (90 degrees a step at most)
        if partner == "wander":
            walked = False
            for _ in range(6):
                env.step("rotate_right(10)")
                walked = walked or abs(ctx.world.data.qpos[hip]) > 0.05
            assert walked  # the same body, the same walk cycle
        env.close()
    # Both people walk in the frames within a step of the multi-agent env (the agent's views).
    env = SingleAgentEnv(ma.parallel_env(task="ComeHere", width=32, height=32, frames_per_step=3), partner="wander")
    env.reset(seed=1)
    _, _, _, _, info = env.step("move_forward(0.5)")
    assert len(info["frames"]) == 2 and info["frames"][0].shape == (32, 32, 3)
    env.close()


def test_a_video_shows_the_frames_within_steps():
    pytest.importorskip("av")
    from legent_gym.data.rollout import expert_policy, make_env, record_episode
    from legent_gym.data.video import episode_video, read_video

    env = make_env("Legent/ComeHere-OneRoom-v0", {"width": 48, "height": 48, "frames_per_step": 3}, expert=True)
    episode = record_episode(env, expert_policy, seed=2, attempt=0, env_id="Legent/ComeHere-OneRoom-v0")
    env.close()
    assert episode.success and all(len(b) == 2 for b in episode.between)
    frames = read_video(episode_video(episode))
    assert len(frames) == 3 * episode.steps + 1


def test_collect_writes_the_frames_within_steps_into_its_videos(tmp_path):
    pytest.importorskip("av")
    import json

    from legent_gym.cli import main
    from legent_gym.data.video import read_video

    assert main(["collect", "Legent/ComeHere-OneRoom-v0", "--episodes", "1", "--out", str(tmp_path / "c"),
                 "--format", "legent,video", "--frames-per-step", "3", "--width", "32", "--height", "32",
                 "--quiet"]) == 0
    (video,) = (tmp_path / "c" / "video").glob("*.mp4")
    record = json.loads((tmp_path / "c" / "legent" / "000000" / "trajectory.json").read_text())
    steps = record["steps"]
    assert steps >= 1
    assert len(read_video(video)) == 3 * steps + 1  # each step's observation and the 2 frames after it


def test_a_user_that_never_moves_is_one_mesh_with_the_same_picture():
    from legent_gym.world.builder import BuildOptions

    scene = _scene(seed=7)
    statue = build_world(scene, BuildOptions(user_articulated=False))
    moving = build_world(scene)
    users = [np.flatnonzero(w.geom_segment == PERSON_SEGMENTATION_ID["user"]) for w in (statue, moving)]
    assert len(users[0]) == 1 and len(users[1]) == 10
    for w in (statue, moving):  # the same (idle) pose in both
        Body(w, "user", other="agent").place(4.0, 2.0, 180.0)
    images = []
    for w in (statue, moving):
        r = Renderer(w, 128, 128)
        images.append((r.rgb("agent"), r.segmentation("agent")))
        r.close()
    (rgb_a, seg_a), (rgb_b, seg_b) = images
    person = seg_b == PERSON_SEGMENTATION_ID["user"]
    assert person.sum() > 100
    assert np.array_equal(seg_a == PERSON_SEGMENTATION_ID["user"], person)
    difference = np.abs(rgb_a.astype(int) - rgb_b.astype(int)).max(axis=2)
    assert (difference[~person] == 0).all()  # the rest of the view is the same
    # The same person on the same pixels; its shading differs a little (measured: 9 levels
    # on average, the one mesh against the ten).
    assert difference[person].mean() < 12
    # The single-agent envs build the still user; the PettingZoo envs the moving one.
    env = gym.make("Legent/ComeHere-OneRoom-v0", width=32, height=32)
    env.reset(seed=0)
    world = env.unwrapped.episode.world
    assert (world.geom_segment == PERSON_SEGMENTATION_ID["user"]).sum() == 1
    env.close()


def test_walk_poses_keep_the_joints_within_their_limits():
    for walked in np.linspace(0.0, 3.0, 61):
        for frame in (Keyframe(0, 0, 0, 60.0, walked=walked, walking=True),
                      Keyframe(0, 0, 0, -60.0, walked=walked, walking=False)):
            for shuffle in (0.0, 0.3, 0.8):
                q = joint_angles(frame, 1.7, shuffle=shuffle)
                assert (q >= JOINT_LOW - 1e-12).all() and (q <= JOINT_HIGH + 1e-12).all()

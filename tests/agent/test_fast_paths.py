"""The speed-ups of generation and stepping give exactly what the plain computations give.

Each fast path is checked against the straightforward computation it replaces (kept here
as the reference), on random and edge-case inputs: same booleans, same floats bit for bit.
"""

from __future__ import annotations

import math
import random

import mujoco
import numpy as np
import pytest
import trimesh
from scipy import ndimage

from legent_gym.agent.actions import ActionParseError, parse_actions
from legent_gym.agent.actions.parse import _parse_simple, _Parser
from legent_gym.agent.body import SKIN, Body, _circle_hit
from legent_gym.world.assets.model import AssetModel, Link, box_part, sphere_part
from legent_gym.world.builder import build_world
from legent_gym.world.generation import generate_house
from legent_gym.world.generation.floorplan import build_floorplan, choice_p, place_doors, plan_grid
from legent_gym.world.generation.furnish import AGENT_RADIUS, CHECK_MARGIN, room_spaces
from legent_gym.world.meshing import MeshAccumulator, Palette
from legent_gym.world.navigation import (
    NavGrid,
    _segment_clear,
    _segments_clear,
    clearance_at_least,
    walkable_from_free,
)


def _random_mask(rng: np.random.Generator) -> np.ndarray:
    h, w = (int(v) for v in rng.integers(1, 120, size=2))
    mask = np.ones((h, w), dtype=bool)
    for _ in range(int(rng.integers(0, 20))):
        r0, c0 = int(rng.integers(0, h)), int(rng.integers(0, w))
        mask[r0:r0 + int(rng.integers(1, 25)), c0:c0 + int(rng.integers(1, 25))] = False
    if rng.random() < 0.3:
        mask[rng.random((h, w)) < 0.02] = False
    return mask[::2, 1:] if rng.random() < 0.2 else mask  # sometimes not contiguous


def test_clearance_threshold_matches_scipy_distance_transform():
    rng = np.random.default_rng(0)
    for _ in range(150):
        mask = _random_mask(rng)
        res = float(rng.choice([0.05, 0.1, 0.037]))
        edt = ndimage.distance_transform_edt(mask)
        for _ in range(4):
            k = int(rng.integers(0, 300))
            exact = math.sqrt(k) * res  # right on a squared-distance boundary, and around it
            for d in (exact, math.nextafter(exact, 9.0), math.nextafter(exact, -9.0), float(rng.uniform(-0.1, 2))):
                assert np.array_equal(clearance_at_least(mask, d, res), edt * res >= d)
        r = float(rng.uniform(0.01, 0.5))
        assert np.array_equal(walkable_from_free(mask, r, res), edt * res >= r + 0.5 * res)


def test_single_segment_check_matches_the_vectorised_one():
    rng = np.random.default_rng(1)
    for _ in range(100):
        h, w = (int(v) for v in rng.integers(3, 30, size=2))
        mask = rng.random((h, w)) < rng.uniform(0.6, 1.0)
        for _ in range(60):
            a = rng.uniform(-2, max(h, w) + 2, size=2)
            b = rng.uniform(-2, max(h, w) + 2, size=2)
            kind = rng.integers(4)
            if kind == 1:  # along a grid line, through grid corners
                a, b = np.floor(a), np.floor(b)
            elif kind == 2:  # axis-parallel
                b = a.copy()
                b[int(rng.integers(2))] += rng.uniform(-8, 8)
            elif kind == 3:  # zero length
                b = a.copy()
            expected = bool(_segments_clear(mask, a, b[None, :])[0])
            assert _segment_clear(mask, *a.tolist(), *b.tolist()) == expected


def test_room_walkable_kept_up_to_date_equals_recomputing_it():
    rng = np.random.default_rng(2)
    for seed in range(4):
        grid = plan_grid(["bedroom", "living_room", "kitchen"], np.random.default_rng(seed), cell_range=(2.2, 2.8))
        fp = build_floorplan(grid, ["bedroom", "living_room", "kitchen"], wall_height=2.8)
        place_doors(fp, np.random.default_rng(seed), openness=1.0)
        for space in room_spaces(fp, np.random.default_rng(seed)):
            reach = space.reach
            bb = space.bbox
            for step in range(12):
                if step == 8:
                    reach.clear()
                x, y = rng.uniform(bb[0], bb[2]), rng.uniform(bb[1], bb[3])
                reach.add(np.array([x, y, x + rng.uniform(0.05, 1.5), y + rng.uniform(0.05, 1.5)]))
                expected = walkable_from_free(reach.floor & ~reach.occupied, AGENT_RADIUS + CHECK_MARGIN, reach.res)
                assert np.array_equal(reach.walkable(), expected)


def test_weighted_choice_draws_like_numpy():
    src = np.random.default_rng(3)
    for _ in range(500):
        n = int(src.integers(1, 10))
        w = np.round(src.random(n) * 10) + 1  # with ties
        p = w / w.sum()
        seed = int(src.integers(1 << 30))
        a, b = np.random.default_rng(seed), np.random.default_rng(seed)
        assert [int(a.choice(n, p=p)) for _ in range(3)] == [choice_p(b, p) for _ in range(3)]
        assert a.bit_generator.state == b.bit_generator.state


def test_icosphere_matches_trimesh():
    for radius in (0.03, 0.0412345, 1.0, 7.3):
        mesh = trimesh.creation.icosphere(subdivisions=1, radius=radius)
        part = sphere_part((0.1, 0.2, 0.3), radius, scale=(1.0, 1.0, 0.9))
        expected = np.asarray(mesh.vertices) * np.asarray((1.0, 1.0, 0.9)) + np.asarray((0.1, 0.2, 0.3))
        assert part.vertices.tobytes() == expected.tobytes()
        assert np.array_equal(part.faces, mesh.faces)


def test_model_bounds_are_cached_but_follow_new_parts():
    model = AssetModel("thing", "thing", [Link("base", [box_part((0, 0, 0.5), (1, 1, 1))])])
    first = model.bounds()
    first[0, 0] = 99.0  # a copy goes out: the cache is not corrupted
    assert model.bounds()[0, 0] == -0.5
    model.links[0].parts.append(box_part((2, 0, 0.5), (1, 1, 1)))
    assert model.bounds()[1, 0] == 2.5
    model.links = [Link("base", [box_part((0, 0, 0.1), (0.2, 0.2, 0.2))])]
    assert model.bounds()[1, 2] == pytest.approx(0.2)


def test_palette_texels_match_row_unique():
    rng = np.random.default_rng(4)
    acc = MeshAccumulator()
    for _ in range(40):
        v = rng.random((8, 3))
        acc.add(v, rng.integers(0, 8, size=(5, 3)), tuple(rng.choice([0.0, 0.25, 0.5, 1.0], size=3)) + (1.0,))
    mesh = acc.build()
    palette, reference = Palette(), Palette()
    colours, inverse = np.unique(mesh.face_rgb, axis=0, return_inverse=True)
    expected = np.array([reference.index(c / 255.0) for c in colours], dtype=np.int32)[inverse.reshape(-1)]
    assert np.array_equal(mesh.texel_indices(palette), expected)
    assert palette._index == reference._index


def test_simple_action_parsing_matches_the_full_parser():
    rnd = random.Random(5)
    names = ["move_forward", "rotate_right", "rotate_down", "speak", "interact", "grab", "put", "release",
             "open", "close", "finish", "jump", "Move_forward"]
    args = ["", "1", "1.", ".5", "+.5", "-3.25", "1e3", "1e", "1e400", "-0", "007", "+5", "12", "inf", '"hi"',
            "'hi'", '"a, b"', '"x\\"y"', "inner", "1 2", "1.2.3", " 3 ", "\t3", "\u00b9",
            "9" * 5000, "9" * 400]  # ids past int()'s digit limit, numbers past float range
    seps = [", ", ",", " , ", "", " ", ",\n"]
    simple = 0
    for _ in range(8000):
        calls = [rnd.choice(names) + rnd.choice(["", " "]) + "(" + rnd.choice(args) + ")"
                 for _ in range(rnd.randint(0, 3))]
        text = rnd.choice(["", " "]) + rnd.choice(seps).join(calls) + rnd.choice(["", ",", ", ", " ", "\n"])
        try:
            expected = _Parser(text).step()
        except ActionParseError as err:
            expected = err
        for _ in range(2):  # the second time through the per-call cache
            got = _parse_simple(text)
            if got is not None:
                simple += 1
                assert not isinstance(expected, Exception), text
                assert got == expected and [type(a) for a in got] == [type(a) for a in expected], text
        if isinstance(expected, Exception):
            with pytest.raises(ActionParseError) as caught:
                parse_actions(text)
            assert str(caught.value) == str(expected)
        else:
            assert parse_actions(text) == expected
    assert simple > 200  # the fast path was exercised


def _swept_everything(body: Body, direction_deg: float, distance: float) -> float:
    """free_distance without the clearance map's shortcut: every box swept."""
    if distance <= 0:
        return 0.0
    yaw = math.radians(direction_deg)
    fx, fy = math.cos(yaw), math.sin(yaw)
    exclude = body.world.object_body[body.state.held] if body.state.held is not None else -1
    clearance = body._clearance()
    r = body.options.radius
    best = min(distance, clearance.sweep(clearance.snapshot(exclude)[1], body.state.x, body.state.y, fx, fy,
                                         distance + SKIN, r) - SKIN)
    other = body._other_position()
    if other is not None:
        best = min(best, _circle_hit(body.state.x, body.state.y, fx, fy, other, r + body._other_radius(), distance))
    return max(0.0, best)


def _box_distance(boxes, x: float, y: float) -> np.ndarray:
    """Distance from (x, y) to every oriented box (0 inside)."""
    cx, cy, cos, sin, hx, hy = boxes.cx, boxes.cy, boxes.cos, boxes.sin, boxes.hx, boxes.hy
    px, py = cos * (x - cx) + sin * (y - cy), cos * (y - cy) - sin * (x - cx)
    return np.hypot(np.maximum(np.abs(px) - hx, 0.0), np.maximum(np.abs(py) - hy, 0.0))


def test_moves_sweep_only_when_needed_with_the_same_result():
    rng = np.random.default_rng(6)
    for seed, layout in ((0, "TwoRoom"), (1, "FourRoom")):
        scene = generate_house(seed, layout)
        world = build_world(scene)
        agent = Body(world, "agent", other="user")
        (x0, y0), (x1, y1) = scene.bounds()
        for k in range(600):
            if k == 200:  # things move: physics settles, a door swings
                door = next(iter(world.door_joint.values()), None)
                if door is not None:
                    world.data.qpos[world.model.jnt_qposadr[door]] *= 0.3
                for _ in range(30):
                    mujoco.mj_step(world.model, world.data)
            if k == 400 and world.free_objects:  # holding an object (it is left out)
                agent.state.held = world.free_objects[0]
            agent.place(rng.uniform(x0 - 0.3, x1 + 0.3), rng.uniform(y0 - 0.3, y1 + 0.3), rng.uniform(0, 360))
            distance = float(rng.choice([rng.uniform(0, 2), 2.0, rng.uniform(0, 0.05)]))
            assert agent.free_distance(agent.state.yaw, distance) == _swept_everything(agent, agent.state.yaw,
                                                                                      distance)


def test_sweep_finds_the_first_contact_a_fine_march_finds():
    """The exact sweep against a march in 1 mm steps, from free starts in a furnished house."""
    scene = generate_house(3, "TwoRoom")
    world = build_world(scene)
    agent = Body(world, "agent")
    clearance = agent._clearance()
    boxes = clearance.snapshot(-1)[1]
    r = agent.options.radius
    rng = np.random.default_rng(2)
    (x0, y0), (x1, y1) = scene.bounds()
    checked = touched = 0
    while checked < 300:
        x, y = rng.uniform(x0, x1), rng.uniform(y0, y1)
        if _box_distance(boxes, x, y).min() <= r + 1e-3:
            continue  # starts touching something: the march has no first contact to find
        yaw = rng.uniform(0, 2 * math.pi)
        fx, fy = math.cos(yaw), math.sin(yaw)
        length = 3.0
        contact = clearance.sweep(boxes, x, y, fx, fy, length, r)
        steps = np.arange(0.0, length + 1e-9, 0.001)
        first = next((t for t in steps if _box_distance(boxes, x + fx * t, y + fy * t).min() <= r), math.inf)
        if math.isinf(first):
            assert math.isinf(contact) or contact > length - 0.001
        else:
            touched += 1
            assert first - 0.001 <= contact <= first + 1e-9
        checked += 1
    assert touched > 100


def test_batched_moves_leave_the_world_as_unbatched_moves_do():
    scene = generate_house(0, "TwoRoom")
    worlds = [build_world(scene) for _ in range(2)]
    bodies = [Body(w, "agent", other="user") for w in worlds]
    for turn, move, tilt in ((30, 0.7, 5), (-80, 1.2, -10), (45, 0.3, 20)):
        with bodies[1].batched():
            for body in bodies:
                body.rotate_right(turn)
                body.move_forward(move)
                body.rotate_down(tilt)
            assert bodies[1]._unsynced  # not yet written to the world
    for name in ("mocap_pos", "mocap_quat", "xpos", "cam_xpos", "cam_xmat"):
        assert np.array_equal(getattr(worlds[0].data, name), getattr(worlds[1].data, name)), name


def test_interactions_inside_a_batch_see_the_moves_before_them():
    scene = generate_house(2, "TwoRoom")
    worlds = [build_world(scene) for _ in range(2)]
    bodies = [Body(w, "agent", other="user") for w in worlds]
    item = next(o for o in scene.objects if o.kind == "interactable" and o.on is not None)
    stand = NavGrid.from_scene(scene).standing_point(item.id, reach=1.0)
    centre = item.position
    yaw = math.degrees(math.atan2(centre[1] - stand[1], centre[0] - stand[0]))
    outcomes = []
    for k, body in enumerate(bodies):
        body.place(stand[0], stand[1], yaw)
        steps = [lambda b: b.grab(item.id), lambda b: b.rotate_right(-40), lambda b: b.move_forward(0.2),
                 lambda b: b.put(item.on), lambda b: b.rotate_right(30)]
        if k == 0:
            outcomes.append([step(body).ok for step in steps])
        else:
            with body.batched():
                outcomes.append([step(body).ok for step in steps])
    assert outcomes[0] == outcomes[1] and outcomes[0][0] and outcomes[0][3]  # grabbed and put down
    for name in ("qpos", "qvel", "mocap_pos", "mocap_quat", "xpos", "cam_xpos"):
        assert np.array_equal(getattr(worlds[0].data, name), getattr(worlds[1].data, name)), name

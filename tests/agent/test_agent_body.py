"""The agent's body: moves that stop at obstacles, and interactions that succeed or say why not."""

from __future__ import annotations

import math

import numpy as np
import pytest

from legent_gym.agent.body import Body
from legent_gym.world.builder import build_world
from legent_gym.world.geometry import object_footprint
from legent_gym.world.scene import load_scene


@pytest.fixture()
def house(example_scene_paths):
    scene = load_scene(next(p for p in example_scene_paths if p.stem == "two_room_furnished"))
    world = build_world(scene)
    return scene, world, Body(world, "agent", other="user")


def _first(scene, asset):
    return next(o for o in scene.objects if o.asset == asset)


def _aim(agent, point):
    d = np.asarray(point[:2]) - agent.position
    yaw = math.degrees(math.atan2(d[1], d[0]))
    pitch = math.degrees(math.atan2(agent.options.camera_height - point[2], float(np.linalg.norm(d))))
    agent.place(agent.state.x, agent.state.y, yaw, pitch)


def test_move_stops_at_an_obstacle_and_reports_it(house):
    scene, world, agent = house
    wardrobe = _first(scene, "wardrobe")
    front = wardrobe.position[0] + world.assets[wardrobe.id].size[1] / 2  # it faces +x
    agent.place(2.0, wardrobe.position[1], 180)  # facing the wardrobe
    out = agent.move_forward(2.0)
    assert out.ok and "blocked" in out.reason
    # Stops a body radius (and a small margin) short of the wardrobe's front.
    assert out.moved == pytest.approx(2.0 - front - agent.options.radius, abs=0.05)
    assert agent.move_forward(1.0).moved < 0.05
    agent.place(2.0, 2.2, 90)  # north: the bed's foot is ~0.8 m away
    assert agent.move_forward(2.0).moved < 1.0


def test_move_through_an_open_door_and_not_a_closed_one(house):
    scene, world, agent = house
    agent.place(4.0, 3.0, 0)  # in front of the inner door (x = 5), facing it
    assert agent.move_forward(2.0).moved == pytest.approx(2.0)
    agent.place(4.0, 3.0, 0)
    assert agent.close("inner").ok
    assert agent.move_forward(2.0).moved < 0.8


def test_grab_succeeds_and_fails_with_reasons(house):
    scene, world, agent = house
    desk = _first(scene, "desk")
    item = next(o for o in scene.objects if o.on == desk.id)
    agent.place(3.3, item.position[1], 0)
    _aim(agent, (*item.position[:2], item.position[2] + 0.02))
    out = agent.grab()
    assert out.ok and agent.state.held == item.id
    again = agent.grab()
    assert not again.ok and "hands are full" in again.reason
    agent.rotate_right(90)
    agent.move_forward(0.3)
    assert np.linalg.norm(world.object_position(item.id)[:2] - agent.position) < 0.6  # carried along


def test_grab_failures(house):
    scene, world, agent = house
    bed = _first(scene, "bed")
    agent.place(2.5, 2.3, 90, 35)  # looking at the bed
    out = agent.grab()
    assert not out.ok and "cannot be picked up" in out.reason
    agent.place(2.0, 2.2, 180, 0)
    far = agent.grab(next(o.id for o in scene.objects if o.on == _first(scene, "sofa").id))
    assert not far.ok and "out of reach" in far.reason
    assert "no object" in agent.grab(999).reason
    agent.place(2.5, 2.5, 0, -60)  # looking at the ceiling
    assert "nothing to interact with" in agent.grab().reason
    del bed


def test_put_succeeds_and_fails_with_reasons(house):
    scene, world, agent = house
    assert "not holding anything" in agent.put().reason
    desk = _first(scene, "desk")
    item = next(o for o in scene.objects if o.on == desk.id)
    agent.place(3.3, item.position[1], 0)
    _aim(agent, (*item.position[:2], item.position[2] + 0.02))
    assert agent.grab().ok
    agent.place(2.25, 2.2, 90, 40)  # looking down at the bed, between the orange and the banana
    put = agent.put()
    assert put.ok and put.target == _first(scene, "bed").id and agent.state.held is None
    rest = world.object_position(item.id)
    assert rest[2] > 0.3  # it lies on the bed, not on the floor
    agent.place(3.3, 1.1418, 0)
    _aim(agent, (4.3, 1.5, 0.8))
    assert agent.grab().ok
    agent.place(2.5, 2.5, 0, -60)
    assert "no surface" in agent.put().reason or "nothing" in agent.put().reason
    agent.place(2.0, 2.2, 180, 0)
    assert "out of reach" in agent.put(_first(scene, "sofa").id).reason


def test_open_and_close_drawers_and_doors(house):
    scene, world, agent = house
    dresser = _first(scene, "dresser")
    agent.place(dresser.position[0], dresser.position[1] + 0.95, 270, 50)
    assert agent.look().object_id == dresser.id
    assert agent.open().ok
    again = agent.open()
    assert not again.ok and "already open" in again.reason
    assert agent.close().ok
    agent.place(4.2, 3.0, 0, 10)
    assert agent.close("inner").ok
    assert "already closed" in agent.close("inner").reason
    assert agent.open("inner").ok
    assert "no door" in agent.open("garage").reason
    bed = _first(scene, "bed")
    agent.place(2.5, 2.6, 90, 35)
    out = agent.open(bed.id)
    assert not out.ok and "nothing to open" in out.reason


def test_pitch_is_clamped(house):
    _, _, agent = house
    out = agent.rotate_down(200)
    assert agent.state.pitch == 60 and "clamped" in out.reason


def test_the_head_camera_follows_the_body():
    # mj_kinematics alone leaves cameras where they were: every frame would be the spawn view.
    import gymnasium as gym

    import legent_gym  # noqa: F401

    env = gym.make("Legent/ComeHere-OneRoom-v0", width=32, height=32)
    first, _ = env.reset(seed=0)
    turned, *_ = env.step("rotate_right(90)")
    tilted, *_ = env.step("rotate_down(40)")
    assert np.abs(first["rgb"].astype(int) - turned["rgb"]).mean() > 1.0
    assert np.abs(turned["rgb"].astype(int) - tilted["rgb"]).mean() > 1.0
    env.close()


def _facing(agent, target_xy, start_xy):
    d = np.asarray(target_xy) - np.asarray(start_xy)
    agent.place(start_xy[0], start_xy[1], math.degrees(math.atan2(d[1], d[0])))


@pytest.mark.parametrize("asset", ["sofa", "coffee_table", "bed", "dining_table", "desk"])
def test_low_and_raised_furniture_blocks_the_whole_body(asset):
    """A sofa's seat, a table's top and a bed's frame stop the body at their edge, at
    whatever height of its band they are (not only where a ray would pass)."""
    from legent_gym.world.generation import generate_house

    for seed in range(40):
        scene = generate_house(seed, "TwoRoom")
        found = [o for o in scene.objects if o.asset == asset]
        if found:
            break
    else:
        pytest.skip(f"no {asset} in the first 40 houses")
    world = build_world(scene)
    agent = Body(world, "agent")
    obj = found[0]
    corners = object_footprint(scene, obj)
    centre = corners.mean(axis=0)
    # Walk at the piece from every side where there is floor: never closer than a body radius.
    walked = 0
    for angle in range(0, 360, 20):
        a = math.radians(angle)
        start = centre + 2.0 * np.array([math.cos(a), math.sin(a)])
        agent.place(*start, 0.0)
        if agent.free_distance(angle + 180, 0.01) < 0.01:
            continue  # starts against something else
        _facing(agent, centre, start)
        agent.move_forward(2.0)
        walked += 1
        gap = _distance_to_polygon(agent.position, corners)
        assert gap >= agent.options.radius - 0.02, (asset, angle, gap)
    assert walked > 0


def _distance_to_polygon(point, corners) -> float:
    """Distance from a point to a convex polygon (0 inside)."""
    p = np.asarray(point, dtype=float)
    if _point_in(corners, p):
        return 0.0
    best = math.inf
    for a, b in zip(corners, np.roll(corners, -1, axis=0)):
        ab = b - a
        t = float(np.clip((p - a) @ ab / (ab @ ab), 0.0, 1.0))
        best = min(best, float(np.linalg.norm(p - (a + t * ab))))
    return best


def test_the_body_cannot_leave_the_house_through_an_outside_door():
    from legent_gym.world.generation import generate_house

    for seed in range(60):
        scene = generate_house(seed, "TwoRoom")
        outside = [d for d in scene.doors if "exterior" in d.connects and d.openness > 0.5]
        if outside:
            break
    else:
        pytest.skip("no open outside door in the first 60 houses")
    door = outside[0]
    wall = scene.wall(door.wall)
    world = build_world(scene)
    agent = Body(world, "agent")
    (x0, y0), (x1, y1) = wall.start, wall.end
    ux, uy = (x1 - x0) / wall.length, (y1 - y0) / wall.length
    mid = np.array([x0 + ux * door.offset, y0 + uy * door.offset])
    for side in (1.0, -1.0):  # one side is the room: start 1 m inside, walk out through the middle
        start = mid + side * np.array([-uy, ux])
        inside = any(_point_in(room.polygon, start) for room in scene.rooms)
        if not inside:
            continue
        _facing(agent, mid - side * np.array([-uy, ux]), start)
        out = agent.move_forward(3.0)
        assert "blocked" in out.reason
        assert any(_point_in(room.polygon, agent.position) for room in scene.rooms)
        return
    pytest.fail("neither side of the door is in a room")


def _point_in(polygon, xy) -> bool:
    from legent_gym.world.geometry import points_in_polygon

    return bool(points_in_polygon(np.asarray([xy], dtype=float), np.asarray(polygon, dtype=float))[0])


def test_a_put_keeps_clear_of_what_stands_there(house):
    """Each object on a surface is a circle round its footprint, as the item is: a spot
    whose circle meets one is taken (an item set down touching it would be thrown off)."""
    scene, world, agent = house
    bed = _first(scene, "bed")
    vase = next(o for o in scene.objects if o.asset == "vase")
    orange = next(o for o in scene.objects if o.asset == "orange" and o.on == bed.id)
    touching = world.assets[vase.id].footprint_radius() + world.assets[orange.id].footprint_radius()
    x, y, z = orange.position
    assert "no room" in agent.free_spot(bed.id, np.array([x + touching, y, z]), vase.id)
    spot = agent.free_spot(bed.id, np.array([x + touching + 0.05, y, z]), vase.id)
    assert not isinstance(spot, str) and spot[0] == pytest.approx(x + touching + 0.05)

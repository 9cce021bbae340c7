"""The outside (ground, sky) and the daylight: seen through exterior doors and windows, never
colliding, never an object, not over the top-down view, and no change to anything else."""

from __future__ import annotations

import math

import mujoco
import numpy as np
import pytest

from legent_gym.world import outside
from legent_gym.world.builder import GROUP_CEILING, BuildOptions, build_world
from legent_gym.world.generation import generate_house
from legent_gym.world.geometry import door_leads_outside, points_in_polygon, wall_frame
from legent_gym.world.rays import VIEW_GROUPS
from legent_gym.world.render import Renderer
from legent_gym.world.scene import Light

SIZE = 64


@pytest.fixture(scope="module")
def house():
    """A generated house with a door to the outside and windows."""
    for seed in range(20):
        scene = generate_house(seed, "FourRoom")
        if scene.windows and any(door_leads_outside(scene.wall(d.wall), d) for d in scene.doors):
            return scene
    pytest.fail("no generated house with a door to the outside and a window")


def _geom(world, name: str) -> int:
    return mujoco.mj_name2id(world.model, mujoco.mjtObj.mjOBJ_GEOM, name)


def _in_house(scene, point) -> bool:
    return any(points_in_polygon(np.asarray([point]), np.asarray(r.polygon))[0] for r in scene.rooms)


def _look_out(world, wall_id: str, offset: float, z: float) -> None:
    """Stand the agent 0.3 m inside an opening of an exterior wall, its eyes on the point
    ``z`` metres up in the opening, looking out."""
    scene = world.scene
    start, u, left, _ = wall_frame(scene.wall(wall_id))
    centre = start + u * offset
    side = next(s for s in (1.0, -1.0) if _in_house(scene, centre + s * 0.3 * left)
                and not _in_house(scene, centre - s * 0.3 * left))
    x, y = centre + side * 0.3 * left
    eye = world.options.agent.camera_height
    world.set_body_pose("agent", x, y, math.degrees(math.atan2(-side * left[1], -side * left[0])),
                        math.degrees(math.atan2(eye - z, 0.3)))
    mujoco.mj_forward(world.model, world.data)


def _open_exterior_door(world):
    scene = world.scene
    door = next(d for d in scene.doors if door_leads_outside(scene.wall(d.wall), d))
    if door.id in world.door_joint:
        joint = world.door_joint[door.id]
        lo, hi = world.model.jnt_range[joint]
        world.data.qpos[world.model.jnt_qposadr[joint]] = hi if abs(hi) > abs(lo) else lo
    _look_out(world, door.wall, door.offset, world.options.agent.camera_height)
    return door


def test_outside_geoms_collide_with_nothing_and_are_no_object(house):
    world = build_world(house)
    model = world.model
    body = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, outside.BODY)
    assert body == model.nbody - 1  # the last body: no other element's id moved
    geoms = np.flatnonzero(model.geom_bodyid == body)
    assert sorted(geoms.tolist()) == sorted([_geom(world, "ground"), _geom(world, "sky")])
    assert geoms.min() == model.ngeom - 2
    assert (model.geom_contype[geoms] == 0).all() and (model.geom_conaffinity[geoms] == 0).all()
    assert (model.geom_group[geoms] == GROUP_CEILING).all() and not VIEW_GROUPS[GROUP_CEILING]
    assert (world.geom_object[geoms] == -1).all() and (world.geom_segment[geoms] == -1).all()


def test_the_house_is_the_same_model_with_or_without_its_outside(house):
    """Every element of the house has the same id and values, the statistics (which scale
    the renderer's near and far planes) are those of the house alone, and physics steps
    the same."""
    with_, without = build_world(house), build_world(house, BuildOptions(with_outside=False))
    a, b = with_.model, without.model
    assert a.stat.extent == pytest.approx(b.stat.extent, rel=1e-12)
    np.testing.assert_allclose(a.stat.center, b.stat.center, rtol=0, atol=1e-9)
    assert a.stat.meaninertia == b.stat.meaninertia
    assert a.stat.meanmass == pytest.approx(b.stat.meanmass, rel=1e-12)
    assert a.stat.meansize == pytest.approx(b.stat.meansize, rel=1e-12)
    for field in ("geom_type", "geom_pos", "geom_size", "geom_group", "geom_contype", "geom_bodyid",
                  "body_pos", "body_mass", "jnt_qposadr"):
        old = getattr(b, field)
        np.testing.assert_array_equal(getattr(a, field)[:len(old)], old, err_msg=field)
    assert (a.nq, a.nv, a.nu) == (b.nq, b.nv, b.nu)
    for world in (with_, without):
        for _ in range(50):
            mujoco.mj_step(world.model, world.data)
    np.testing.assert_array_equal(with_.data.qpos, without.data.qpos)


def test_an_open_exterior_door_shows_sky_and_ground_not_black(house):
    views = {}
    for with_outside in (True, False):
        world = build_world(house, BuildOptions(with_outside=with_outside))
        _open_exterior_door(world)
        renderer = Renderer(world, SIZE, SIZE)
        views[with_outside] = renderer.rgb("agent"), renderer.geom_ids("agent"), renderer.segmentation("agent")
        if with_outside:
            sky, ground = _geom(world, "sky"), _geom(world, "ground")
        renderer.close()
    rgb, ids, seg = views[True]
    centre = SIZE // 2
    # Straight ahead at eye height: the sky; straight below the horizon, further down: ground.
    assert ids[centre - 2, centre] == sky and ids[SIZE - 12, centre] == ground
    sky_px, ground_px = rgb[centre - 2, centre].astype(int), rgb[SIZE - 12, centre].astype(int)
    assert sky_px.min() > 100 and sky_px[2] > sky_px[0] + 30  # light blue, not black
    assert ground_px[1] > ground_px[2] + 20 and ground_px[1] > 50  # green
    # Segmentation shows them as it showed the void: -1.
    assert (seg[(ids == sky) | (ids == ground)] == -1).all()
    # Without the outside the same pixels were black: what this change is for.
    old_rgb, old_ids, old_seg = views[False]
    assert old_ids[centre - 2, centre] == -1 and old_rgb[centre - 2, centre].max() == 0
    np.testing.assert_array_equal(old_seg, seg)


def test_a_window_shows_the_outside(house):
    world = build_world(house)
    window = house.windows[0]
    _look_out(world, window.wall, window.offset, window.sill + window.height / 2)
    renderer = Renderer(world, SIZE, SIZE)
    ids = renderer.geom_ids("agent")
    rgb = renderer.rgb("agent")
    renderer.close()
    centre = SIZE // 2
    assert ids[centre, centre] in (_geom(world, "sky"), _geom(world, "ground"))
    assert rgb[centre, centre].max() > 60


def test_top_down_view_shows_the_house_not_the_sky(house):
    """The sky's lid is above the top-down camera: the house is drawn as without it, and the
    ground fills what lay black around it."""
    ids = {}
    for with_outside in (True, False):
        world = build_world(house, BuildOptions(with_outside=with_outside))
        renderer = Renderer(world, SIZE, SIZE)
        ids[with_outside] = renderer.geom_ids("topdown")
        if with_outside:
            sky, ground = _geom(world, "sky"), _geom(world, "ground")
        renderer.close()
    new, old = ids[True], ids[False]
    assert not (new == sky).any()
    house_px = old >= 0
    assert house_px.mean() > 0.3
    np.testing.assert_array_equal(new[house_px], old[house_px])
    assert (new[~house_px] == ground).all()


def test_daylight_within_the_light_budget():
    scene = generate_house(0, "TwoRoom")
    world = build_world(scene)
    model = world.model
    daylight = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_LIGHT, "daylight")
    assert daylight == model.nlight - 1 == len(scene.lights)  # the scene's lights, then the daylight
    assert model.light_type[daylight] == mujoco.mjtLightType.mjLIGHT_DIRECTIONAL
    assert model.light_castshadow[daylight] and model.light_dir[daylight][2] < 0
    # Eight scene lights: the first seven and the daylight (OpenGL draws at most eight).
    many = scene.model_copy(update={"lights": [Light(position=(1.0, 1.0, 2.5))] * 8})
    assert build_world(many).model.nlight == 8
    # The "flat" style has no lights: no daylight either.
    flat = scene.model_copy(update={"style": scene.style.model_copy(update={"preset": "flat"})})
    model = build_world(flat).model
    assert (model.light_diffuse[mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_LIGHT, "daylight")] == 0).all()

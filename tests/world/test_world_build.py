"""The builder and renderer on real scenes: assets, physics, segmentation, glTF, profiles."""

from __future__ import annotations

import math

import mujoco
import numpy as np
import pytest

from legent_gym.world.assets import registry
from legent_gym.world.builder import GROUP_COLLISION, BuildOptions, build_world
from legent_gym.world.materials import surface_pattern
from legent_gym.world.preview import fitted_camera, preview_scene
from legent_gym.world.render import FreeCamera, Renderer, set_texture_filters, shadow_map_size
from legent_gym.world.scene import ImportedAsset, load_scene, validate_scene

BUILTIN = registry.asset_ids(builtin=True)


@pytest.fixture(scope="module")
def two_room(example_scene_paths):
    return load_scene(next(p for p in example_scene_paths if p.stem == "two_room_furnished"))


@pytest.mark.parametrize("asset_id", BUILTIN)
def test_every_asset_builds_and_renders_non_blank(asset_id):
    world = build_world(preview_scene(asset_id, variant=3, kind="static"))
    renderer = Renderer(world, 64, 64)
    camera = fitted_camera(world)
    seg = renderer.segmentation(camera)
    rgb = renderer.rgb(camera)
    # The asset covers a real part of its own test view, and the view is not one flat colour.
    assert (seg == 0).mean() > 0.03, f"{asset_id} covers {(seg == 0).mean():.1%} of its preview"
    assert rgb.std() > 5
    renderer.close()


def _receptacle_world_pose(world, obj_id, rec):
    """World (x, y, z) of a receptacle's centre and the object's yaw (radians)."""
    obj = world.scene.object(obj_id)
    yaw = math.radians(obj.rotation[2])
    link = world.assets[obj_id].link(rec.link)
    offset = np.array(link.pos, dtype=float)
    if link.joint is not None and link.joint.kind == "slide":
        offset += np.asarray(link.joint.axis) * link.joint.range[1]  # drawers are opened first
    local = offset + np.array([rec.center[0], rec.center[1], rec.height])
    c, s = math.cos(yaw), math.sin(yaw)
    return np.array(obj.position) + np.array([c * local[0] - s * local[1], s * local[0] + c * local[1], local[2]]), yaw


RECEPTACLE_CASES = [(a, r.name) for a in BUILTIN for r in registry.make(a, 0).receptacles]


@pytest.mark.parametrize("asset_id,receptacle", RECEPTACLE_CASES, ids=[f"{a}-{r}" for a, r in RECEPTACLE_CASES])
def test_receptacle_holds_a_dropped_object(asset_id, receptacle):
    """An apple dropped 3 cm above a receptacle comes to rest on it."""
    model = registry.make(asset_id, 0)
    rec = next(r for r in model.receptacles if r.name == receptacle)
    base = {
        "rooms": [{"id": "r", "type": "test", "name": "floor", "polygon": [[-3, -3], [3, -3], [3, 3], [-3, 3]]}],
        "objects": [{"id": 0, "asset": asset_id, "position": [0, 0, 0], "rotation": [0, 0, 30]}],
        "agent": {"position": [2.5, 2.5]},
    }
    link = model.link(rec.link)
    if link.joint is not None:
        base["objects"][0]["joints"] = {rec.link: link.joint.range[1]}
    scene = validate_scene(base)
    probe = build_world(scene)
    target, _ = _receptacle_world_pose(probe, 0, rec)
    base["objects"].append({"id": 1, "asset": "apple", "position": [*target[:2], target[2] + 0.03],
                            "kind": "interactable", "on": 0})
    world = build_world(validate_scene(base))
    for _ in range(int(1.5 / world.model.opt.timestep)):
        mujoco.mj_step(world.model, world.data)
    rest = world.object_position(1)
    assert abs(rest[2] - target[2]) < 0.02, f"rests at z={rest[2]:.3f}, surface at {target[2]:.3f}"
    assert np.linalg.norm(rest[:2] - target[:2]) < 0.05
    assert np.linalg.norm(world.data.qvel[-6:-3]) < 0.05  # at rest


def test_example_house_is_stable_under_physics(two_room):
    """Small objects placed on surfaces stay within 2 cm over 2 s of simulation."""
    world = build_world(two_room)
    start = {i: world.object_position(i) for i in world.free_objects}
    for _ in range(int(2.0 / world.model.opt.timestep)):
        mujoco.mj_step(world.model, world.data)
    moved = {i: float(np.linalg.norm(world.object_position(i) - start[i])) for i in start}
    worst = max(moved, key=moved.get)
    assert moved[worst] < 0.02, f"object {worst} ({two_room.object(worst).asset}) moved {moved[worst]:.3f} m"


def _visible_by_ray(world, camera_pos, point, object_id) -> bool:
    """A ray from the camera to the point first hits the object's own visual geometry."""
    direction = point - camera_pos
    geomid = np.array([-1], dtype=np.int32)
    groups = np.array([1, 1, 0, 0, 0, 0], dtype=np.uint8)  # house and objects, not collision/avatars
    dist = mujoco.mj_ray(world.model, world.data, camera_pos, direction / np.linalg.norm(direction),
                         groups, 1, -1, geomid)
    return dist > 0 and geomid[0] >= 0 and world.geom_object[geomid[0]] == object_id


def test_segmentation_finds_every_visible_object(two_room):
    world = build_world(two_room)
    renderer = Renderer(world, 128, 128)
    checked = 0
    for x, y, yaw in [(2.0, 2.2, 0), (2.0, 2.2, 180), (8.6, 2.3, 180), (8.6, 2.3, 0), (3.0, 1.5, 90)]:
        world.set_body_pose("agent", x, y, yaw, pitch_deg=20)
        mujoco.mj_forward(world.model, world.data)
        seg = renderer.segmentation("agent")
        found = set(np.unique(seg[seg >= 0]).tolist())
        cam_id = world.model.camera("agent_camera").id
        cam_pos = world.data.cam_xpos[cam_id].copy()
        cam_mat = world.data.cam_xmat[cam_id].reshape(3, 3)
        for obj in two_room.objects:
            lo, hi = world.assets[obj.id].bounds()
            centre = world.object_position(obj.id) + (lo + hi) / 2 if obj.kind == "interactable" else \
                np.array(obj.position) + np.array([0, 0, (lo[2] + hi[2]) / 2])
            local = cam_mat.T @ (centre - cam_pos)
            if local[2] > -0.3:  # behind the camera (a MuJoCo camera looks along its -z)
                continue
            half_fov = math.radians(world.model.cam_fovy[cam_id] / 2) * 0.8
            if abs(local[0] / -local[2]) > math.tan(half_fov) or abs(local[1] / -local[2]) > math.tan(half_fov):
                continue
            extent = float(np.max(hi - lo))
            pixels = extent / -local[2] * (128 / 2) / math.tan(math.radians(world.model.cam_fovy[cam_id] / 2))
            if pixels >= 3 and _visible_by_ray(world, cam_pos, centre, obj.id):
                checked += 1
                assert obj.id in found, f"object {obj.id} ({obj.asset}) visible by ray but not segmented"
    assert checked >= 15


def test_segmentation_pixels_belong_to_their_objects(two_room):
    """A pixel labelled with an object id lies on that object: its depth matches a ray hit."""
    world = build_world(two_room)
    renderer = Renderer(world, 64, 64)
    seg = renderer.segmentation("agent")
    geoms = renderer.geom_ids("agent")
    assert (world.geom_object_lookup(geoms) == seg).all()
    assert len(set(seg[seg >= 0].tolist())) >= 5


def test_depth_matches_ray_distance(two_room):
    world = build_world(two_room)
    renderer = Renderer(world, 65, 65)
    depth = renderer.depth("agent")
    cam = world.model.camera("agent_camera").id
    pos = world.data.cam_xpos[cam]
    forward = -world.data.cam_xmat[cam].reshape(3, 3)[:, 2]
    geomid = np.array([-1], dtype=np.int32)
    dist = mujoco.mj_ray(world.model, world.data, pos, forward, np.array([1, 1, 1, 0, 0, 0], np.uint8), 1, -1, geomid)
    assert depth[32, 32] == pytest.approx(dist, rel=0.02)


def test_views_and_profiles(two_room):
    world = build_world(two_room)
    for profile in ("fast", "pretty"):
        r = Renderer(world, 80, 60, profile)
        for camera in ("agent", "user", "topdown", FreeCamera((5.5, 2.5, 0.5), 8, 90, -60)):
            img = r.rgb(camera)
            assert img.shape == (60, 80, 3) and img.dtype == np.uint8
            assert img.std() > 3, f"{profile}/{camera} is blank"
        a, b = r.rgb("agent"), r.rgb("agent")
        assert a is not b and (a == b).all()
        r.close()
    with pytest.raises(ValueError, match="unknown camera"):
        Renderer(world, 32, 32).rgb("nowhere")
    with pytest.raises(ValueError, match="render profile"):
        Renderer(world, 32, 32, "ultra")


def test_pretty_shadow_maps_scale_with_the_image(two_room):
    """The "pretty" profile's shadow maps are about eight texels per image pixel across,
    a power of two from 512 to 2048: what its renderer sets in the model's visual quality
    before it makes its context."""
    world = build_world(two_room)
    for size, side in ((48, 512), (96, 1024), (128, 1024), (224, 2048), (448, 2048)):
        r = Renderer(world, size, size, "pretty")
        assert r.rgb("agent").std() > 3
        assert world.model.vis.quality.shadowsize == side == shadow_map_size(size, size)
        r.close()


def test_agent_does_not_see_itself_but_sees_the_user():
    scene = validate_scene({
        "rooms": [{"id": "r", "type": "bedroom", "name": "room", "polygon": [[0, 0], [6, 0], [6, 4], [0, 4]]}],
        "agent": {"position": [1, 2], "yaw": 0}, "user": {"position": [4, 2], "yaw": 180},
    })
    world = build_world(scene)
    r = Renderer(world, 64, 64)
    geoms = r.geom_ids("agent")
    names = {world.model.geom(g).name for g in np.unique(geoms[geoms >= 0])}
    assert any(n.startswith("user/") for n in names) and not any(n.startswith("agent/") for n in names)
    geoms = r.geom_ids("user")
    names = {world.model.geom(g).name for g in np.unique(geoms[geoms >= 0])}
    assert any(n.startswith("agent/") for n in names) and not any(n.startswith("user/") for n in names)


def test_doors_and_drawers_are_joints(two_room):
    world = build_world(two_room)
    inner = world.door_joint["inner"]
    assert world.model.jnt_type[inner] == mujoco.mjtJoint.mjJNT_HINGE
    assert abs(world.data.qpos[world.model.jnt_qposadr[inner]]) == pytest.approx(math.pi / 2)
    dresser = next(o.id for o in two_room.objects if o.asset == "dresser")
    joints = world.object_joints[dresser]
    assert joints and all(world.model.jnt_type[j] == mujoco.mjtJoint.mjJNT_SLIDE for j in joints.values())
    wardrobe = next(o.id for o in two_room.objects if o.asset == "wardrobe")
    assert all(world.model.jnt_type[j] == mujoco.mjtJoint.mjJNT_HINGE for j in world.object_joints[wardrobe].values())


ARTICULATED_ASSETS = [a for a in BUILTIN if any(len(registry.make(a, v).links) > 1 for v in range(10))]
#: Assets whose doors turn about their back edge: a static piece is welded to the world, so
#: MuJoCo does not filter contacts between it and its doors, and such a door swung past a
#: right angle meets the carcass's side and is pushed back to it.
STOP_AT_RIGHT_ANGLE = {"wardrobe", "storage_cabinet", "vanity", "pantry_cabinet"}


@pytest.mark.parametrize("asset_id", ARTICULATED_ASSETS)
def test_doors_and_drawers_open_in_a_built_world(asset_id):
    """Each door and drawer of variants 0..9, set to its range's end, stays there under
    physics (or, a door of STOP_AT_RIGHT_ANGLE, at a right angle), all of them open at once
    too (no door or drawer runs into another), and moves nothing else; the simulation stays
    finite."""
    tried = 0
    for v in range(10):
        if len(registry.make(asset_id, v).links) == 1:
            continue
        world = build_world(preview_scene(asset_id, variant=v, kind="static"))
        model, data = world.model, world.data
        joints = list(world.object_joints[0].values())
        assert len(joints) == len(registry.make(asset_id, v).links) - 1
        for group in [joints, *([j] for j in joints)]:
            mujoco.mj_resetData(model, data)
            for j in group:
                data.qpos[model.jnt_qposadr[j]] = model.jnt_range[j][1]
            for _ in range(300):
                mujoco.mj_step(model, data)
            assert np.isfinite(data.qpos).all() and np.isfinite(data.qvel).all()
            for j in joints:
                q, hi = data.qpos[model.jnt_qposadr[j]], model.jnt_range[j][1]
                if j in group:
                    least = np.pi / 2 - 0.01 if asset_id in STOP_AT_RIGHT_ANGLE else hi - 1e-3
                    assert least <= q <= hi + 1e-3, (v, model.joint(j).name, q)
                else:
                    assert abs(q) < 0.01, (v, model.joint(j).name, q)
        tried += 1
    assert tried


def test_static_geometry_is_merged(two_room):
    """Few draw calls: one visual geom per object link, three for the whole house shell and
    one per patterned floor or wall surface (pattern and colour), two for its outside (ground
    and sky)."""
    world = build_world(two_room)
    people = world.geom_segment < -1
    visual = (world.model.geom_group != GROUP_COLLISION) & ~people
    n_links = sum(len(world.assets[o.id].links) for o in two_room.objects)
    n_leaves = sum(d.leaf for d in two_room.doors)
    surfaces = {(kind, s.material, s.rgba) for r in two_room.rooms for kind, s in (("floors", r.floor), ("walls", r.wall))
                if surface_pattern(s.material) not in (None, "paint")}
    assert surfaces  # the example's floors are patterned
    assert visual.sum() <= n_links + n_leaves + 3 + len(surfaces) + 2
    assert people.sum() == 12 + 10  # one merged mesh per moving part: the agent's hands apart
    naive = build_world(two_room, BuildOptions(naive=True))
    assert (naive.model.geom_group != GROUP_COLLISION).sum() > 3 * visual.sum()


def test_gltf_asset_imports_renders_and_collides(tmp_path):
    """A textured, vertex-coloured, multi-node GLB written by trimesh, used in a scene."""
    import trimesh
    from PIL import Image

    box = trimesh.creation.box(extents=(0.1, 0.1, 0.1))
    tex = np.zeros((8, 8, 3), dtype=np.uint8)
    tex[:4] = (255, 0, 0)
    tex[4:] = (0, 0, 255)
    uv = np.random.default_rng(0).uniform(0, 1, (len(box.vertices), 2))
    box.visual = trimesh.visual.TextureVisuals(uv=uv, image=Image.fromarray(tex))
    sphere = trimesh.creation.icosphere(subdivisions=1, radius=0.04)
    sphere.visual.vertex_colors = np.tile([0, 200, 0, 255], (len(sphere.vertices), 1))
    glb_scene = trimesh.Scene()
    glb_scene.add_geometry(box, node_name="body")
    glb_scene.add_geometry(sphere, node_name="knob", transform=trimesh.transformations.translation_matrix([0, 0.09, 0]))
    path = tmp_path / "gadget.glb"
    path.write_bytes(glb_scene.export(file_type="glb"))

    scene = validate_scene({
        "rooms": [{"id": "r", "type": "test", "name": "floor", "polygon": [[-2, -2], [2, -2], [2, 2], [-2, 2]]}],
        "assets": [ImportedAsset(id="gadget", source="gadget.glb", size=(0.15, 0.15, 0.15)).model_dump()],
        "objects": [{"id": 0, "asset": "gadget", "position": [0, 0, 0.3], "kind": "interactable"}],
        "agent": {"position": [1.5, 1.5]},
    }, asset_known=None)
    scene.base_dir = tmp_path
    world = build_world(scene)
    for _ in range(int(1.5 / world.model.opt.timestep)):
        mujoco.mj_step(world.model, world.data)
    assert abs(world.object_position(0)[2]) < 0.01  # fell and rests on the floor: it collides
    renderer = Renderer(world, 64, 64)
    seg = renderer.segmentation(FreeCamera((0, 0, 0.07), 0.5, 45, -30))
    assert (seg == 0).mean() > 0.05


@pytest.mark.parametrize("preset", ["realistic", "flat", "pastel", "night", "greyscale"])
def test_style_presets_change_the_look(two_room, preset):
    scene = two_room.model_copy(deep=True)
    scene.style.preset = preset
    img = Renderer(build_world(scene), 48, 48).rgb("agent")
    reference = Renderer(build_world(two_room), 48, 48).rgb("agent")
    assert img.std() > 3
    if preset == "realistic":
        assert (img == reference).all()
    else:
        assert np.abs(img.astype(int) - reference).mean() > 2
    if preset == "greyscale":
        assert np.abs(img[..., 0].astype(int) - img[..., 2]).mean() < 6  # only the lights tint it


def test_unknown_style_is_rejected(two_room):
    from legent_gym.world.scene import SceneError

    data = two_room.to_dict()
    data["style"]["preset"] = "vaporwave"
    with pytest.raises(SceneError, match="unknown style preset 'vaporwave'"):
        validate_scene(data)


def test_domain_randomisation_is_deterministic_and_changes_colours(two_room):
    from legent_gym.world.styles import randomize_appearance

    images = []
    for seed in (1, 1, 2):
        world = build_world(two_room)
        renderer = Renderer(world, 48, 48)
        before = renderer.rgb("agent")
        randomize_appearance(world, np.random.default_rng(seed))
        renderer.upload_textures()
        images.append(renderer.rgb("agent"))
        assert np.abs(images[-1].astype(int) - before).mean() > 2
    assert (images[0] == images[1]).all()
    assert not (images[0] == images[2]).all()


@pytest.mark.parametrize("yaw", [0, 37, 200])
def test_camera_pitch_looks_down_with_the_image_upright(yaw):
    """Looking down at the floor, the top of the image sees farther than the bottom."""
    scene = validate_scene({
        "rooms": [{"id": "r", "type": "test", "name": "room", "polygon": [[-5, -5], [5, -5], [5, 5], [-5, 5]]}],
        "agent": {"position": [0, 0], "yaw": yaw},
    })
    world = build_world(scene)
    world.set_body_pose("agent", 0, 0, yaw, pitch_deg=45)
    mujoco.mj_forward(world.model, world.data)
    depth = Renderer(world, 33, 33).depth("agent")
    height = world.options.agent.camera_height
    assert depth[16, 16] == pytest.approx(height / math.sin(math.radians(45)), rel=0.03)
    assert depth[2, 16] > depth[16, 16] > depth[30, 16]
    assert depth[16, 2] == pytest.approx(depth[16, 30], rel=0.02)  # level: left and right alike


def stock_renderer(model: mujoco.MjModel, height: int, width: int) -> mujoco.Renderer:
    """MuJoCo's own renderer, its textures sampled as ours are in the "fast" profile (it
    samples every texture trilinearly; it keeps its contexts in attributes of its own)."""
    stock = mujoco.Renderer(model, height, width)
    stock._gl_context.make_current()
    set_texture_filters(stock._mjr_context, model, "fast")
    return stock


def test_frames_match_mujocos_own_renderer_whatever_else_draws_in_between(two_room):
    """A frame sets only what changed since the last (the current GL context, the bound
    framebuffer, the camera). Interleaved with MuJoCo's stock renderer (its own GL
    context), another of our renderers (its own framebuffer) and other cameras, every
    image still equals the one MuJoCo's own ``mujoco.Renderer`` draws with the same
    settings, and the one a fresh renderer draws."""
    world, other_world = build_world(two_room), build_world(two_room)
    ours, other = Renderer(world, 64, 48), Renderer(other_world, 32, 32)
    option, camera, flags = ours.mujoco_settings("agent")
    stock = stock_renderer(world.model, 48, 64)
    stock.scene.flags[:] = flags

    def stock_rgb():
        stock.update_scene(world.data, camera, option)
        return stock.render()

    views = []
    for yaw in (0.0, 70.0, 140.0):
        world.set_body_pose("agent", 2.0, 2.0, yaw, 10.0)
        mujoco.mj_kinematics(world.model, world.data)
        mujoco.mj_camlight(world.model, world.data)
        expected = stock_rgb()  # the stock renderer's context is current now
        assert np.array_equal(ours.rgb("agent"), expected)
        other.rgb("agent")  # our other renderer binds its own framebuffer
        assert np.array_equal(ours.rgb("agent"), expected)
        ours.rgb("topdown"), ours.depth("agent")  # another camera, segmentation mode
        assert np.array_equal(ours.rgb("agent"), expected)
        views.append(expected)
    assert not np.array_equal(views[0], views[1])  # the poses do show different views
    fresh = Renderer(world, 64, 48)
    assert np.array_equal(fresh.rgb("agent"), views[-1])
    stock.close()


def test_a_free_camera_after_a_topdown_view_draws_as_before(two_room):
    # "topdown" sets the model's global fovy to the house's size; a free camera uses that
    # fovy, so it must set it back (also when another renderer drew the topdown view).
    world = build_world(two_room)
    free = FreeCamera((5.5, 2.5, 0.5), 8, 90, -60)
    first, other = Renderer(world, 48, 48), Renderer(world, 48, 48)
    before = first.rgb(free)
    first.rgb("topdown")
    assert np.array_equal(first.rgb(free), before)
    other.rgb("topdown")
    assert np.array_equal(first.rgb(free), before)


@pytest.mark.parametrize("seed", [3, 8])
def test_culling_leaves_out_unseen_geoms_and_draws_the_same_pixels(seed):
    """The agent's and user's cameras leave out geoms wholly outside their view. Over many
    poses (wide images, looking up and down, standing by walls), every RGB and segmentation
    image equals the one MuJoCo's own renderer draws from the full scene, and the culled
    scene does lack geoms."""
    from legent_gym.world.generation.house import generate_house

    world = build_world(generate_house(seed, "TwoRoom"))
    ours = Renderer(world, 80, 48)
    stock, stock_ids = stock_renderer(world.model, 48, 80), mujoco.Renderer(world.model, 48, 80)
    stock_ids.enable_segmentation_rendering()
    (lo_x, lo_y), (hi_x, hi_y) = world.scene.bounds()
    rng = np.random.default_rng(seed)
    left_out = []
    for i in range(40):
        camera = "agent" if i % 2 else "user"
        body = "agent" if camera == "agent" else "user"
        world.set_body_pose(body, rng.uniform(lo_x, hi_x), rng.uniform(lo_y, hi_y), rng.uniform(-180, 180),
                            rng.uniform(-60, 60))
        mujoco.mj_kinematics(world.model, world.data)
        mujoco.mj_camlight(world.model, world.data)
        option, cam, flags = ours.mujoco_settings(camera)
        stock.scene.flags[:] = flags
        stock.update_scene(world.data, cam, option)
        full = stock.scene.ngeom
        assert np.array_equal(ours.rgb(camera), stock.render()), f"view {i} ({camera})"
        left_out.append(full - ours._scene.ngeom)
        stock_ids.update_scene(world.data, cam, option)
        ids, types = np.moveaxis(stock_ids.render(), -1, 0)
        expected = np.where(types == mujoco.mjtObj.mjOBJ_GEOM, ids, -1)
        assert np.array_equal(ours.geom_ids(camera), expected), f"view {i} ({camera})"
    assert min(left_out) >= 0 and np.mean(left_out) > 5, left_out
    stock.close()
    stock_ids.close()

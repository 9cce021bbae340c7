"""Patterned materials as the builder draws them: the house's atlas of palette colours and
pattern tiles, floors and walls on repeating textures, domain randomisation over both,
and the ceiling lamps."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from legent_gym.world import materials
from legent_gym.world.builder import SURFACE_TEXTURE_PREFIX, BuildOptions, build_world
from legent_gym.world.meshing import PATTERN_MIN_SIZE, Atlas, pattern_variant
from legent_gym.world.render import FreeCamera, Renderer
from legent_gym.world.scene import load_scene, validate_scene
from legent_gym.world.styles import randomize_appearance


@pytest.fixture(scope="module")
def two_room(example_scene_paths):
    return load_scene(next(p for p in example_scene_paths if p.stem == "two_room_furnished"))


def _texture(model: mujoco.MjModel, name: str) -> np.ndarray:
    tex = model.texture(name)
    adr, w, h = int(tex.adr[0]), int(tex.width[0]), int(tex.height[0])
    return model.tex_data[adr:adr + w * h * 3].reshape(h, w, 3)


def _mesh_texcoords(model: mujoco.MjModel, geom: int) -> np.ndarray:
    """(faces, 3, 2) texture coordinates of each face corner of a mesh geom."""
    mesh = model.geom_dataid[geom]
    tc = model.mesh_texcoord[model.mesh_texcoordadr[mesh]:model.mesh_texcoordadr[mesh] + model.mesh_texcoordnum[mesh]]
    f0, nf = model.mesh_faceadr[mesh], model.mesh_facenum[mesh]
    return tc[model.mesh_facetexcoord[f0:f0 + nf]]


def test_wooden_faces_show_their_tile_of_the_atlas(two_room):
    """A wooden piece of furniture has faces whose corners span a whole tile of the atlas,
    and that tile is the wood pattern in the face's colour."""
    world = build_world(two_room)
    model, atlas = world.model, world.atlas
    width, height = atlas.size()
    image = _texture(model, "palette")
    assert image.shape == (height, width, 3)
    wood = [i for i, (pattern, _) in enumerate(atlas.tiles) if pattern == "wood"]
    assert wood, "the example's furniture has wooden parts"
    for slot in wood:
        x, y = atlas.slot_origin(slot)
        pattern, colour = atlas.tiles[slot]
        expected = materials.tile(pattern, pattern_variant(colour), colour)
        assert np.array_equal(image[y:y + materials.TILE, x:x + materials.TILE], expected)
    # Some object geom has a face spanning a wood tile: its corners lie within the tile and
    # one of its sides crosses most of it.
    spans = []
    for geom in np.flatnonzero(world.geom_object >= 0):
        if model.geom_type[geom] != mujoco.mjtGeom.mjGEOM_MESH or model.geom_matid[geom] != model.material("palette").id:
            continue
        corners = _mesh_texcoords(model, geom) * [width, height]
        size = np.ptp(corners, axis=1)
        spans.append(size.max(axis=1))
    assert max(s.max() for s in spans) >= materials.TILE - 2
    # Flat faces keep all three corners on one texel centre.
    assert any((s == 0).any() for s in spans)


def test_small_parts_and_unpatterned_materials_are_flat():
    from legent_gym.world.assets.model import box_part
    from legent_gym.world.meshing import _merged_many

    big_wood = box_part((0, 0, 0), (0.5, 0.3, 0.02), (0.6, 0.4, 0.2, 1), material="wood")
    small_wood = box_part((0, 0, 0), (PATTERN_MIN_SIZE / 2,) * 3, (0.6, 0.4, 0.2, 1), material="wood")
    big_plastic = box_part((0, 0, 0), (0.5, 0.3, 0.02), (0.2, 0.4, 0.6, 1), material="plastic")
    mesh, small, plastic = _merged_many([[big_wood], [small_wood], [big_plastic]])
    assert mesh.face_pattern is not None and (mesh.face_pattern >= 0).all()
    assert small.face_pattern is None and plastic.face_pattern is None
    # The board's long side (x) runs along u: the top face's u spans 0..1 over x.
    top = np.flatnonzero(mesh.normals[:, 2] > 0.5)
    corners = mesh.vertices[mesh.faces[top]]
    u = mesh.face_uv[top][..., 0]
    assert np.allclose(u, (corners[..., 0] + 0.25) / 0.5)


def test_floors_and_walls_repeat_their_pattern_every_period(two_room):
    world = build_world(two_room)
    model = world.model
    surfaces = [m for m in range(model.nmat) if model.material(m).name.startswith(SURFACE_TEXTURE_PREFIX)]
    assert surfaces
    for mat in surfaces:
        tex = model.texture(int(model.mat_texid[mat, mujoco.mjtTextureRole.mjTEXROLE_RGB]))
        assert tex.name.startswith(SURFACE_TEXTURE_PREFIX)
        geoms = np.flatnonzero(model.geom_matid == mat)
        if model.tex_width[model.mat_texid[mat, mujoco.mjtTextureRole.mjTEXROLE_RGB]] == 1:
            assert len(geoms) == 0  # an unused slot
            continue
        assert len(geoms) == 1  # one geom per (pattern, colour)
        mesh = model.geom_dataid[geoms[0]]
        v0, nv = model.mesh_vertadr[mesh], model.mesh_vertnum[mesh]
        f0, nf = model.mesh_faceadr[mesh], model.mesh_facenum[mesh]
        verts = model.mesh_vert[v0:v0 + nv][model.mesh_face[f0:f0 + nf]]  # (nf, 3, 3), in the geom's frame
        data = world.data
        world_verts = verts @ data.geom_xmat[geoms[0]].reshape(3, 3).T + data.geom_xpos[geoms[0]]
        uv = _mesh_texcoords(model, geoms[0])
        floor = np.abs(world_verts[..., 2]).max(axis=1) < 1e-6
        if floor.any():  # floor corners: u is x in periods (v is -y, rows top down)
            assert np.allclose(uv[floor][..., 0], world_verts[floor][..., 0] / materials.SURFACE_PERIOD, atol=1e-4)
            assert np.allclose(uv[floor][..., 1], -world_verts[floor][..., 1] / materials.SURFACE_PERIOD, atol=1e-4)
    # Unused slots are one texel; a used one is the pattern's tile in the surface's colour.
    used = [m for m in surfaces if model.tex_width[model.mat_texid[m, mujoco.mjtTextureRole.mjTEXROLE_RGB]] > 1]
    assert len(used) == len({(kind, s.material, s.rgba) for r in two_room.rooms
                             for kind, s in (("floors", r.floor), ("walls", r.wall))
                             if materials.surface_pattern(s.material) not in (None, "paint")})


def test_a_patterned_floor_is_not_one_flat_colour():
    """Looking down at a wooden floor shows its boards: the floor's pixels vary beyond flat
    shading (a plain floor of the same colour is uniform)."""
    images = []
    for material in ("wood", "plain"):
        scene = validate_scene({
            "rooms": [{"id": "r", "type": "test", "name": "room", "polygon": [[-3, -3], [3, -3], [3, 3], [-3, 3]],
                       "floor": {"material": material, "rgba": [0.6, 0.45, 0.3, 1]}}],
            "agent": {"position": [0, 0], "yaw": 0},
            "lights": [{"position": [0, 0, 2.5], "directional": True, "cast_shadow": False}],
        })
        world = build_world(scene, BuildOptions(with_outside=False))
        world.set_body_pose("agent", 0, 2.5, 0)  # out of the view
        mujoco.mj_forward(world.model, world.data)
        images.append(Renderer(world, 64, 64).rgb(FreeCamera((0.0, 0.0, 0.0), 2.0, 0.0, -89.0)).astype(float))
    wood, plain = images
    centre = np.s_[16:48, 16:48]
    assert plain[centre].std(axis=(0, 1)).max() < 1.0
    assert wood[centre].std(axis=(0, 1)).max() > 4.0
    assert abs(wood[centre].mean() - plain[centre].mean()) < 20  # the same colour on the whole


def test_domain_randomisation_moves_tiles_with_their_colours(two_room):
    world = build_world(two_room)
    model, atlas = world.model, world.atlas
    before = _texture(model, "palette").astype(float)
    floor = "surface_0"
    floor_before = _texture(model, floor).astype(float)
    randomize_appearance(world, np.random.default_rng(5))
    after = _texture(model, "palette").astype(float)
    first = after.copy()
    assert not np.array_equal(before, after)
    tiles = [(before[y:y + t, x:x + t], after[y:y + t, x:x + t]) for x, y, _ in atlas.tile_boxes()
             for t in [materials.TILE]]
    tiles.append((floor_before, _texture(model, floor).astype(float)))
    assert not np.array_equal(*tiles[-1])
    for old, new in tiles:
        # The pattern keeps its shape: each channel scaled by one factor (to rounding, where
        # not clipped).
        for c in range(3):
            o, n = old[..., c].ravel(), new[..., c].ravel()
            kept = n < 255
            factor = (o[kept] @ n[kept]) / max(o[kept] @ o[kept], 1e-9)
            assert np.abs(n[kept] - o[kept] * factor).max() <= 1.5
    randomize_appearance(world, np.random.default_rng(5))
    assert np.array_equal(_texture(model, "palette").astype(float), first)  # deterministic, no drift


def test_a_full_atlas_draws_the_rest_flat(two_room, monkeypatch):
    monkeypatch.setattr(Atlas, "MAX_HEIGHT", materials.TILE)  # room for the slots beside the palette's first row
    world = build_world(two_room)
    beside = (Atlas.WIDTH - world.atlas.palette.size) // materials.TILE
    assert len(world.atlas.tiles) == beside
    assert world.atlas.size()[1] == world.atlas.palette.size
    assert Renderer(world, 32, 32).rgb("agent").std() > 5


def test_ceiling_lamps_glow_above_their_lights():
    scene = validate_scene({
        "rooms": [{"id": "r", "type": "test", "name": "room", "polygon": [[-3, -3], [3, -3], [3, 3], [-3, 3]]}],
        "walls": [{"id": f"w{i}", "start": s, "end": e, "height": 2.8, "rooms": ["r", "exterior"]}
                  for i, (s, e) in enumerate([([-3, -3], [3, -3]), ([3, -3], [3, 3]), ([3, 3], [-3, 3]),
                                              ([-3, 3], [-3, -3])])],
        "agent": {"position": [0, 0], "yaw": 0},
        "lights": [{"position": [1.5, 0, 2.6], "diffuse": [0.5, 0.5, 0.5], "cast_shadow": False},
                   {"position": [0, 0, 6.0], "directional": True}],
    })
    world = build_world(scene)
    model = world.model
    lamp = model.geom("light_fixtures").id
    mesh = model.geom_dataid[lamp]
    v = model.mesh_vert[model.mesh_vertadr[mesh]:model.mesh_vertadr[mesh] + model.mesh_vertnum[mesh]]
    v = v @ world.data.geom_xmat[lamp].reshape(3, 3).T + world.data.geom_xpos[lamp]  # in the world
    assert np.allclose(v[:, :2].mean(axis=0), [1.5, 0], atol=0.02)  # over the hanging light only
    assert v[:, 2].min() > 2.6  # above it
    world.set_body_pose("agent", 0, 0, 0, pitch_deg=-50)  # looking up at it
    mujoco.mj_forward(model, world.data)
    renderer = Renderer(world, 64, 64)
    seg_geoms = renderer.geom_ids("agent")
    rgb = renderer.rgb("agent")
    lit = seg_geoms == lamp
    assert lit.sum() > 10
    assert rgb[lit].min(axis=1).mean() > 200  # it glows, unlike the ceiling around it
    assert rgb[~lit].mean() < rgb[lit].mean() - 40

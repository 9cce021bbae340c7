"""glTF/GLB import: geometry, node transforms, colours, textures, frames, errors, cache.

Real files: the Khronos glTF 2.0 sample models in ``tests/fixtures/gltf`` (sources and licences in
SOURCES.md there). Expectations that concern the file's content are
computed here from the raw JSON and buffers, independently of trimesh.
"""

from __future__ import annotations

import base64
import json
import os
import warnings
from pathlib import Path

import numpy as np
import pytest

from legent_gym.world.assets import registry
from legent_gym.world.assets.gltf import (
    GLTF_TO_ASSET,
    AssetImportError,
    AssetImportWarning,
    clear_cache,
    load_gltf,
    load_imported_asset,
    register_gltf,
)
from legent_gym.world.assets.model import Receptacle
from tests.conftest import GLTF_SAMPLES as SAMPLES


@pytest.fixture(autouse=True)
def _fresh_cache():
    clear_cache()
    yield
    clear_cache()


def sample(name: str) -> Path:
    return SAMPLES / f"{name}.gltf"


def load_quiet(path, **kwargs):
    """load_gltf without the expected 'flat model' warning of the 2D samples."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AssetImportWarning)
        return load_gltf(path, **kwargs)


def all_vertices(model) -> np.ndarray:
    return np.concatenate([p.vertices for p in model.base.parts])


def signed_volume(model) -> float:
    """Volume by the divergence theorem: positive iff triangles wind outward."""
    total = 0.0
    for p in model.base.parts:
        tri = p.vertices[p.faces]
        total += np.einsum("ij,ij->i", tri[:, 0], np.cross(tri[:, 1], tri[:, 2])).sum() / 6.0
    return total


# --- an independent reader for the embedded samples' accessors and node transforms -------

_COMPONENTS = {5120: np.int8, 5121: np.uint8, 5122: np.int16, 5123: np.uint16, 5125: np.uint32,
               5126: np.float32}
_WIDTHS = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}


def read_accessor(doc: dict, index: int) -> np.ndarray:
    """An accessor of an embedded (data: URI) glTF, as a (count, width) array."""
    acc = doc["accessors"][index]
    view = doc["bufferViews"][acc["bufferView"]]
    uri = doc["buffers"][view["buffer"]]["uri"]
    data = base64.b64decode(uri.split(",", 1)[1])
    dtype = np.dtype(_COMPONENTS[acc["componentType"]]).newbyteorder("<")
    width = _WIDTHS[acc["type"]]
    stride = view.get("byteStride", dtype.itemsize * width)
    start = view.get("byteOffset", 0) + acc.get("byteOffset", 0)
    rows = [np.frombuffer(data, dtype, width, start + i * stride) for i in range(acc["count"])]
    return np.array(rows, dtype=np.float64)


def node_matrix(node: dict) -> np.ndarray:
    """A node's local 4x4 transform from ``matrix`` (column-major) or T * R * S."""
    if "matrix" in node:
        return np.array(node["matrix"], dtype=np.float64).reshape(4, 4).T
    x, y, z, w = node.get("rotation", [0.0, 0.0, 0.0, 1.0])
    rot = np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ])
    out = np.eye(4)
    out[:3, :3] = rot * np.array(node.get("scale", [1.0, 1.0, 1.0]))
    out[:3, 3] = node.get("translation", [0.0, 0.0, 0.0])
    return out


def world_positions(doc: dict) -> np.ndarray:
    """Every mesh instance's vertices in the glTF world frame (one scene, any depth)."""
    out = []

    def visit(index: int, parent: np.ndarray) -> None:
        node = doc["nodes"][index]
        world = parent @ node_matrix(node)
        if "mesh" in node:
            for prim in doc["meshes"][node["mesh"]]["primitives"]:
                pos = read_accessor(doc, prim["attributes"]["POSITION"])
                out.append(pos @ world[:3, :3].T + world[:3, 3])
        for child in node.get("children", []):
            visit(child, world)

    for root in doc["scenes"][doc.get("scene", 0)]["nodes"]:
        visit(root, np.eye(4))
    return np.concatenate(out)


def expected_vertices(doc: dict) -> np.ndarray:
    """What the import should produce: glTF (x, y, z) -> (-x, z, y), then recentred."""
    pts = world_positions(doc)
    ours = np.column_stack([-pts[:, 0], pts[:, 2], pts[:, 1]])
    lo, hi = ours.min(axis=0), ours.max(axis=0)
    return ours + [-(lo[0] + hi[0]) / 2, -(lo[1] + hi[1]) / 2, -lo[2]]


def expected_bounds(doc: dict) -> np.ndarray:
    ours = expected_vertices(doc)
    return np.stack([ours.min(axis=0), ours.max(axis=0)])


# --- generated files -------------------------------------------------------------------


def write_generated_glb(path: Path) -> Path:
    """A GLB with four nodes: a textured box at glTF +z (its front), a vertex-coloured box
    at glTF +x, and one green box instanced twice near the origin."""
    import trimesh
    from PIL import Image
    from trimesh.visual.material import PBRMaterial
    from trimesh.visual.texture import TextureVisuals

    image = np.zeros((4, 8, 3), dtype=np.uint8)
    image[:2] = (255, 0, 0)  # top rows red
    image[2:] = (0, 0, 255)
    textured = trimesh.creation.box(extents=(0.2, 0.2, 0.2))
    uv = (textured.vertices[:, :2] + 0.1) / 0.2
    textured.visual = TextureVisuals(uv=uv, material=PBRMaterial(baseColorTexture=Image.fromarray(image)))

    coloured = trimesh.creation.box(extents=(0.2, 0.2, 0.2))
    red, blue = [255, 0, 0, 255], [0, 0, 255, 255]
    coloured.visual.vertex_colors = np.where(coloured.vertices[:, :1] < 0, red, blue).astype(np.uint8)

    plain = trimesh.creation.box(extents=(0.1, 0.1, 0.1))
    plain.visual = TextureVisuals(material=PBRMaterial(baseColorFactor=[0, 255, 0, 255]))

    scene = trimesh.Scene()
    scene.add_geometry(textured, node_name="front", transform=trimesh.transformations.translation_matrix([0, 0, 1]))
    scene.add_geometry(coloured, node_name="plus_x", transform=trimesh.transformations.translation_matrix([1, 0, 0]))
    scene.add_geometry(plain, geom_name="plain", node_name="a", transform=trimesh.transformations.translation_matrix([0, 0.5, 0]))
    scene.add_geometry(plain, geom_name="plain", node_name="b", transform=trimesh.transformations.translation_matrix([0, 0.3, 0]))
    path.write_bytes(scene.export(file_type="glb"))
    return path


def write_gltf(path: Path, positions, *, mode: int = 4, indices=None) -> Path:
    """A hand-made embedded glTF with one primitive (positions as float32)."""
    pos = np.asarray(positions, dtype="<f4").reshape(-1, 3)
    blob = pos.tobytes()
    finite = pos[np.isfinite(pos).all(axis=1)]
    accessors = [{"bufferView": 0, "componentType": 5126, "count": len(pos), "type": "VEC3",
                  "min": finite.min(axis=0).tolist() if len(finite) else [0, 0, 0],
                  "max": finite.max(axis=0).tolist() if len(finite) else [0, 0, 0]}]
    views = [{"buffer": 0, "byteOffset": 0, "byteLength": len(blob)}]
    prim = {"attributes": {"POSITION": 0}, "mode": mode}
    if indices is not None:
        idx = np.asarray(indices, dtype="<u2").tobytes()
        views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": len(idx)})
        accessors.append({"bufferView": 1, "componentType": 5123, "count": len(indices), "type": "SCALAR"})
        prim["indices"] = 1
        blob += idx
    doc = {
        "asset": {"version": "2.0"},
        "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [prim]}],
        "accessors": accessors, "bufferViews": views,
        "buffers": [{"byteLength": len(blob),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode()}],
    }
    path.write_text(json.dumps(doc))
    return path


TETRA = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]
TETRA_FACES = [0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3]


# --- the frame ------------------------------------------------------------------------


def test_frame_conversion_is_a_rotation():
    assert np.linalg.det(GLTF_TO_ASSET) > 0
    np.testing.assert_allclose(GLTF_TO_ASSET @ GLTF_TO_ASSET.T, np.eye(3))
    np.testing.assert_array_equal(GLTF_TO_ASSET @ [0, 1, 0], [0, 0, 1])  # glTF up -> our up
    np.testing.assert_array_equal(GLTF_TO_ASSET @ [0, 0, 1], [0, 1, 0])  # glTF front -> our front


def test_box_colour_frame_and_winding():
    model = load_gltf(sample("Box"))
    assert model.triangle_count() == 12 and len(model.base.parts) == 1
    part = model.base.parts[0]
    assert part.rgba == pytest.approx((0.8, 0.0, 0.0, 1.0))  # baseColorFactor, alpha opaque
    assert part.collision == "hull" and part.texture is None and part.uv is None
    bounds = model.bounds()
    assert bounds[0][2] == pytest.approx(0.0)
    np.testing.assert_allclose((bounds[0][:2] + bounds[1][:2]) / 2, 0.0, atol=1e-9)
    np.testing.assert_allclose(model.size, [1.0, 1.0, 1.0], atol=1e-6)
    assert signed_volume(model) == pytest.approx(1.0, rel=1e-5)  # no mirroring, outward faces
    assert model.category == "box" and model.names == ["box"]


def test_simple_meshes_two_instances_of_one_mesh():
    model = load_quiet(sample("SimpleMeshes"))
    # One triangle (0,0,0) (1,0,0) (0,1,0), instanced at the origin and at translation x + 1.
    assert model.triangle_count() == 2 and len(model.base.parts) == 2
    np.testing.assert_allclose(model.bounds(), [[-1.0, 0.0, 0.0], [1.0, 0.0, 1.0]], atol=1e-6)
    doc = json.loads(sample("SimpleMeshes").read_text())
    np.testing.assert_allclose(model.bounds(), expected_bounds(doc), atol=1e-6)


def test_orientation_test_node_transforms():
    model = load_gltf(sample("OrientationTest"))
    doc = json.loads(sample("OrientationTest").read_text())
    assert len(model.base.parts) == 13
    assert sum(len(p.vertices) for p in model.base.parts) == len(world_positions(doc))
    np.testing.assert_allclose(model.bounds(), expected_bounds(doc), atol=1e-4)
    # Vertex by vertex, as sets (the part order follows trimesh's node order).
    ours, expected = all_vertices(model), expected_vertices(doc)
    dist = np.linalg.norm(ours[:, None, :] - expected[None, :, :], axis=2)
    assert dist.min(axis=1).max() < 1e-4 and dist.min(axis=0).max() < 1e-4


def test_triangle_without_indices():
    model = load_quiet(sample("TriangleWithoutIndices"))
    assert model.triangle_count() == 1
    # MuJoCo compiles no mesh of fewer than 4 vertices: the centroid is added, used by no face.
    part = model.base.parts[0]
    assert len(part.vertices) == 4 and part.faces.max() == 2
    np.testing.assert_allclose(part.vertices[3], part.vertices[:3].mean(axis=0))
    assert part.rgba == (1.0, 1.0, 1.0, 1.0)  # glTF default material
    assert part.collision == "box"  # MuJoCo cannot hull a flat part: a thin box from its bounds


def test_a_mesh_of_zero_area_triangles_is_left_out(tmp_path):
    # MuJoCo compiles no mesh without surface area: such a primitive is dropped, with a warning.
    path = write_gltf(tmp_path / "two.gltf", [[0, 0, 0], [1, 0, 0], [2, 0, 0],
                                              [0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]],
                      indices=[0, 1, 2])
    doc = json.loads(path.read_text())
    idx = np.asarray([3, 4, 5, 3, 5, 6, 3, 6, 4, 4, 6, 5], dtype="<u2").tobytes()
    blob = base64.b64decode(doc["buffers"][0]["uri"].split(",", 1)[1])
    doc["bufferViews"].append({"buffer": 0, "byteOffset": len(blob), "byteLength": len(idx)})
    doc["accessors"].append({"bufferView": 2, "componentType": 5123, "count": 12, "type": "SCALAR"})
    doc["buffers"][0] = {"byteLength": len(blob) + len(idx),
                         "uri": "data:application/octet-stream;base64," + base64.b64encode(blob + idx).decode()}
    doc["meshes"][0]["primitives"].append({"attributes": {"POSITION": 0}, "indices": 2, "mode": 4})
    path.write_text(json.dumps(doc))
    with pytest.warns(AssetImportWarning, match="no surface area"):
        model = load_gltf(path)
    assert len(model.base.parts) == 1 and model.triangle_count() == 4


def test_flat_model_warns_it_has_no_collision(tmp_path):
    path = write_gltf(tmp_path / "quad.gltf", [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]],
                      indices=[0, 1, 2, 2, 1, 3])
    with pytest.warns(AssetImportWarning, match="flat.*thin box"):
        model = load_gltf(path)
    assert [p.collision for p in model.base.parts] == ["box"]


def test_textured_box_keeps_texture_and_flips_v():
    model = load_gltf(sample("BoxTextured"))
    part = model.base.parts[0]
    assert part.texture is not None
    assert part.texture.shape == (211, 211, 3) and part.texture.dtype == np.uint8
    doc = json.loads(sample("BoxTextured").read_text())
    raw = read_accessor(doc, doc["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"])
    assert part.uv.shape == (len(part.vertices), 2)
    np.testing.assert_allclose(part.uv[:, 0], raw[:, 0], atol=1e-6)
    np.testing.assert_allclose(part.uv[:, 1], 1.0 - raw[:, 1], atol=1e-6)  # v pointing up
    assert part.uv[:, 1].min() == pytest.approx(0.0, abs=1e-6)
    assert part.uv[:, 1].max() == pytest.approx(1.0, abs=1e-6)
    assert part.rgba == (1.0, 1.0, 1.0, 1.0)


def test_vertex_colours_are_averaged():
    model = load_gltf(sample("BoxVertexColors"))
    doc = json.loads(sample("BoxVertexColors").read_text())
    attrs = doc["meshes"][0]["primitives"][0]
    pos = read_accessor(doc, attrs["attributes"]["POSITION"])
    col = read_accessor(doc, attrs["attributes"]["COLOR_0"])[:, :3]
    faces = read_accessor(doc, attrs["indices"]).astype(int).reshape(-1, 3)
    tri = pos[faces]
    area = np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1)
    expected = (col[faces].mean(axis=1) * area[:, None]).sum(axis=0) / area.sum()
    part = model.base.parts[0]
    assert part.rgba[:3] == pytest.approx(tuple(expected), abs=2 / 255)  # COLOR_0 read as uint8
    assert part.rgba[3] == 1.0 and part.texture is None


def test_rigged_simple_imports_static_mesh_and_up_axis():
    model = load_gltf(sample("RiggedSimple"))
    assert model.triangle_count() == 188
    size = model.size
    assert size[2] == pytest.approx(9.15, abs=0.01)  # tallest along glTF y -> our z
    assert size[2] > 4 * max(size[0], size[1])
    as_z_up = load_gltf(sample("RiggedSimple"), up_axis="z")  # taken as already z-up
    assert np.argmax(as_z_up.size) == 1
    assert as_z_up.bounds()[0][2] == pytest.approx(0.0)


def test_generated_glb_nodes_texture_colours_and_front(tmp_path):
    model = load_gltf(write_generated_glb(tmp_path / "Generated Scene.glb"))
    parts = model.base.parts
    assert len(parts) == 4 and model.triangle_count() == 48
    textured = [p for p in parts if p.texture is not None]
    assert len(textured) == 1
    tex = textured[0]
    assert tex.texture.shape == (4, 8, 3) and tex.texture.dtype == np.uint8
    np.testing.assert_array_equal(tex.texture[0, 0], [255, 0, 0])  # row 0 is the image's top
    assert tex.uv.min() >= -1e-6 and tex.uv.max() <= 1 + 1e-6
    coloured = [p for p in parts if p.rgba[:3] == pytest.approx((0.5, 0.0, 0.5), abs=0.01)]
    assert len(coloured) == 1
    green = [p for p in parts if p.rgba == pytest.approx((0.0, 1.0, 0.0, 1.0))]
    assert len(green) == 2  # one mesh, two nodes
    # glTF front (+z) -> our +y; glTF +x -> our -x (a rotation, no mirror).
    centre = {id(p): p.vertices.mean(axis=0) for p in parts}
    assert centre[id(tex)][1] == pytest.approx(model.bounds()[1][1] - 0.1)
    assert centre[id(coloured[0])][0] == pytest.approx(model.bounds()[0][0] + 0.1)
    assert signed_volume(model) > 0
    assert model.category == "generated_scene"


def test_generated_glb_imports_without_warnings(tmp_path):
    path = write_generated_glb(tmp_path / "clean.glb")  # its PNG sits in a buffer view
    with warnings.catch_warnings():
        warnings.simplefilter("error", AssetImportWarning)
        assert load_gltf(path).triangle_count() == 48


def test_colour_factor_times_vertex_colours(tmp_path):
    import trimesh
    from trimesh.visual.material import PBRMaterial
    from trimesh.visual.texture import TextureVisuals

    mesh = trimesh.creation.box(extents=(0.2, 0.2, 0.2))
    mesh.visual = TextureVisuals(material=PBRMaterial(baseColorFactor=[255, 128, 0, 255]))
    mesh.visual.vertex_attributes["color"] = np.tile([0, 255, 255, 255], (8, 1)).astype(np.uint8)
    path = tmp_path / "tinted.glb"
    path.write_bytes(mesh.export(file_type="glb"))
    assert load_gltf(path).base.parts[0].rgba == pytest.approx((0.0, 128 / 255, 0.0, 1.0))


@pytest.mark.parametrize("mode, alpha", [("BLEND", 0.5), ("OPAQUE", 1.0), ("MASK", 1.0)])
def test_alpha_counts_only_when_blending(tmp_path, mode, alpha):
    path = write_gltf(tmp_path / "glass.gltf", TETRA, indices=TETRA_FACES)
    doc = json.loads(path.read_text())
    doc["materials"] = [{"name": "Tinted Glass", "alphaMode": mode,
                         "pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.4, 0.6, 0.5]}}]
    doc["meshes"][0]["primitives"][0]["material"] = 0
    path.write_text(json.dumps(doc))
    part = load_gltf(path).base.parts[0]
    assert part.rgba == pytest.approx((0.2, 0.4, 0.6, alpha), abs=1 / 255)
    assert part.material == "glass"  # hint from the material name


def test_large_texture_is_downscaled(tmp_path):
    import trimesh
    from PIL import Image
    from trimesh.visual.material import PBRMaterial
    from trimesh.visual.texture import TextureVisuals

    mesh = trimesh.creation.box(extents=(0.2, 0.2, 0.2))
    image = Image.new("RGB", (2048, 4), (10, 20, 30))
    mesh.visual = TextureVisuals(uv=np.zeros((8, 2)), material=PBRMaterial(baseColorTexture=image))
    path = tmp_path / "wide.glb"
    path.write_bytes(mesh.export(file_type="glb"))
    texture = load_gltf(path).base.parts[0].texture
    assert texture.shape == (2, 1024, 3)
    np.testing.assert_array_equal(texture[0, 0], [10, 20, 30])


def test_undecodable_image_warns_and_keeps_base_colour(tmp_path):
    path = write_gltf(tmp_path / "badimage.gltf", TETRA, indices=TETRA_FACES)
    doc = json.loads(path.read_text())
    junk = base64.b64encode(b"\x89PNG\r\n\x1a\nnot really a png").decode()
    doc["images"] = [{"uri": "data:image/png;base64," + junk}]
    doc["textures"] = [{"source": 0}]
    doc["materials"] = [{"pbrMetallicRoughness": {"baseColorFactor": [0, 0, 1, 1],
                                                  "baseColorTexture": {"index": 0}}}]
    doc["meshes"][0]["primitives"][0]["material"] = 0
    path.write_text(json.dumps(doc))
    with pytest.warns(AssetImportWarning, match=r"badimage\.gltf: image 0 cannot be decoded"):
        model = load_gltf(path)
    part = model.base.parts[0]
    assert part.texture is None and part.rgba == (0.0, 0.0, 1.0, 1.0)


# --- size, annotations ----------------------------------------------------------------


def test_size_scales_uniformly_to_fit():
    model = load_gltf(sample("Box"), size=(2.0, 4.0, 0.4))
    np.testing.assert_allclose(model.size, [0.4, 0.4, 0.4], atol=1e-6)
    assert model.bounds()[0][2] == pytest.approx(0.0)
    assert model.pickupable and model.placement == "surface"
    assert model.mass == pytest.approx(200 * 0.4**3)
    assert model.receptacles == []
    native = load_gltf(sample("RiggedSimple"), size=(1.0, 1.0, 1.0))
    assert native.size.max() == pytest.approx(1.0)
    assert native.size[2] == pytest.approx(1.0)


def test_default_annotations_of_a_large_box():
    model = load_gltf(sample("Box"))
    assert not model.pickupable and model.placement == "wall"
    assert model.mass == 50.0  # 200 kg/m^3 * 1 m^3, clipped
    (top,) = model.receptacles
    assert top.height == pytest.approx(1.0) and top.link == "base"
    assert top.center == pytest.approx((0.0, 0.0), abs=1e-6)
    assert top.half_size == pytest.approx((0.48, 0.48))


def test_explicit_annotations():
    model = load_gltf(sample("Box"), category="crate", names=["crate", "red box"], pickupable=True,
                      mass=3.0, placement="middle", rooms=["garage"],
                      receptacles=[{"name": "lid", "center": (0, 0), "half_size": (0.2, 0.2), "height": 1.0}])
    assert model.category == "crate" and model.names == ["crate", "red box"]
    assert model.pickupable and model.mass == 3.0 and model.placement == "middle"
    assert model.rooms == ["garage"]
    assert model.receptacles == [Receptacle("lid", (0.0, 0.0), (0.2, 0.2), 1.0)]
    assert load_gltf(sample("Box"), receptacles=[]).receptacles == []


def test_table_gets_a_receptacle_on_its_top(tmp_path):
    import trimesh
    from trimesh.transformations import translation_matrix

    scene = trimesh.Scene()  # built y-up, as glTF is: a 1.2 x 0.8 top at 0.75 m, four legs
    scene.add_geometry(trimesh.creation.box(extents=(1.2, 0.04, 0.8)), node_name="top",
                       transform=translation_matrix([0, 0.73, 0]))
    scene.add_geometry(trimesh.creation.box(extents=(0.1, 0.3, 0.1)), node_name="vase",
                       transform=translation_matrix([0.3, 0.9, 0]))
    for i, (x, z) in enumerate([(-0.55, -0.35), (0.55, -0.35), (-0.55, 0.35), (0.55, 0.35)]):
        scene.add_geometry(trimesh.creation.box(extents=(0.05, 0.71, 0.05)), node_name=f"leg{i}",
                           transform=translation_matrix([x, 0.355, z]))
    path = tmp_path / "table.glb"
    path.write_bytes(scene.export(file_type="glb"))
    model = load_gltf(path)
    assert len(model.base.parts) == 6 and all(p.collision == "hull" for p in model.base.parts)
    assert not model.pickupable and model.placement == "wall"
    (top,) = model.receptacles  # the vase's small top does not count
    assert top.height == pytest.approx(0.75)
    assert top.half_size == pytest.approx((0.58, 0.38))
    assert top.center == pytest.approx((0.0, 0.0), abs=1e-6)


def test_triangle_count_warning(tmp_path):
    import trimesh

    path = tmp_path / "dense.glb"
    path.write_bytes(trimesh.creation.icosphere(subdivisions=5).export(file_type="glb"))
    with pytest.warns(AssetImportWarning, match="20480 triangles"):
        model = load_gltf(path)
    assert model.triangle_count() == 20480


# --- cache and registry ---------------------------------------------------------------


def test_cache_returns_same_object_until_file_changes(tmp_path):
    path = write_gltf(tmp_path / "tetra.gltf", TETRA, indices=TETRA_FACES)
    first = load_gltf(path)
    assert load_gltf(path) is first
    assert load_gltf(str(path)) is first
    assert load_gltf(path, size=(1, 1, 1)) is not first
    stat = path.stat()
    os.utime(path, ns=(stat.st_atime_ns, stat.st_mtime_ns + 1_000_000_000))
    assert load_gltf(path) is not first


def test_register_gltf_and_make(tmp_path):
    path = write_gltf(tmp_path / "tetra.gltf", TETRA, indices=TETRA_FACES)
    try:
        register_gltf("test_gltf_tetra", path, category="pyramid", size=(0.3, 0.3, 0.3))
        a, b = registry.make("test_gltf_tetra", 0), registry.make("test_gltf_tetra", 5)
        assert a.asset_id == "test_gltf_tetra" and a.category == "pyramid"
        np.testing.assert_allclose(a.bounds(), b.bounds())
        assert a.size.max() == pytest.approx(0.3)
        assert load_gltf(path, category="pyramid", size=(0.3, 0.3, 0.3)).asset_id == "tetra"
        with pytest.raises(ValueError, match="already registered"):
            register_gltf("test_gltf_tetra", path)
        register_gltf("test_gltf_tetra", path, replace=True)
        assert registry.make("test_gltf_tetra").category == "tetra"
    finally:
        registry.unregister("test_gltf_tetra")


def test_load_imported_asset_for_the_builder(tmp_path):
    from legent_gym.world.scene import ImportedAsset

    write_gltf(tmp_path / "tetra.gltf", TETRA, indices=TETRA_FACES)
    entry = ImportedAsset(id="my_tetra", source="tetra.gltf", size=(0.2, 0.2, 0.2), mass=1.5,
                          names=["pyramid"])
    model = load_imported_asset(entry, tmp_path)
    assert model.asset_id == "my_tetra" and model.names == ["pyramid"] and model.mass == 1.5
    assert model.size.max() == pytest.approx(0.2)
    absolute = ImportedAsset(id="abs", source=str(tmp_path / "tetra.gltf"))
    assert load_imported_asset(absolute, "/nonexistent").triangle_count() == 4
    with pytest.raises(AssetImportError, match="gone.glb"):
        load_imported_asset(ImportedAsset(id="gone", source="gone.glb"), tmp_path)


def test_register_gltf_validates_eagerly(tmp_path):
    with pytest.raises(AssetImportError, match="missing.glb"):
        register_gltf("test_gltf_missing", tmp_path / "missing.glb")
    assert not registry.has("test_gltf_missing")


# --- bad input ------------------------------------------------------------------------


def test_missing_file(tmp_path):
    with pytest.raises(AssetImportError, match="nothing.gltf"):
        load_gltf(tmp_path / "nothing.gltf")


def test_truncated_glb(tmp_path):
    whole = write_generated_glb(tmp_path / "whole.glb").read_bytes()
    cut = tmp_path / "cut.glb"
    cut.write_bytes(whole[: len(whole) // 2])
    with pytest.raises(AssetImportError, match=r"cut\.glb.*truncated"):
        load_gltf(cut)
    tiny = tmp_path / "tiny.glb"
    tiny.write_bytes(whole[:10])
    with pytest.raises(AssetImportError, match="tiny.glb"):
        load_gltf(tiny)


def test_not_a_glb(tmp_path):
    path = tmp_path / "junk.glb"
    path.write_bytes(b"this is not a binary glTF file at all")
    with pytest.raises(AssetImportError, match=r"junk\.glb.*magic"):
        load_gltf(path)


def test_corrupt_json(tmp_path):
    path = tmp_path / "broken.gltf"
    path.write_text('{"asset": {"version": "2.0"}, "meshes": [')
    with pytest.raises(AssetImportError, match=r"broken\.gltf.*JSON"):
        load_gltf(path)


def test_corrupt_buffer_data(tmp_path):
    path = write_gltf(tmp_path / "short.gltf", TETRA, indices=TETRA_FACES)
    doc = json.loads(path.read_text())
    doc["accessors"][0]["count"] = 400  # more vertices than the buffer holds
    path.write_text(json.dumps(doc))
    with pytest.raises(AssetImportError, match="short.gltf"):
        load_gltf(path)


def test_missing_external_buffer(tmp_path):
    path = write_gltf(tmp_path / "external.gltf", TETRA, indices=TETRA_FACES)
    doc = json.loads(path.read_text())
    doc["buffers"][0]["uri"] = "external.bin"
    path.write_text(json.dumps(doc))
    with pytest.raises(AssetImportError, match="missing buffer file 'external.bin'"):
        load_gltf(path)


def test_glb_with_external_buffer_loads(tmp_path):
    import trimesh

    mesh = trimesh.creation.box(extents=(0.1, 0.2, 0.3))
    files = mesh.export(file_type="gltf")  # {"model.gltf": ..., "gltf_buffer_0.bin": ...}
    assert any(not name.endswith(".gltf") for name in files)
    for name, data in files.items():
        (tmp_path / name).write_bytes(data)
    model = load_gltf(tmp_path / "model.gltf")
    np.testing.assert_allclose(sorted(model.size), [0.1, 0.2, 0.3], atol=1e-6)


def test_missing_external_image_warns(tmp_path):
    path = write_gltf(tmp_path / "noimage.gltf", TETRA, indices=TETRA_FACES)
    doc = json.loads(path.read_text())
    doc["images"] = [{"uri": "wood.png"}]
    path.write_text(json.dumps(doc))
    with pytest.warns(AssetImportWarning, match=r"image 0 cannot be decoded.*wood\.png"):
        assert load_gltf(path).triangle_count() == 4


def test_glb_named_gltf(tmp_path):
    path = tmp_path / "binary.gltf"
    path.write_bytes(write_generated_glb(tmp_path / "binary.glb").read_bytes())
    with pytest.raises(AssetImportError, match=r"binary\.gltf.*\.glb extension"):
        load_gltf(path)


def test_only_points(tmp_path):
    path = write_gltf(tmp_path / "points.gltf", TETRA, mode=0)
    with pytest.raises(AssetImportError, match=r"points\.gltf.*no triangle geometry.*points"):
        load_gltf(path)


def test_only_lines(tmp_path):
    path = write_gltf(tmp_path / "lines.gltf", TETRA, mode=1)
    with pytest.raises(AssetImportError, match=r"lines\.gltf.*no triangle geometry.*lines"):
        load_gltf(path)


def test_non_finite_vertices(tmp_path):
    path = write_gltf(tmp_path / "nan.gltf", [[0, 0, 0], [1, 0, 0], [0, np.nan, 0], [0, 0, 1]],
                      indices=TETRA_FACES)
    with pytest.raises(AssetImportError, match=r"nan\.gltf.*non-finite"):
        load_gltf(path)


def test_zero_size_bounds(tmp_path):
    path = write_gltf(tmp_path / "dot.gltf", [[0.5, 0.5, 0.5]] * 3)
    with pytest.raises(AssetImportError, match=r"dot\.gltf.*zero-size"):
        load_gltf(path)


def test_unsupported_extension_and_version(tmp_path):
    other = tmp_path / "mesh.obj"
    other.write_text("v 0 0 0\n")
    with pytest.raises(AssetImportError, match=r"mesh\.obj.*\.gltf or \.glb"):
        load_gltf(other)
    path = write_gltf(tmp_path / "old.gltf", TETRA, indices=TETRA_FACES)
    doc = json.loads(path.read_text())
    doc["asset"]["version"] = "1.0"
    path.write_text(json.dumps(doc))
    with pytest.raises(AssetImportError, match="only glTF 2.0"):
        load_gltf(path)


@pytest.mark.parametrize("kwargs, message", [
    ({"size": (1, 0, 1)}, "size"),
    ({"size": (1, 1)}, "size"),
    ({"size": (1, float("nan"), 1)}, "size"),
    ({"size": "big"}, "size"),
    ({"up_axis": "x"}, "up_axis"),
    ({"mass": -1.0}, "mass"),
    ({"placement": "ceiling"}, "placement"),
    ({"names": "chair"}, "names"),
    ({"max_hull_vertices": 3}, "max_hull_vertices"),
    ({"receptacles": [{"name": "top"}]}, "receptacle"),
])
def test_bad_arguments(tmp_path, kwargs, message):
    path = write_gltf(tmp_path / "tetra.gltf", TETRA, indices=TETRA_FACES)
    with pytest.raises(AssetImportError, match=rf"tetra\.gltf.*{message}"):
        load_gltf(path, **kwargs)


def test_errors_are_value_errors():
    assert issubclass(AssetImportError, ValueError)


@pytest.mark.parametrize("kind", ["static", "interactable"])
@pytest.mark.parametrize("shape", ["triangle", "quad"])
def test_flat_meshes_build_with_a_collision_box(tmp_path, shape, kind):
    """MuJoCo compiles neither a hull of a flat mesh nor any mesh of 3 vertices: a flat
    import keeps its visual mesh and collides through a thin box."""
    from legent_gym.world.builder import GROUP_COLLISION, build_world
    from legent_gym.world.preview import preview_scene
    from legent_gym.world.scene import ImportedAsset

    if shape == "triangle":
        path = write_gltf(tmp_path / "tri.gltf", [[0, 0, 0], [0.3, 0, 0], [0, 0.3, 0]])
    else:
        path = write_gltf(tmp_path / "quad.gltf", [[0, 0, 0], [0.3, 0, 0], [0, 0.3, 0], [0.3, 0.3, 0]],
                          indices=[0, 1, 2, 2, 1, 3])
    imported = ImportedAsset(id="flat", source=str(path))
    with pytest.warns(AssetImportWarning, match="flat"):
        world = build_world(preview_scene("flat", imported=imported, kind=kind))
    model = world.model
    geoms = [g for g in range(model.ngeom) if world.geom_object_lookup(np.array([g]))[0] == 0]
    collision = [g for g in geoms if model.geom_group[g] == GROUP_COLLISION]
    visual = [g for g in geoms if model.geom_group[g] != GROUP_COLLISION]
    assert visual and collision
    assert all(model.geom_type[g] == 6 for g in collision)  # mjGEOM_BOX


def test_a_model_too_small_to_build_is_a_clear_error(tmp_path):
    path = write_gltf(tmp_path / "speck.gltf", np.asarray(TETRA) * 1e-7, indices=[0, 1, 2, 0, 1, 3, 0, 2, 3, 1, 2, 3])
    with pytest.raises(AssetImportError, match=r"speck\.gltf: the model is too small"):
        load_gltf(path)
    load_gltf(path, size=(0.1, 0.1, 0.1))  # scaled up to a size it builds


def test_a_thin_solid_collides_through_a_box(tmp_path):
    # Not flat, but its hull holds less volume than MuJoCo accepts (a 1 mm sliver of 1 mm^2).
    pts = [[0, 0, 0], [1e-3, 0, 0], [0, 1e-3, 0], [0, 0, 1e-3]]
    path = write_gltf(tmp_path / "sliver.gltf", pts, indices=[0, 1, 2, 0, 1, 3, 0, 2, 3, 1, 2, 3])
    with pytest.warns(AssetImportWarning, match="almost no volume"):
        model = load_gltf(path)
    assert [p.collision for p in model.base.parts] == ["box"]

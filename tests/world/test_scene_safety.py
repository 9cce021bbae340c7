"""Hostile scene and glTF files: size and count bounds, and references to files outside the
file's own folder, to URLs or to devices, each refused with an error naming the field or
the file."""

from __future__ import annotations

import base64
import json
import os
from pathlib import Path

import numpy as np
import pytest

from legent_gym.world.assets.gltf import (
    MAX_GLTF_BYTES,
    MAX_GLTF_ITEMS,
    MAX_IMAGES,
    MAX_VERTICES,
    AssetImportError,
    load_gltf,
    load_imported_asset,
)
from legent_gym.world.scene import (
    MAX_IMPORTED_ASSETS,
    MAX_LIGHTS,
    MAX_OBJECTS,
    MAX_POLYGON_POINTS,
    MAX_SCENE_BYTES,
    ImportedAsset,
    SceneError,
    load_scene,
    loads_scene,
)
from tests.conftest import EXAMPLES
from tests.world.test_gltf import TETRA, TETRA_FACES, write_gltf


def _scene() -> dict:
    return json.loads((EXAMPLES / "one_room.json").read_text())


def _sparse(path: Path, size: int) -> Path:
    """A file of ``size`` bytes that takes no disk space."""
    with open(path, "wb") as file:
        file.truncate(size)
    return path


def _with_asset(source: str) -> dict:
    data = _scene()
    data["assets"] = [{"id": "thing", "source": source}]
    data["objects"][0]["asset"] = "thing"
    return data


# --- scenes: counts and size ------------------------------------------------------------

def _many_objects(data: dict) -> None:
    first = data["objects"][0]
    data["objects"] = [{**first, "id": i} for i in range(MAX_OBJECTS + 1)]


def _many_points(data: dict) -> None:
    n = MAX_POLYGON_POINTS + 1
    angles = np.linspace(0, 2 * np.pi, n, endpoint=False)
    data["rooms"][0]["polygon"] = [[3 + 2 * np.cos(a), 3 + 2 * np.sin(a)] for a in angles]


def _many_lights(data: dict) -> None:
    data["lights"] = [{"position": [1, 1, 2]}] * (MAX_LIGHTS + 1)


def _many_assets(data: dict) -> None:
    data["assets"] = [{"id": f"a{i}", "source": f"a{i}.glb"} for i in range(MAX_IMPORTED_ASSETS + 1)]


def _many_joints(data: dict) -> None:
    data["objects"][0]["joints"] = {f"j{i}": 0.0 for i in range(1001)}


BAD_COUNTS = {
    "objects": (_many_objects, "objects", f"at most {MAX_OBJECTS}"),
    "polygon points": (_many_points, "rooms[0].polygon", f"at most {MAX_POLYGON_POINTS}"),
    "lights": (_many_lights, "lights", f"at most {MAX_LIGHTS}"),
    "imported assets": (_many_assets, "assets", f"at most {MAX_IMPORTED_ASSETS}"),
    "joints": (_many_joints, "objects[0].joints", "at most 1000"),
}


@pytest.mark.parametrize("case", BAD_COUNTS)
def test_too_many_entries_are_refused_by_field(tmp_path, case):
    grow, field, fragment = BAD_COUNTS[case]
    data = _scene()
    grow(data)
    path = tmp_path / "scene.json"
    path.write_text(json.dumps(data))
    with pytest.raises(SceneError) as info:
        load_scene(path)
    assert any(where == field and fragment in msg for where, msg in info.value.problems), info.value.problems
    assert str(path) in info.value.summary()


def _fifo(tmp_path: Path) -> Path:
    path = tmp_path / "scene.json"
    os.mkfifo(path)
    return path


BAD_SCENE_FILES = {
    "larger than MAX_SCENE_BYTES": (lambda d: _sparse(d / "scene.json", MAX_SCENE_BYTES + 1), "MAX_SCENE_BYTES"),
    "a device": (lambda d: Path("/dev/zero"), "not a regular file"),
    "a link to a device": (lambda d: (d / "scene.json").symlink_to("/dev/zero") or d / "scene.json",
                           "not a regular file"),
    "a FIFO (would block on open)": (_fifo, "not a regular file"),
    "a directory": (lambda d: (d / "scene.json").mkdir() or d / "scene.json", "not a regular file"),
}


@pytest.mark.parametrize("case", BAD_SCENE_FILES)
def test_scene_files_that_are_not_small_regular_files_are_refused(tmp_path, case):
    make, fragment = BAD_SCENE_FILES[case]
    path = make(tmp_path)
    with pytest.raises(SceneError) as info:
        load_scene(path)
    assert fragment in str(info.value) and str(path) in info.value.summary()


def test_scene_text_longer_than_the_bound_is_refused():
    with pytest.raises(SceneError, match="MAX_SCENE_BYTES"):
        loads_scene(" " * (MAX_SCENE_BYTES + 1), source="big.json")


# --- scenes: asset sources ------------------------------------------------------------------

def _outside_model(tmp_path: Path) -> None:
    (tmp_path / "house").mkdir(exist_ok=True)
    write_gltf(tmp_path / "outside.gltf", TETRA, indices=TETRA_FACES)


def _link_out(tmp_path: Path) -> None:
    _outside_model(tmp_path)
    (tmp_path / "house" / "model.gltf").symlink_to(tmp_path / "outside.gltf")


def _link_to_device(tmp_path: Path) -> None:
    (tmp_path / "house").mkdir(exist_ok=True)
    (tmp_path / "house" / "model.glb").symlink_to("/dev/zero")


def _directory(tmp_path: Path) -> None:
    (tmp_path / "house" / "model.glb").mkdir(parents=True)


BAD_SOURCES = {
    "http URL": ("http://example.com/model.glb", None, "is a URL (http:)"),
    "https URL": ("https://example.com/model.glb", None, "is a URL (https:)"),
    "file URL": ("file:///etc/model.glb", None, "is a URL (file:)"),
    "data URI": ("data:model/gltf-binary;base64,Z2xURg==.glb", None, "is a URL (data:)"),
    "absolute path": ("/tmp/model.glb", None, "absolute path"),
    "home path": ("~/model.glb", None, "absolute path"),
    "device file": ("/dev/zero", None, "must name a .gltf or .glb file"),
    "device as .glb": ("/dev/zero.glb", None, "absolute path"),
    "parent folder": ("../outside.gltf", _outside_model, "leaves the scene's folder"),
    "parent via subfolder": ("sub/../../outside.gltf", _outside_model, "leaves the scene's folder"),
    "symbolic link out": ("model.gltf", _link_out, "leads out of the scene's folder"),
    "symbolic link to a device": ("model.glb", _link_to_device, "leads out of the scene's folder"),
    "a directory": ("model.glb", _directory, "not a regular file"),
    "not glTF": ("model.obj", None, "must name a .gltf or .glb file"),
    "control character": ("mo\x00del.glb", None, "control character"),
}


@pytest.mark.parametrize("case", BAD_SOURCES)
def test_scene_asset_sources_outside_the_folder_are_refused(tmp_path, case):
    source, make, fragment = BAD_SOURCES[case]
    (tmp_path / "house").mkdir(exist_ok=True)
    if make is not None:
        make(tmp_path)
    path = tmp_path / "house" / "scene.json"
    path.write_text(json.dumps(_with_asset(source)))
    with pytest.raises(SceneError) as info:
        load_scene(path)
    assert any(where == "assets[0].source" and fragment in msg for where, msg in info.value.problems), \
        info.value.problems


def test_scene_asset_sources_inside_the_folder_load(tmp_path):
    (tmp_path / "models").mkdir()
    write_gltf(tmp_path / "models" / "tetra.gltf", TETRA, indices=TETRA_FACES)
    for source in ("models/tetra.gltf", "models/../models/tetra.gltf", "./models/tetra.gltf"):
        path = tmp_path / "scene.json"
        path.write_text(json.dumps(_with_asset(source)))
        scene = load_scene(path)
        model = load_imported_asset(scene.assets[0], scene.base_dir)
        assert model.asset_id == "thing" and model.links[0].parts


@pytest.mark.parametrize("source", ["../outside.gltf", "model.gltf"])
def test_build_time_import_refuses_paths_out_of_the_folder(tmp_path, source):
    """A scene made in Python skips the file checks; the import itself still refuses a
    relative source that leads out of the scene's folder (through .. or a link)."""
    _link_out(tmp_path)
    with pytest.raises(AssetImportError, match="out of the scene's folder"):
        load_imported_asset(ImportedAsset(id="thing", source=source), tmp_path / "house")


# --- glTF files ---------------------------------------------------------------------------

def _doc(tmp_path: Path) -> dict:
    return json.loads(write_gltf(tmp_path / "base.gltf", TETRA, indices=TETRA_FACES).read_text())


def _buffer_uri(uri: str, make=None):
    def change(tmp_path: Path, doc: dict) -> None:
        if make is not None:
            make(tmp_path)
        doc["buffers"][0]["uri"] = uri
    return change


def _image_uri(uri: str):
    def change(tmp_path: Path, doc: dict) -> None:
        doc["images"] = [{"uri": uri}]
    return change


def _outside_bin(tmp_path: Path) -> None:
    (tmp_path / "outside.bin").write_bytes(b"\0" * 64)


def _link_bin_out(tmp_path: Path) -> None:
    _outside_bin(tmp_path)
    (tmp_path / "asset" / "linked.bin").symlink_to(tmp_path / "outside.bin")


def _fifo_bin(tmp_path: Path) -> None:
    os.mkfifo(tmp_path / "asset" / "pipe.bin")


def _big_bin(tmp_path: Path) -> None:
    _sparse(tmp_path / "asset" / "big.bin", MAX_GLTF_BYTES + 1)


def _many(key: str, n: int, item):
    def change(tmp_path: Path, doc: dict) -> None:
        doc[key] = [item] * n
    return change


def _declared_vertices(tmp_path: Path, doc: dict) -> None:
    doc["accessors"][0]["count"] = MAX_VERTICES + 1


def _instanced(tmp_path: Path, doc: dict) -> None:
    """One mesh of 30,000 vertices instanced by enough nodes to pass MAX_VERTICES."""
    n = 30_000
    rng = np.random.default_rng(0)
    pos = rng.random((n, 3)).astype("<f4")
    idx = np.arange(n, dtype="<u4")
    blob = pos.tobytes() + idx.tobytes()
    doc["accessors"] = [
        {"bufferView": 0, "componentType": 5126, "count": n, "type": "VEC3",
         "min": pos.min(axis=0).tolist(), "max": pos.max(axis=0).tolist()},
        {"bufferView": 1, "componentType": 5125, "count": n, "type": "SCALAR"}]
    doc["bufferViews"] = [{"buffer": 0, "byteOffset": 0, "byteLength": pos.nbytes},
                          {"buffer": 0, "byteOffset": pos.nbytes, "byteLength": idx.nbytes}]
    doc["buffers"] = [{"byteLength": len(blob),
                       "uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode()}]
    doc["meshes"] = [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}]
    copies = MAX_VERTICES // n + 1
    doc["nodes"] = [{"children": list(range(1, copies + 1))}] + [
        {"mesh": 0, "translation": [float(i), 0.0, 0.0]} for i in range(copies)]


BAD_GLTF_REFS = {
    "http buffer": (_buffer_uri("http://example.com/data.bin"), "URL"),
    "file URL buffer": (_buffer_uri("file:///etc/passwd"), "URL"),
    "absolute buffer": (_buffer_uri("/etc/passwd"), "absolute path"),
    "device buffer": (_buffer_uri("/dev/zero"), "absolute path"),
    "encoded absolute buffer": (_buffer_uri("%2Fdev%2Fzero"), "absolute path"),
    "parent-folder buffer": (_buffer_uri("../outside.bin", _outside_bin), "outside the asset's folder"),
    "linked buffer": (_buffer_uri("linked.bin", _link_bin_out), "outside the asset's folder"),
    "FIFO buffer": (_buffer_uri("pipe.bin", _fifo_bin), "not a regular file"),
    "oversized buffer": (_buffer_uri("big.bin", _big_bin), "MAX_GLTF_BYTES"),
    "plain data URI": (_buffer_uri("data:application/octet-stream,AAAA"), "not base64"),
    "http image": (_image_uri("https://example.com/t.png"), "URL"),
    "parent-folder image": (_image_uri("../t.png"), "outside the asset's folder"),
    "absolute image": (_image_uri("/dev/random"), "absolute path"),
    "too many images": (_many("images", MAX_IMAGES + 1, {"uri": "t.png"}), "MAX_IMAGES"),
    "too many nodes": (_many("nodes", MAX_GLTF_ITEMS + 1, {}), "MAX_GLTF_ITEMS"),
    "declared vertices": (_declared_vertices, "MAX_VERTICES"),
    "instanced vertices": (_instanced, "MAX_VERTICES"),
}


@pytest.mark.parametrize("case", BAD_GLTF_REFS)
def test_gltf_references_and_counts_are_refused(tmp_path, case):
    change, fragment = BAD_GLTF_REFS[case]
    (tmp_path / "asset").mkdir()
    doc = _doc(tmp_path)
    change(tmp_path, doc)
    path = tmp_path / "asset" / "model.gltf"
    path.write_text(json.dumps(doc))
    with pytest.raises(AssetImportError) as info:
        load_gltf(path)
    assert str(path) in str(info.value) and fragment in str(info.value), str(info.value)


BAD_GLTF_FILES = {
    "larger than MAX_GLTF_BYTES": (lambda d: _sparse(d / "model.glb", MAX_GLTF_BYTES + 1), "MAX_GLTF_BYTES"),
    "a link to a device": (lambda d: (d / "model.glb").symlink_to("/dev/zero") or d / "model.glb", "not a file"),
}


@pytest.mark.parametrize("case", BAD_GLTF_FILES)
def test_gltf_files_that_are_not_small_regular_files_are_refused(tmp_path, case):
    make, fragment = BAD_GLTF_FILES[case]
    path = make(tmp_path)
    with pytest.raises(AssetImportError) as info:
        load_gltf(path)
    assert str(path) in str(info.value) and fragment in str(info.value), str(info.value)


def test_a_buffer_file_beside_the_asset_loads(tmp_path):
    doc = _doc(tmp_path)
    uri = doc["buffers"][0]["uri"]
    (tmp_path / "sub").mkdir()
    (tmp_path / "sub" / "data.bin").write_bytes(base64.b64decode(uri.partition(",")[2]))
    doc["buffers"][0]["uri"] = "sub/data.bin"
    path = tmp_path / "model.gltf"
    path.write_text(json.dumps(doc))
    assert len(load_gltf(path).links[0].parts) == 1

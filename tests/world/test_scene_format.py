"""The scene format: exact round trips, and malformed files rejected with named fields."""

from __future__ import annotations

import copy
import json
import math

import pytest

from legent_gym.world.scene import (
    SceneError,
    load_scene,
    loads_scene,
    save_scene,
    scene_json_schema,
    validate_scene,
)

MINIMAL = {
    "rooms": [{"id": "r0", "type": "bedroom", "name": "bedroom", "polygon": [[0, 0], [4, 0], [4, 3], [0, 3]]}],
    "walls": [{"id": "w0", "start": [0, 0], "end": [4, 0], "rooms": ["r0", "exterior"]}],
    "doors": [{"id": "d0", "wall": "w0", "offset": 2.0}],
    "objects": [
        {"id": 0, "asset": "bed", "position": [1.5, 1.5, 0.0], "rotation": [0, 0, 90]},
        {"id": 1, "asset": "apple", "position": [1.5, 1.5, 0.5], "kind": "interactable", "on": 0},
    ],
    "agent": {"position": [3.0, 1.0], "yaw": 90.0},
}


def _with(path: str, value):
    """MINIMAL with the field at a dotted path (list indices as ints) replaced."""
    data = copy.deepcopy(MINIMAL)
    keys = [int(k) if k.isdigit() else k for k in path.split(".")]
    target = data
    for k in keys[:-1]:
        target = target[k]
    if value is _DELETE:
        del target[keys[-1]]
    else:
        target[keys[-1]] = value
    return data


_DELETE = object()


def test_minimal_scene_validates():
    scene = validate_scene(MINIMAL)
    assert scene.object(1).on == 0
    assert scene.wall("w0").length == 4.0


def test_round_trip_is_exact(tmp_path, example_scene_paths):
    assert example_scene_paths, "examples/scenes/*.json must exist"
    for path in example_scene_paths:
        scene = load_scene(path)
        out = tmp_path / path.name
        save_scene(scene, out)
        again = load_scene(out)
        assert again.to_dict() == scene.to_dict()
        assert out.read_text() == scene.to_json()
        # Saving what was loaded reproduces the file byte for byte.
        assert out.read_text() == path.read_text()


def test_round_trip_keeps_awkward_floats(tmp_path):
    data = _with("objects.0.position", [0.1 + 0.2, 1e-7, 1 / 3])
    scene = validate_scene(data)
    save_scene(scene, tmp_path / "s.json")
    assert load_scene(tmp_path / "s.json").object(0).position == (0.1 + 0.2, 1e-7, 1 / 3)


MALFORMED = [
    # (name, text or dict, fragment of the expected message, field path expected)
    ("truncated json", json.dumps(MINIMAL)[:-40], "not valid JSON", ""),
    ("top level list", "[1, 2]", "expected a JSON object", ""),
    ("wrong type", _with("objects.0.position", "here"), "", "objects[0].position"),
    ("missing field", _with("agent", _DELETE), "Field required", "agent"),
    ("missing rooms", _with("rooms", []), "at least 1", "rooms"),
    ("nan", json.dumps(MINIMAL).replace("[1.5, 1.5, 0.0]", "[NaN, 1.5, 0.0]"), "NaN", ""),
    ("infinity", json.dumps(MINIMAL).replace("[3.0, 1.0]", "[Infinity, 1.0]"), "Infinity", ""),
    ("nan via python", _with("agent.yaw", math.nan), "finite", "agent.yaw"),
    ("unknown asset", _with("objects.0.asset", "spaceship"), "unknown asset id 'spaceship'", "objects[0].asset"),
    ("negative scale", _with("objects.0.scale", [1, -1, 1]), "greater than or equal to 0.001",
     "objects[0].scale[1]"),
    # Pathological but well-formed: numbers whose lengths, areas or meshes overflow, nesting
    # deeper than Python's parser goes, degenerate shapes.
    ("huge coordinate", json.dumps(_with("rooms.0.polygon", [[0, 0], [1e308, 0], [1e308, 1e308], [0, 1e308]])),
     "less than or equal to 10000", "rooms[0].polygon[1][0]"),
    ("wall of overflowing length", _with("walls.0.start", [-1e308, 0]), "greater than or equal to -10000",
     "walls[0].start[0]"),
    ("huge size", _with("walls.0.height", 1e300), "less than or equal to 10000", "walls[0].height"),
    ("vanishing scale", _with("objects.0.scale", [1e-300, 1, 1]), "greater than or equal to 0.001",
     "objects[0].scale[0]"),
    ("overflowing float", json.dumps(MINIMAL).replace("[3.0, 1.0]", "[1e400, 1.0]"), "finite", "agent.position[0]"),
    ("huge id", _with("objects.0.id", 10**30), "less than or equal to 2147483647", "objects[0].id"),
    ("zero light direction", _with("lights", [{"position": [1, 1, 2], "direction": [0, 0, 0]}]), "zero vector",
     "lights[0].direction"),
    ("zero-length wall", _with("walls.0.end", [0, 0]), "same point", "walls[0]"),
    ("two-point room", _with("rooms.0.polygon", [[0, 0], [1, 0]]), "at least 3", "rooms[0].polygon"),
    ("deeply nested", "[" * 100_000 + "]" * 100_000, "nested too deeply", ""),
    ("deeply nested object", '{"a":' * 100_000 + "1" + "}" * 100_000, "nested too deeply", ""),
    ("empty file", "", "not valid JSON", ""),
    ("top level null", "null", "expected a JSON object", ""),
    ("duplicate object ids", _with("objects.1.id", 0), "duplicate id 0", "objects[1].id"),
    ("unknown field", _with("objects.0.colour", "red"), "Extra inputs", "objects[0].colour"),
    ("door on unknown wall", _with("doors.0.wall", "w9"), "unknown wall 'w9'", "doors[0].wall"),
    ("door outside wall", _with("doors.0.offset", 3.9), "does not fit", "doors[0].offset"),
    ("rests on missing object", _with("objects.1.on", 7), "no object with id 7", "objects[1].on"),
    ("degenerate room", _with("rooms.0.polygon", [[0, 0], [1, 1], [2, 2]]), "no area", "rooms[0].polygon"),
    ("bad kind", _with("objects.1.kind", "flying"), "static", "objects[1].kind"),
    ("wrong version", _with("version", 7), "1", "version"),
    ("negative id", _with("objects.0.id", -3), "greater than or equal to 0", "objects[0].id"),
    ("colour out of range", _with("rooms.0.floor", {"rgba": [2, 0, 0, 1]}), "less than or equal to 1",
     "rooms[0].floor.rgba[0]"),
]


@pytest.mark.parametrize("name,data,message,path", MALFORMED, ids=[m[0] for m in MALFORMED])
def test_malformed_scene_is_rejected_with_a_named_problem(name, data, message, path, tmp_path):
    file = tmp_path / "bad.json"
    with pytest.raises(SceneError) as info:
        if isinstance(data, str):  # text: through the file loader
            file.write_text(data)
            load_scene(file)
        else:  # Python data (may hold NaN, which JSON text cannot): through the validator
            validate_scene(data, source=str(file))
    err = info.value
    rendered = str(err)
    assert str(file) in rendered
    assert message in rendered, rendered
    if path:
        assert any(p == path for p, _ in err.problems), err.problems


def test_one_line_summary_names_the_file(tmp_path):
    file = tmp_path / "bad.json"
    file.write_text(json.dumps(_with("agent.position", [1e308, 1e308])))
    with pytest.raises(SceneError) as info:
        load_scene(file)
    summary = info.value.summary()
    assert "\n" not in summary and summary.startswith(f"{file}: invalid scene: agent.position[0]")


def test_byte_order_mark_is_allowed(tmp_path):
    file = tmp_path / "bom.json"
    file.write_bytes(b"\xef\xbb\xbf" + json.dumps(MINIMAL).encode())
    assert load_scene(file).agent.yaw == 90.0


def test_missing_file_and_binary_file(tmp_path):
    with pytest.raises(SceneError, match="cannot read file"):
        load_scene(tmp_path / "nope.json")
    (tmp_path / "bin.json").write_bytes(b"\xff\xfe\x00garbage")
    with pytest.raises(SceneError, match="UTF-8"):
        load_scene(tmp_path / "bin.json")


def test_all_problems_reported_at_once():
    data = _with("objects.0.asset", "spaceship")
    data["doors"][0]["wall"] = "nowhere"
    with pytest.raises(SceneError) as info:
        validate_scene(data)
    paths = {p for p, _ in info.value.problems}
    assert {"objects[0].asset", "doors[0].wall"} <= paths


def test_save_is_atomic(tmp_path, monkeypatch):
    """A save interrupted mid-write leaves the old file intact and no temporary file."""
    import legent_gym.utils.atomic as atomic_module

    scene = validate_scene(MINIMAL)
    target = tmp_path / "scene.json"
    save_scene(scene, target)
    before = target.read_text()

    class PowerCut(Exception):
        pass

    def cut(fd):
        raise PowerCut

    monkeypatch.setattr(atomic_module.os, "fsync", cut)
    scene.name = "changed"
    with pytest.raises(PowerCut):
        save_scene(scene, target)
    assert target.read_text() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["scene.json"]


def test_json_schema_describes_the_format():
    schema = scene_json_schema()
    assert "rooms" in schema["properties"] and "objects" in schema["properties"]


def test_loads_scene_skips_asset_check_when_asked():
    text = json.dumps(_with("objects.0.asset", "my_own"))
    assert loads_scene(text, asset_known=None).object(0).asset == "my_own"


def test_saved_files_get_ordinary_permissions(tmp_path):
    import os
    import stat

    save_scene(validate_scene(MINIMAL), tmp_path / "s.json")
    umask = os.umask(0)
    os.umask(umask)
    assert stat.S_IMODE((tmp_path / "s.json").stat().st_mode) == 0o666 & ~umask


def test_save_makes_imported_sources_relative_copying_what_lies_outside(tmp_path):
    """An absolute source outside the scene's folder is copied beside the file (a .gltf with
    the buffers it names); one inside the folder is only written relative; the saved scene
    loads and its assets import from the copies."""
    import trimesh

    from legent_gym.world.assets.gltf import load_imported_asset

    outside, house = tmp_path / "models", tmp_path / "house"
    outside.mkdir()
    (house / "own").mkdir(parents=True)
    trimesh.creation.box((0.5, 0.3, 0.4)).export(outside / "crate.gltf")  # + gltf_buffer_*.bin
    trimesh.creation.box((0.2, 0.2, 0.2)).export(house / "own" / "cube.glb")
    assert sorted(p.name for p in outside.iterdir()) != ["crate.gltf"]  # it names buffer files
    data = copy.deepcopy(MINIMAL)
    data["assets"] = [
        {"id": "crate", "source": str(outside / "crate.gltf"), "yaw": 90, "receptacles": []},
        {"id": "cube", "source": str(house / "own" / "cube.glb")}]
    data["objects"] += [{"id": 2, "asset": "crate", "position": [3.0, 2.5, 0.0]},
                        {"id": 3, "asset": "cube", "position": [0.5, 2.5, 0.0]}]
    scene = validate_scene(data)
    save_scene(scene, house / "scene.json")
    saved = json.loads((house / "scene.json").read_text())
    assert [a["source"] for a in saved["assets"]] == ["scene_assets/crate/crate.gltf", "own/cube.glb"]
    assert sorted(p.name for p in (house / "scene_assets" / "crate").iterdir()) == \
        sorted(p.name for p in outside.iterdir())
    assert scene.assets[0].source == str(outside / "crate.gltf")  # the scene itself is unchanged
    loaded = load_scene(house / "scene.json")
    crate = load_imported_asset(loaded.assets[0], loaded.base_dir)
    lo, hi = crate.bounds()
    # glTF y is up: 0.5 wide, 0.4 deep, 0.3 high; turned a quarter, the width lies along y.
    assert hi - lo == pytest.approx((0.4, 0.5, 0.3), abs=1e-6) and crate.receptacles == []

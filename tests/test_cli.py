"""The legent-gym command line, as a user runs it."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import cv2
import numpy as np
import pytest

from legent_gym.cli import main

from .conftest import EXAMPLES, GLTF_SAMPLES

# The console script that `pip install` puts beside the interpreter (pyproject's [project.scripts]).
LEGENT_GYM = Path(sys.executable).parent / "legent-gym"


def test_validate_good_and_bad(tmp_path, capsys):
    assert main(["validate", str(EXAMPLES / "one_room.json")]) == 0
    assert "valid" in capsys.readouterr().out
    bad = tmp_path / "bad.json"
    bad.write_text('{"rooms": [], "agent": {"position": [0, "x"]}}')
    assert main(["validate", str(bad)]) == 2
    err = capsys.readouterr().err
    assert "rooms" in err and "agent.position[1]" in err and str(bad) in err


@pytest.mark.parametrize("view", ["topdown", "agent", "user"])
def test_render_views(tmp_path, view):
    out = tmp_path / f"{view}.png"
    assert main(["render", str(EXAMPLES / "two_room_furnished.json"), "--view", view, "--out", str(out),
                 "--size", "64", "--profile", "fast"]) == 0
    img = cv2.imread(str(out))
    assert img.shape == (64, 64, 3) and img.std() > 3


def test_asset_list_and_builtin_preview(tmp_path, capsys):
    assert main(["asset", "list"]) == 0
    listing = capsys.readouterr().out
    assert "sofa" in listing and "couch" in listing
    out = tmp_path / "sofa.png"
    assert main(["asset", "preview", "sofa", "--out", str(out), "--size", "64"]) == 0
    assert cv2.imread(str(out)).std() > 3
    assert main(["asset", "preview", "spaceship", "--out", str(out)]) == 2
    assert "neither" in capsys.readouterr().err


def test_asset_preview_of_a_gltf_file(tmp_path):
    source = GLTF_SAMPLES / "BoxTextured.gltf"
    out = tmp_path / "box.png"
    assert main(["asset", "preview", str(source), "--out", str(out), "--size", "64"]) == 0
    img = cv2.imread(str(out))
    assert img.std() > 3


def test_broken_glb_is_a_clear_error(tmp_path, capsys):
    broken = tmp_path / "broken.glb"
    broken.write_bytes(b"glTF\x02\x00\x00\x00\xff\x00\x00\x00trunc")
    assert main(["asset", "preview", str(broken), "--out", str(tmp_path / "x.png")]) == 2
    err = capsys.readouterr().err
    assert "broken.glb" in err and "Traceback" not in err
    assert not (tmp_path / "x.png").exists()


def test_installed_entry_point(tmp_path):
    assert LEGENT_GYM.is_file(), f"{LEGENT_GYM} is missing: install the package (pip install -e .)"
    result = run_cli("validate", str(EXAMPLES / "two_room_furnished.json"))
    assert result.returncode == 0, result.stderr
    assert "80 objects" in result.stdout


def test_generate_single_house_with_map(tmp_path, capsys):
    out, png = tmp_path / "house.json", tmp_path / "house.png"
    assert main(["generate", "--preset", "TwoRoom", "--seed", "3", "--out", str(out), "--map", str(png)]) == 0
    assert main(["validate", str(out)]) == 0
    img = cv2.imread(str(png))
    assert img is not None and img.std() > 3
    first = out.read_text()
    assert main(["generate", "--preset", "TwoRoom", "--seed", "3", "--out", str(out)]) == 0
    assert out.read_text() == first  # deterministic


def test_generate_batch_resumes(tmp_path):
    out_dir = tmp_path / "houses"
    assert main(["generate", "--preset", "OneRoom", "--seed", "0", "--count", "3", "--out-dir", str(out_dir)]) == 0
    files = sorted(out_dir.glob("*.json"))
    assert len(files) == 3
    files[1].unlink()
    assert main(["generate", "--preset", "OneRoom", "--seed", "0", "--count", "3", "--out-dir", str(out_dir)]) == 0
    assert len(sorted(out_dir.glob("*.json"))) == 3


def test_generate_impossible_request_is_a_clear_error(tmp_path, capsys):
    assert main(["generate", "--preset", "Castle", "--out", str(tmp_path / "x.json")]) == 2
    assert "Castle" in capsys.readouterr().err
    assert not (tmp_path / "x.json").exists()


# --- bad inputs, as a user meets them: one line naming the file, exit status 2 ------------

def run_cli(*args: str, cwd=None) -> subprocess.CompletedProcess:
    """``legent-gym ARGS`` in a fresh process: the installed console script, as a user runs it."""
    return subprocess.run([str(LEGENT_GYM), *args], capture_output=True, text=True, timeout=300, cwd=cwd)


def assert_one_line_error(result: subprocess.CompletedProcess, named: str | None) -> None:
    output = result.stdout + result.stderr
    assert result.returncode == 2, output
    assert "Traceback" not in output, output
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("legent-gym: error: "), result.stderr
    if named is not None:
        assert named in lines[0], lines[0]


def _scene(**changes) -> dict:
    data = json.loads((EXAMPLES / "one_room.json").read_text())
    for path, value in changes.items():
        target = data
        keys = [int(k) if k.isdigit() else k for k in path.split("__")]
        for key in keys[:-1]:
            target = target[key]
        target[keys[-1]] = value
    return data


def _json_file(text: str | bytes | dict | list):
    def write(tmp_path: Path) -> Path:
        path = tmp_path / "bad scene.json"
        if isinstance(text, bytes):
            path.write_bytes(text)
        else:
            path.write_text(text if isinstance(text, str) else json.dumps(text))
        return path
    return write


GOOD = json.dumps(_scene())
BAD_SCENES = {
    "empty file": _json_file(""),
    "json list": _json_file("[1, 2, 3]"),
    "json null": _json_file("null"),
    "not utf-8": _json_file(b"\xff\xfe{\"rooms\": \x80}"),
    "truncated": _json_file(GOOD[:-30]),
    "NaN literal": _json_file(GOOD.replace('"yaw": 180.0', '"yaw": NaN')),
    "Infinity literal": _json_file(GOOD.replace('"yaw": 180.0', '"yaw": -Infinity')),
    "overflowing 1e400": _json_file(GOOD.replace('"yaw": 180.0', '"yaw": 1e400')),
    "1e308 room": _json_file(_scene(rooms__0__polygon=[[0, 0], [1e308, 0], [1e308, 1e308], [0, 1e308]])),
    "1e308 wall": _json_file(_scene(walls__0__start=[-1e308, 0], walls__0__end=[1e308, 0])),
    "1e308 object": _json_file(_scene(objects__0__position=[1e308, 0, 0], objects__0__scale=[1e308, 1, 1])),
    "huge integer": _json_file(GOOD.replace('"version": 1', '"version": ' + "9" * 5000)),
    "huge id": _json_file(_scene(objects__0__id=10**30)),
    "zero-length wall": _json_file(_scene(walls__0__end=_scene()["walls"][0]["start"])),
    "2-point polygon": _json_file(_scene(rooms__0__polygon=[[0, 0], [1, 0]])),
    "collinear polygon": _json_file(_scene(rooms__0__polygon=[[0, 0], [1, 0], [2, 0]])),
    "zero light direction": _json_file(_scene(lights=[{"position": [1, 1, 2], "direction": [0, 0, 0]}])),
    "vanishing scale": _json_file(_scene(objects__0__scale=[1e-300, 1, 1])),
    "deeply nested array": _json_file("[" * 100_000 + "]" * 100_000),
    "deeply nested object": _json_file('{"a":' * 100_000 + "1" + "}" * 100_000),
    "unknown asset": _json_file(_scene(objects__0__asset="spaceship")),
    "a directory": lambda tmp_path: (tmp_path / "bad scene.json").mkdir() or tmp_path / "bad scene.json",
    "missing file": lambda tmp_path: tmp_path / "bad scene.json",
    "a device": lambda tmp_path: Path("/dev/zero"),
    "too many objects": _json_file(_scene(objects=[{**_scene()["objects"][0], "id": i} for i in range(10_001)])),
    "asset URL": _json_file(_scene(assets=[{"id": "x", "source": "https://example.com/x.glb"}])),
    "asset outside the folder": _json_file(_scene(assets=[{"id": "x", "source": "../x.glb"}])),
    "asset on a device": _json_file(_scene(assets=[{"id": "x", "source": "/dev/zero"}])),
}


@pytest.mark.parametrize("case", BAD_SCENES)
def test_validate_bad_scene_is_one_line(tmp_path, case):
    path = BAD_SCENES[case](tmp_path)
    assert_one_line_error(run_cli("validate", str(path)), str(path))


def _gltf(points, *, indices=None, mode=4, name="model.gltf"):
    def write(tmp_path: Path) -> Path:
        from tests.world.test_gltf import write_gltf

        return write_gltf(tmp_path / name, points, indices=indices, mode=mode)
    return write


def _raw(name: str, data: bytes | str):
    def write(tmp_path: Path) -> Path:
        path = tmp_path / name
        path.write_bytes(data if isinstance(data, bytes) else data.encode())
        return path
    return write


TETRA_FACES = [0, 1, 2, 0, 1, 3, 0, 2, 3, 1, 2, 3]
BAD_GLTF = {
    "empty glb": _raw("model.glb", b""),
    "truncated glb": _raw("model.glb", b"glTF\x02\x00\x00\x00\xff\x00\x00\x00trunc"),
    "empty gltf": _raw("model.gltf", ""),
    "json list": _raw("model.gltf", "[1, 2]"),
    "not utf-8": _raw("model.gltf", b"\xff\xfe\x80"),
    "deeply nested": _raw("model.gltf", "[" * 100_000 + "]" * 100_000),
    "glTF 1.0": _raw("model.gltf", '{"asset": {"version": "1.0"}}'),
    "missing buffer": _raw("model.gltf", '{"asset": {"version": "2.0"}, "buffers": [{"uri": "gone.bin", '
                                         '"byteLength": 4}]}'),
    "no meshes": _raw("model.gltf", '{"asset": {"version": "2.0"}}'),
    "trimesh fails": _raw("model.gltf", json.dumps({
        "asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
        "accessors": [{"bufferView": 7, "componentType": 5126, "count": 3, "type": "VEC3"}]})),
    "points only": _gltf([[0, 0, 0], [1, 0, 0], [0, 1, 0]], mode=0),
    "non-finite vertices": _gltf([[0, 0, 0], [float("nan"), 0, 0], [0, 1, 0], [0, 0, 1]], indices=TETRA_FACES),
    "zero-area triangles": _gltf([[0, 0, 0], [1, 0, 0], [2, 0, 0]]),
    "too small to build": _gltf([[0, 0, 0], [1e-7, 0, 0], [0, 1e-7, 0], [0, 0, 1e-7]], indices=TETRA_FACES),
    "missing file": lambda tmp_path: tmp_path / "model.glb",
    "a directory": lambda tmp_path: (tmp_path / "model.glb").mkdir() or tmp_path / "model.glb",
}


@pytest.mark.parametrize("case", BAD_GLTF)
def test_asset_preview_bad_file_is_one_line(tmp_path, case):
    path = BAD_GLTF[case](tmp_path)
    out = tmp_path / "x.png"
    assert_one_line_error(run_cli("asset", "preview", str(path), "--out", str(out), "--size", "32"), str(path))
    assert not out.exists()


BAD_PREVIEW_ARGS = {
    "unknown id": (["spaceship"], "spaceship"),
    "not a glTF": (["model.obj"], "model.obj"),
    "out is a directory": (["sofa", "--out", "outdir"], "outdir"),
    "size 0": (["sofa", "--size", "0"], "--size"),
    "negative variant": (["sofa", "--variant", "-1"], "--variant"),
}


@pytest.mark.parametrize("case", BAD_PREVIEW_ARGS)
def test_asset_preview_bad_arguments_are_one_line(tmp_path, case):
    args, named = BAD_PREVIEW_ARGS[case]
    (tmp_path / "outdir").mkdir()
    (tmp_path / "model.obj").write_text("v 0 0 0\n")
    if "--out" not in args:
        args = [*args, "--out", "x.png"]
    assert_one_line_error(run_cli("asset", "preview", *args, cwd=tmp_path), named)


def _scene_with_asset(source: str, make=None):
    def write(tmp_path: Path) -> Path:
        if make is not None:
            make(tmp_path)
        data = _scene(assets=[{"id": "thing", "source": source}])
        data["objects"][0]["asset"] = "thing"
        path = tmp_path / "bad scene.json"
        path.write_text(json.dumps(data))
        return path
    return write


BAD_RENDER = {
    "1e308 room (MuJoCo's compiler)": (BAD_SCENES["1e308 room"], "bad scene.json"),
    "deeply nested": (BAD_SCENES["deeply nested array"], "bad scene.json"),
    "vanishing scale (MuJoCo's compiler)": (BAD_SCENES["vanishing scale"], "bad scene.json"),
    "asset is not glTF": (_scene_with_asset("asset.txt", _raw("asset.txt", "hello")), "asset.txt"),
    "asset missing": (_scene_with_asset("gone.glb"), "gone.glb"),
    "asset truncated": (_scene_with_asset("model.glb", BAD_GLTF["truncated glb"]), "model.glb"),
    "asset too small": (_scene_with_asset("model.gltf", BAD_GLTF["too small to build"]), "model.gltf"),
}


@pytest.mark.parametrize("case", BAD_RENDER)
def test_render_bad_scene_is_one_line(tmp_path, case):
    write, named = BAD_RENDER[case]
    path = write(tmp_path)
    out = tmp_path / "x.png"
    result = run_cli("render", str(path), "--out", str(out), "--size", "32", "--profile", "fast")
    assert_one_line_error(result, named)
    assert not out.exists()


def test_render_to_a_directory_is_one_line(tmp_path):
    (tmp_path / "outdir").mkdir()
    result = run_cli("render", str(EXAMPLES / "one_room.json"), "--out", "outdir", "--size", "32", cwd=tmp_path)
    assert_one_line_error(result, "outdir")


BAD_GENERATE = {
    "unknown preset": (["--preset", "Castle", "--out", "x.json"], "Castle"),
    "out is a directory": (["--out", "outdir"], "outdir"),
    "map is a directory": (["--out", "x.json", "--map", "outdir"], "outdir"),
    "out-dir is a file": (["--count", "2", "--out-dir", "afile"], "afile"),
    "out below a file": (["--out", "afile/x.json"], "afile"),
    "negative seed": (["--seed", "-1", "--out", "x.json"], "--seed"),
    "huge seed": (["--seed", "9" * 30, "--out", "x.json"], "--seed"),
    "zero count": (["--count", "0", "--out-dir", "houses"], "--count"),
}


@pytest.mark.parametrize("case", BAD_GENERATE)
def test_generate_bad_arguments_are_one_line(tmp_path, case):
    args, named = BAD_GENERATE[case]
    (tmp_path / "outdir").mkdir()
    (tmp_path / "afile").write_text("")
    assert_one_line_error(run_cli("generate", *args, cwd=tmp_path), named)


BAD_COLLECT = {
    "unknown env": (["Legent/Nope-v0", "--out", "data"], "Legent/Nope-v0"),
    "out is a file": (["Legent/ComeHere-OneRoom-v0", "--out", "afile"], "afile"),
    "bad env-kwargs JSON": (["Legent/ComeHere-OneRoom-v0", "--out", "data", "--env-kwargs", "{bad"],
                            "--env-kwargs"),
    "scene file nested too deeply": (["Legent/ComeHere-OneRoom-v0", "--out", "data", "--env-kwargs",
                                      '{"scene": "deep.json"}'], "deep.json"),
    "unknown format": (["Legent/ComeHere-OneRoom-v0", "--out", "data", "--format", "bogus"], "bogus"),
    "zero episodes": (["Legent/ComeHere-OneRoom-v0", "--out", "data", "--episodes", "0"], "--episodes"),
}


@pytest.mark.parametrize("case", BAD_COLLECT)
def test_collect_bad_arguments_are_one_line(tmp_path, case):
    args, named = BAD_COLLECT[case]
    (tmp_path / "afile").write_text("")
    (tmp_path / "deep.json").write_text("[" * 100_000 + "]" * 100_000)
    if "--episodes" not in args:
        args = [*args, "--episodes", "1"]
    assert_one_line_error(run_cli("collect", *args, "--quiet", cwd=tmp_path), named)


BAD_ANNOTATE = {
    "missing file": (["nothere.glb"], "nothere.glb"),
    "not a glTF": (["afile"], "not a .glb or .gltf file"),
    "URL without model": ([str(GLTF_SAMPLES / "Box.gltf"), "--llm-base-url", "http://127.0.0.1:9/v1"], "--model"),
    "out is a directory": ([str(GLTF_SAMPLES / "Box.gltf"), "--out", "outdir"], "outdir"),
    "nothing listens": ([str(GLTF_SAMPLES / "Box.gltf"), "--llm-base-url", "http://127.0.0.1:9/v1", "--model", "m",
                         "--retries", "0", "--timeout", "2"], "Connection refused"),
}


@pytest.mark.parametrize("case", BAD_ANNOTATE)
def test_asset_annotate_bad_arguments_are_one_line(tmp_path, case):
    args, named = BAD_ANNOTATE[case]
    (tmp_path / "outdir").mkdir()
    (tmp_path / "afile").write_text("")
    assert_one_line_error(run_cli("asset", "annotate", *args, "--cache-dir", "cache", "--out", "x.json"
                                  if "--out" not in args else "outdir", cwd=tmp_path), named)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["afile", "outdir"]


BAD_TASKS = {
    "zero tasks": (["--n", "0", "--model", "m", "--out", "t.jsonl"], "--n"),
    "too many tasks": (["--n", "1000", "--model", "m", "--out", "t.jsonl"], "--n"),
    "no model": (["--out", "t.jsonl"], "--model"),
    "out is a directory": (["--model", "m", "--out", "outdir"], "outdir"),
    "scene missing": (["--model", "m", "--out", "t.jsonl"], "missing.json"),
    "asset annotation missing": (["--model", "m", "--out", "t.jsonl", "--asset", "nothere.asset.json"],
                                 "nothere.asset.json: No such file"),
    "nothing listens": (["--model", "m", "--out", "t.jsonl", "--llm-base-url", "http://127.0.0.1:9/v1",
                         "--retries", "0", "--timeout", "2"], "Connection refused"),
}


@pytest.mark.parametrize("case", BAD_TASKS)
def test_tasks_generate_bad_arguments_are_one_line(tmp_path, case):
    args, named = BAD_TASKS[case]
    (tmp_path / "outdir").mkdir()
    scene = "missing.json" if case == "scene missing" else str(EXAMPLES / "one_room.json")
    assert_one_line_error(run_cli("tasks", "generate", scene, *args, cwd=tmp_path), named)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["outdir"]


@pytest.mark.parametrize("where", ["before", "after"])
def test_debug_shows_the_traceback(tmp_path, where):
    bad = tmp_path / "deep.json"
    bad.write_text("[" * 100_000 + "]" * 100_000)
    args = ["--debug", "validate", str(bad)] if where == "before" else ["validate", str(bad), "--debug"]
    result = run_cli(*args)
    assert result.returncode != 0 and "Traceback" in result.stderr


def test_every_gltf_sample_previews_to_a_non_blank_image(tmp_path):
    samples = sorted(GLTF_SAMPLES.glob("*.gltf"))
    assert len(samples) == 7, samples
    failed = []
    for sample in samples:
        out = tmp_path / f"{sample.stem}.png"
        result = run_cli("asset", "preview", str(sample), "--out", str(out), "--size", "64", "--profile", "fast")
        image = cv2.imread(str(out)) if result.returncode == 0 else None
        # Not blank: more than one colour in the PNG.
        if image is None or len(np.unique(image.reshape(-1, 3), axis=0)) < 2:
            failed.append(f"{sample.name}: rc={result.returncode} {result.stderr.strip()[-300:]}")
    assert not failed, "\n".join(failed)

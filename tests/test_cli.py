"""The legent-gym command line, as a user runs it."""

from __future__ import annotations

import shutil
import subprocess

import cv2
import pytest

from legent_gym.cli import main

from .conftest import EXAMPLES, SHARED_GLTF


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
    source = SHARED_GLTF / "BoxTextured.gltf"
    if not source.exists():
        pytest.skip("shared/testdata/gltf is not beside the checkout")
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
    exe = shutil.which("legent-gym")
    if exe is None:
        pytest.skip("legent-gym is not on PATH (package not installed)")
    result = subprocess.run([exe, "validate", str(EXAMPLES / "two_room_furnished.json")],
                            capture_output=True, text=True, timeout=120)
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

"""scripts/gallery.py: a picture of each room type in both profiles and a map, the same twice."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import cv2

SCRIPT = Path(__file__).resolve().parents[1] / "scripts" / "gallery.py"


def _gallery():
    spec = importlib.util.spec_from_file_location("gallery", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_gallery_pictures_every_room_type_the_same_twice(tmp_path):
    gallery = _gallery()
    first, second = tmp_path / "a", tmp_path / "b"
    assert gallery.main(["--out", str(first), "--size", "64"]) == 0
    expected = {f"{room}_{profile}.jpg" for room in gallery.ROOM_TYPES for profile in ("fast", "pretty")}
    assert {p.name for p in first.iterdir()} == expected | {"map.png"}
    for name in expected:
        image = cv2.imread(str(first / name))
        assert image.shape == (64, 64, 3) and image.std() > 10, name  # a view of something, not one colour
    assert gallery.main(["--out", str(second), "--size", "64"]) == 0
    assert all((first / n).read_bytes() == (second / n).read_bytes() for n in expected | {"map.png"})

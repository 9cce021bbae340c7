"""Surface patterns: in range, deterministic, distinct per variant, seamless where they repeat,
grain along u, and the mappings from scene materials."""

from __future__ import annotations

import hashlib
import itertools
import subprocess
import sys

import numpy as np
import pytest

from legent_gym.world.materials import (
    OBJECT_PATTERNS,
    PATTERN_VARIANTS,
    SURFACE_PATTERNS,
    TILE,
    object_pattern,
    pattern,
    surface_pattern,
    tile,
)

ALL_PATTERNS = sorted(OBJECT_PATTERNS | SURFACE_PATTERNS)
EVERY = [(name, variant) for name in ALL_PATTERNS for variant in range(PATTERN_VARIANTS)]


def _digest(array: np.ndarray) -> str:
    return hashlib.sha256(np.ascontiguousarray(array).tobytes()).hexdigest()


@pytest.mark.parametrize(("name", "variant"), EVERY)
def test_pattern_shape_range_and_contrast(name: str, variant: int) -> None:
    p = pattern(name, variant)
    assert p.shape == (TILE, TILE)
    assert p.dtype == np.float32
    assert not p.flags.writeable
    assert 0.9 <= p.mean() <= 1.1
    assert p.min() >= 0.5 and p.max() <= 1.4
    assert p.std() > 0.005  # not flat


def test_patterns_are_cached_and_variants_wrap() -> None:
    assert pattern("wood", 1) is pattern("wood", 1)
    assert np.array_equal(pattern("wood", 1 + PATTERN_VARIANTS), pattern("wood", 1))


def test_patterns_are_deterministic_across_processes() -> None:
    """The same texels in a fresh process (another hash seed, nothing cached)."""
    here = {f"{name} {variant}": _digest(pattern(name, variant)) for name, variant in EVERY}
    code = (
        "import hashlib, numpy as np\n"
        "from legent_gym.world.materials import OBJECT_PATTERNS, PATTERN_VARIANTS, SURFACE_PATTERNS, pattern\n"
        "for name in sorted(OBJECT_PATTERNS | SURFACE_PATTERNS):\n"
        "    for variant in range(PATTERN_VARIANTS):\n"
        "        p = np.ascontiguousarray(pattern(name, variant))\n"
        "        print(name, variant, hashlib.sha256(p.tobytes()).hexdigest())\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    there = {" ".join(line.split()[:2]): line.split()[2] for line in out.splitlines()}
    assert there == here


def test_recomputed_after_cache_clear_is_identical() -> None:
    before = {key: pattern(*key).copy() for key in EVERY}
    pattern.cache_clear()
    for key, array in before.items():
        assert np.array_equal(pattern(*key), array), key


@pytest.mark.parametrize("name", ALL_PATTERNS)
def test_variants_differ(name: str) -> None:
    variants = [pattern(name, v) for v in range(PATTERN_VARIANTS)]
    for a, b in itertools.combinations(range(PATTERN_VARIANTS), 2):
        assert not np.array_equal(variants[a], variants[b]), (name, a, b)


@pytest.mark.parametrize(("name", "variant"), [(n, v) for n, v in EVERY if n in SURFACE_PATTERNS])
def test_surface_patterns_tile_seamlessly(name: str, variant: int) -> None:
    """The step from the last column (row) to the first is no harsher than a step inside."""
    p = pattern(name, variant).astype(np.float64)
    for axis in (0, 1):
        q = np.moveaxis(p, axis, 0)  # rows of q: the lines across `axis`
        interior = np.abs(np.diff(q, axis=0)).mean()
        wrap = np.abs(q[-1] - q[0]).mean()
        assert wrap <= 1.5 * interior, (name, variant, axis, wrap, interior)


@pytest.mark.parametrize("name", ["wood", "metal"])
@pytest.mark.parametrize("variant", range(PATTERN_VARIANTS))
def test_grain_runs_along_u(name: str, variant: int) -> None:
    p = pattern(name, variant).astype(np.float64)
    along_u = np.abs(np.diff(p, axis=1)).mean()
    along_v = np.abs(np.diff(p, axis=0)).mean()
    assert along_u < along_v


@pytest.mark.parametrize(("name", "variant"), EVERY)
def test_tile_multiplies_the_colour(name: str, variant: int) -> None:
    t = tile(name, variant, (200, 100, 50))
    assert t.dtype == np.uint8 and t.shape == (TILE, TILE, 3)
    expected = np.clip(np.round(np.array([200, 100, 50]) * pattern(name, variant)[..., None]), 0, 255)
    assert np.array_equal(t, expected.astype(np.uint8))


def test_tile_clips_bright_colours() -> None:
    t = tile("floorboards", 0, (255, 255, 255))
    assert t.max() == 255 and t.min() < 200  # brighter boards clip, seams stay dark


def test_unknown_pattern_is_named() -> None:
    with pytest.raises(ValueError, match="velvet") as raised:
        pattern("velvet", 0)
    assert "wood" in str(raised.value)  # the known ones are listed


def test_surface_pattern_of_scene_materials() -> None:
    assert surface_pattern("wood") == "floorboards"
    assert surface_pattern("tile") == "tile"
    assert surface_pattern("carpet") == "carpet"
    assert surface_pattern("stone") == "stone_slabs"
    assert surface_pattern("paint") == "paint"
    assert surface_pattern("wallpaper") == "wallpaper"
    for flat in ("plain", "glass", "floorboards", ""):
        assert surface_pattern(flat) is None
    assert {surface_pattern(m) for m in ("wood", "tile", "carpet", "stone", "paint", "wallpaper")} == SURFACE_PATTERNS


def test_object_pattern_of_part_materials() -> None:
    for name in OBJECT_PATTERNS:
        assert object_pattern(name) == name
    for flat in ("plastic", "glass", "food", "plain", "floorboards", "carpet"):
        assert object_pattern(flat) is None

"""Shared fixtures. Rendering runs headless through EGL (set by legent_gym on import)."""

from __future__ import annotations

from pathlib import Path

import pytest

import legent_gym  # noqa: F401  (sets MUJOCO_GL before mujoco is imported)

REPO = Path(__file__).resolve().parents[1]
EXAMPLES = REPO / "examples" / "scenes"
SHARED_GLTF = REPO.parent / "shared" / "testdata" / "gltf"


@pytest.fixture(scope="session")
def example_scene_paths() -> list[Path]:
    return sorted(EXAMPLES.glob("*.json"))

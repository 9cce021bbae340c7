"""Shared fixtures. Rendering runs headless through EGL (set by legent_gym on import)."""

from __future__ import annotations

from pathlib import Path

import pytest

import legent_gym  # noqa: F401  (sets MUJOCO_GL before mujoco is imported)

from .skip_check import pytest_addoption, pytest_sessionfinish, pytest_terminal_summary  # noqa: F401

REPO = Path(__file__).resolve().parents[1]
EXAMPLES = REPO / "examples" / "scenes"
# Khronos glTF 2.0 sample models (CC0 / CC-BY 4.0; sources and attribution in SOURCES.md there).
GLTF_SAMPLES = REPO / "tests" / "fixtures" / "gltf"


@pytest.fixture(scope="session")
def example_scene_paths() -> list[Path]:
    return sorted(EXAMPLES.glob("*.json"))


"""Shared fixtures. Rendering runs headless through EGL (set by legent_gym on import)."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

# A Ray started by a test binds and advertises the loopback interface only: Ray reads this
# when it is imported, and any test of a worker process may import it before the one that
# starts a cluster (legent_gym.utils.scale sets it too, but only before the first import).
os.environ.setdefault("RAY_ENABLE_WINDOWS_OR_OSX_CLUSTER", "0")
os.environ.setdefault("RAY_USAGE_STATS_ENABLED", "0")

import legent_gym  # noqa: F401  (sets MUJOCO_GL before mujoco is imported)

from .skip_check import pytest_addoption, pytest_sessionfinish, pytest_terminal_summary  # noqa: F401

REPO = Path(__file__).resolve().parents[1]
EXAMPLES = REPO / "examples" / "scenes"
# Khronos glTF 2.0 sample models (CC0 / CC-BY 4.0; sources and attribution in SOURCES.md there).
GLTF_SAMPLES = REPO / "tests" / "fixtures" / "gltf"


@pytest.fixture(scope="session")
def example_scene_paths() -> list[Path]:
    return sorted(EXAMPLES.glob("*.json"))


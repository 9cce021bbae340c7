"""legent_gym/utils/gl_backend.py: the OpenGL backend MuJoCo renders through, in a fresh Python
per case (MuJoCo reads ``MUJOCO_GL`` once, at its first import): EGL on a machine with no
display, the user's ``MUJOCO_GL`` whatever else holds, and MuJoCo's own default (GLFW) on a
display, a real X server (Xvfb) here. Each case renders a frame and compares it with the
EGL frame."""

from __future__ import annotations

import contextlib
import ctypes.util
import json
import os
import shutil
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest

from tests.conftest import REPO

#: Renders the agent's view of an example house at 32 x 32 and prints what was chosen.
PROBE = """
import json, os, sys
if "mujoco-first" in sys.argv:
    import mujoco
import legent_gym
from legent_gym.utils import gl_backend
chosen = {"MUJOCO_GL": os.environ.get("MUJOCO_GL"), "PYOPENGL_PLATFORM": os.environ.get("PYOPENGL_PLATFORM")}
if "render" in sys.argv:
    from legent_gym.world import load_scene
    from legent_gym.world.builder import build_world
    from legent_gym.world.render import Renderer
    renderer = Renderer(build_world(load_scene("examples/scenes/one_room.json")), 32, 32, profile="fast")
    chosen["rgb"] = renderer.rgb("agent").tolist()
    chosen["context"] = gl_backend.context_class().__module__
print(json.dumps(chosen))
"""
XVFB = shutil.which("Xvfb")
needs_osmesa = pytest.mark.skipif(ctypes.util.find_library("OSMesa") is None,
                                  reason="no libOSMesa (Debian: apt-get install libosmesa6; scripts/setup.sh installs "
                                         "it with the dev extra)")
needs_xvfb = pytest.mark.skipif(XVFB is None, reason="no Xvfb (Debian: apt-get install xvfb; scripts/setup.sh "
                                                      "installs it with the dev extra)")


def probe(render: bool = True, mujoco_first: bool = False, **variables: str) -> tuple[dict, str]:
    """What a fresh ``import legent_gym`` chooses (after ``import mujoco`` if
    ``mujoco_first``), with ``variables`` as the only display and OpenGL variables set; and
    what else it wrote (stderr, other lines of stdout)."""
    env = {k: v for k, v in os.environ.items()
           if k not in ("MUJOCO_GL", "PYOPENGL_PLATFORM", "DISPLAY", "WAYLAND_DISPLAY")}
    env.update(variables)
    flags = (["render"] if render else []) + (["mujoco-first"] if mujoco_first else [])
    done = subprocess.run([sys.executable, "-c", PROBE, *flags], cwd=REPO, env=env,
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr[-3000:]
    printed = [line for line in done.stdout.splitlines() if line.startswith("{")]
    assert printed, done.stdout[-2000:]
    return json.loads(printed[-1]), done.stderr + done.stdout.replace(printed[-1], "")


@pytest.fixture(scope="module")
def egl_frame() -> np.ndarray:
    chosen, _ = probe()
    assert chosen["MUJOCO_GL"] == "egl" and chosen["PYOPENGL_PLATFORM"] == "egl" and chosen["context"] == "mujoco.egl"
    return np.array(chosen["rgb"], dtype=np.uint8)


@contextlib.contextmanager
def xvfb() -> Iterator[str]:
    """A virtual X server on a display number it picks; yields ``":N"``."""
    read, write = os.pipe()
    proc = subprocess.Popen([XVFB, "-displayfd", str(write), "-nolisten", "tcp", "-screen", "0", "320x240x24"],
                            pass_fds=(write,), stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    os.close(write)
    try:
        with os.fdopen(read) as pipe:
            number = pipe.readline().strip()  # written once the server accepts connections
        assert number.isdigit(), "Xvfb did not start"
        yield f":{number}"
    finally:
        proc.terminate()
        proc.wait(timeout=30)


def test_no_display_no_choice_is_egl(egl_frame):
    assert egl_frame.shape == (32, 32, 3) and egl_frame.std() > 5  # a picture, not a blank


def test_mujoco_imported_first_still_renders_through_egl(egl_frame):
    """A program that imports MuJoCo before legent_gym on a machine with no display (MuJoCo
    then picks GLFW, which needs one) renders the same frame through EGL."""
    chosen, stderr = probe(mujoco_first=True)
    assert chosen["MUJOCO_GL"] == "egl" and chosen["context"] == "mujoco.egl"
    assert np.array_equal(np.array(chosen["rgb"], dtype=np.uint8), egl_frame)


@needs_osmesa
def test_mujoco_gl_osmesa_is_honoured_and_renders_the_same_picture(egl_frame):
    chosen, stderr = probe(MUJOCO_GL="osmesa")
    assert chosen["MUJOCO_GL"] == "osmesa" and chosen["PYOPENGL_PLATFORM"] == "osmesa"
    assert chosen["context"] == "mujoco.osmesa"
    assert np.abs(np.array(chosen["rgb"], dtype=np.int16) - egl_frame).mean() < 1.0
    assert "Traceback" not in stderr and "Exception ignored" not in stderr, stderr[-2000:]  # a clean exit


def test_a_display_without_mujoco_gl_is_left_to_mujoco():
    """With a display the choice is MuJoCo's (GLFW): nothing is set (without rendering: no
    X server listens on this display)."""
    for variable in ("DISPLAY", "WAYLAND_DISPLAY"):
        chosen, _ = probe(render=False, **{variable: ":4242" if variable == "DISPLAY" else "wayland-4242"})
        assert chosen == {"MUJOCO_GL": None, "PYOPENGL_PLATFORM": None}, variable


@needs_xvfb
def test_on_a_real_display_mujoco_renders_through_glfw_and_mujoco_gl_still_wins(egl_frame):
    with xvfb() as display:
        chosen, _ = probe(DISPLAY=display)
        assert chosen["MUJOCO_GL"] is None and chosen["context"] == "mujoco.glfw"
        assert np.abs(np.array(chosen["rgb"], dtype=np.int16) - egl_frame).mean() < 1.0
        chosen, _ = probe(DISPLAY=display, MUJOCO_GL="egl")
        assert chosen["MUJOCO_GL"] == "egl" and chosen["context"] == "mujoco.egl"


# -- GPUs for vector env workers ------------------------------------------------------------

def test_workers_are_spread_over_the_gpus_round_robin():
    from legent_gym.utils.gl_backend import egl_device_for_worker

    assert [egl_device_for_worker(n, 4) for n in range(9)] == [0, 1, 2, 3, 0, 1, 2, 3, 0]
    assert [egl_device_for_worker(n, gpus) for n in range(3) for gpus in (0, 1)] == [None] * 6


@pytest.mark.parametrize(("visible", "count"), [("0,2,3", 3), ("1", 1), ("", 0), ("-1", 0)])
def test_gpu_count_follows_cuda_visible_devices(monkeypatch, visible, count):
    from legent_gym.utils.gl_backend import nvidia_gpu_count

    monkeypatch.setenv("CUDA_VISIBLE_DEVICES", visible)
    assert nvidia_gpu_count() == count


def test_a_worker_gets_its_gpu_unless_the_user_chose(monkeypatch):
    """Two visible GPUs: worker 3 renders on the second; a device the user set, or a backend
    other than EGL, is left alone."""
    from legent_gym.utils.gl_backend import assign_egl_device

    monkeypatch.setenv("CUDA_VISIBLE_DEVICES", "0,1")
    monkeypatch.setenv("MUJOCO_GL", "egl")
    # setenv first, so that monkeypatch restores the variable as it was, whatever
    # assign_egl_device writes: a device left set would follow this worker's later tests
    monkeypatch.setenv("MUJOCO_EGL_DEVICE_ID", "unset")
    monkeypatch.delenv("MUJOCO_EGL_DEVICE_ID")
    assert assign_egl_device(3) == 1 and os.environ["MUJOCO_EGL_DEVICE_ID"] == "1"
    monkeypatch.setenv("MUJOCO_EGL_DEVICE_ID", "0")
    assert assign_egl_device(3) is None and os.environ["MUJOCO_EGL_DEVICE_ID"] == "0"
    monkeypatch.delenv("MUJOCO_EGL_DEVICE_ID")
    monkeypatch.setenv("MUJOCO_GL", "osmesa")
    assert assign_egl_device(3) is None and "MUJOCO_EGL_DEVICE_ID" not in os.environ
    monkeypatch.setenv("MUJOCO_GL", "egl")
    monkeypatch.setenv("CUDA_VISIBLE_DEVICES", "0")
    assert assign_egl_device(3) is None and "MUJOCO_EGL_DEVICE_ID" not in os.environ


def test_gl_info_names_what_renders():
    """``legent-gym gl-info`` makes a context and prints its renderer: on a machine without
    an NVIDIA GPU, Mesa's llvmpipe; a device that does not exist is an error naming the
    variable."""
    command = str(Path(sys.executable).with_name("legent-gym"))
    env = {k: v for k, v in os.environ.items() if k not in ("MUJOCO_GL", "PYOPENGL_PLATFORM", "DISPLAY",
                                                              "WAYLAND_DISPLAY", "MUJOCO_EGL_DEVICE_ID")}
    out = subprocess.run([command, "gl-info"], capture_output=True, text=True, env=env, timeout=120)
    assert out.returncode == 0, out.stderr
    info = dict(line.split(": ", 1) for line in out.stdout.splitlines())
    assert info["MUJOCO_GL"] == "egl" and info["renderer"]
    if info["NVIDIA GPUs"] == "0":
        assert "llvmpipe" in info["renderer"]
    bad = subprocess.run([command, "gl-info"], capture_output=True, text=True, timeout=120,
                         env={**env, "MUJOCO_EGL_DEVICE_ID": "99"})
    assert bad.returncode != 0 and "MUJOCO_EGL_DEVICE_ID" in bad.stderr


#: Renders one 32 x 32 frame in the profile argv[1] names and prints the renderer, the
#: ``LP_NUM_THREADS`` then set and the names of the process's threads.
THREADS_PROBE = """
import json, os, sys
import legent_gym
from OpenGL import GL
from legent_gym.world import load_scene
from legent_gym.world.builder import build_world
from legent_gym.world.render import Renderer
renderer = Renderer(build_world(load_scene("examples/scenes/one_room.json")), 32, 32, profile=sys.argv[1])
renderer.rgb("agent")
threads = [open(f"/proc/self/task/{t}/comm").read().strip() for t in os.listdir("/proc/self/task")]
print(json.dumps({"renderer": GL.glGetString(GL.GL_RENDERER).decode(), "lp": os.environ.get("LP_NUM_THREADS"),
                  "threads": threads}))
"""


def threads_probe(profile: str, **variables: str) -> dict:
    env = {k: v for k, v in os.environ.items() if k not in ("LP_NUM_THREADS", "MUJOCO_GL", "PYOPENGL_PLATFORM",
                                                              "DISPLAY", "WAYLAND_DISPLAY")}
    env.update(variables)
    done = subprocess.run([sys.executable, "-c", THREADS_PROBE, profile], cwd=REPO, env=env,
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr[-3000:]
    return json.loads([line for line in done.stdout.splitlines() if line.startswith("{")][-1])


def rasteriser_threads(found: dict) -> int:
    return sum(name.startswith("llvmpipe-") for name in found["threads"])


@pytest.mark.skipif(not Path("/proc/self/task").is_dir(), reason="needs Linux's /proc to name threads")
def test_a_fast_renderer_has_llvmpipe_draw_in_its_own_thread_unless_the_user_chose():
    """A process whose first renderer is "fast" sets ``LP_NUM_THREADS=0`` before its
    OpenGL context (llvmpipe then starts no rasteriser thread); a "pretty" first renderer
    leaves llvmpipe its threads; a value the user set is kept."""
    fast = threads_probe("fast")
    assert fast["lp"] == "0"
    if "llvmpipe" not in fast["renderer"]:
        pytest.skip(f"renders on {fast['renderer']}, not llvmpipe: no rasteriser threads to count")
    assert rasteriser_threads(fast) == 0
    chosen = threads_probe("fast", LP_NUM_THREADS="2")
    assert chosen["lp"] == "2" and rasteriser_threads(chosen) == 2
    pretty = threads_probe("pretty")
    assert pretty["lp"] is None
    if len(os.sched_getaffinity(0)) > 1:
        assert rasteriser_threads(pretty) > 0

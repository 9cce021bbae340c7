"""Pick an OpenGL backend for MuJoCo before anything imports it: EGL on a Linux machine
with no display, unless ``MUJOCO_GL`` is set (why: see docs/architecture.md). MuJoCo reads
``MUJOCO_GL`` once, at its first import, so every module that imports MuJoCo imports this
first.
"""

import os
import sys


def default_mujoco_gl() -> None:
    if "MUJOCO_GL" in os.environ:
        return
    has_display = bool(os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"))
    if sys.platform.startswith("linux") and not has_display:
        os.environ["MUJOCO_GL"] = "egl"
        # PyOpenGL must agree with MuJoCo about the platform.
        os.environ.setdefault("PYOPENGL_PLATFORM", "egl")


default_mujoco_gl()

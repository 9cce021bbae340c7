"""Pick an OpenGL backend for MuJoCo before anything imports it.

MuJoCo reads ``MUJOCO_GL`` once, at its first import. Our users run on headless Linux
servers, where GLFW (MuJoCo's default) aborts the process when there is no display, so
we default to EGL (works with Mesa llvmpipe, no X server) unless the user chose a
backend or a display is present.
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

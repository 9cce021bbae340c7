"""Pick an OpenGL backend for MuJoCo before anything imports it: EGL on a Linux machine
with no display, unless ``MUJOCO_GL`` is set (why: see docs/architecture.md). MuJoCo reads
``MUJOCO_GL`` once, at its first import, so every module that imports MuJoCo imports this
first.
"""

import atexit
import os
import sys
import weakref


def default_mujoco_gl() -> None:
    if "MUJOCO_GL" in os.environ:
        return
    has_display = bool(os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"))
    if sys.platform.startswith("linux") and not has_display:
        os.environ["MUJOCO_GL"] = "egl"
        # PyOpenGL must agree with MuJoCo about the platform.
        os.environ.setdefault("PYOPENGL_PLATFORM", "egl")


default_mujoco_gl()


# Live OpenGL contexts, for leak checks: the renderer registers each EGL/OSMesa context it
# makes ("gl") and each MuJoCo rendering context (``MjrContext``: framebuffers, uploaded
# meshes and textures, "mjr"). Weak references: an object that is garbage is not counted.
_live: dict[str, weakref.WeakSet] = {"gl": weakref.WeakSet(), "mjr": weakref.WeakSet()}


def track_context(kind: str, context: object) -> None:
    """Count ``context`` (kind ``"gl"`` or ``"mjr"``) in :func:`live_contexts` while it lives."""
    _live[kind].add(context)
    if kind == "gl" and type(context).__module__ == "mujoco.osmesa":
        # MuJoCo's OSMesa context frees itself in __del__, which at interpreter exit may run
        # after PyOpenGL is torn down and print a traceback: free it while Python is whole.
        atexit.register(_free_at_exit, weakref.ref(context))


def _free_at_exit(context: weakref.ref) -> None:
    live = context()
    if live is not None:
        live.free()


def live_contexts() -> dict[str, int]:
    """How many OpenGL contexts (``"gl"``) and MuJoCo rendering contexts (``"mjr"``) made
    by this process's renderers are alive now."""
    return {kind: len(objects) for kind, objects in _live.items()}

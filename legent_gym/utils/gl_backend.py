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


def context_class() -> type:
    """The OpenGL context class of the backend ``MUJOCO_GL`` names now.

    MuJoCo chooses its backend when it is first imported: a program that imports MuJoCo
    before legent_gym on a machine with no display gets GLFW, which cannot open a context
    there, although :func:`default_mujoco_gl` has since set ``MUJOCO_GL=egl``. So the EGL
    and OSMesa classes are taken from their own modules, whatever the import order was."""
    backend = os.environ.get("MUJOCO_GL", "").strip().lower()
    # imported here: this module is imported before MuJoCo, to set MUJOCO_GL first
    if backend == "egl":
        from mujoco.egl import GLContext
        return GLContext
    if backend == "osmesa":
        from mujoco.osmesa import GLContext
        return GLContext
    from mujoco import gl_context  # MuJoCo's own choice (GLFW where there is a display)

    chosen = getattr(gl_context, "GLContext", None)
    if chosen is None:
        raise RuntimeError("no OpenGL backend: set MUJOCO_GL to egl or osmesa on a headless machine")
    return chosen


def draw_in_calling_thread() -> None:
    """Have Mesa's llvmpipe draw in the thread that renders (``LP_NUM_THREADS=0``), unless
    ``LP_NUM_THREADS`` is set already. Mesa reads it when the process makes its first
    OpenGL context, so this is called just before that. Left alone, llvmpipe starts a
    rasteriser thread per core the process may use and splits every frame between them:
    for a 96 px frame the hand-over costs more than the drawing (``docs/performance.md``,
    "Rendering threads"). Same images either way; other drivers (NVIDIA's) ignore it."""
    os.environ.setdefault("LP_NUM_THREADS", "0")


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


# -- NVIDIA GPUs ------------------------------------------------------------------------
# MuJoCo's EGL backend renders on the EGL device that MUJOCO_EGL_DEVICE_ID names (a CUDA
# device index when the driver maps EGL devices to CUDA ones, as NVIDIA's does), read when
# the process makes its first OpenGL context; without it, every process takes the first
# device. So on a machine with several GPUs the workers of a vector env are spread over them.

#: One folder per NVIDIA GPU the kernel driver knows.
NVIDIA_GPUS = "/proc/driver/nvidia/gpus"


def nvidia_gpu_count() -> int:
    """How many NVIDIA GPUs this process may use: the entries of ``CUDA_VISIBLE_DEVICES``
    when it is set, else the GPUs the NVIDIA kernel driver lists (0 without the driver)."""
    visible = os.environ.get("CUDA_VISIBLE_DEVICES")
    if visible is not None:
        return len([v for v in visible.split(",") if v.strip() and not v.strip().startswith("-")])
    try:
        return len(os.listdir(NVIDIA_GPUS))
    except OSError:
        return 0


def egl_device_for_worker(number: int, gpus: int) -> int | None:
    """The GPU a vector env's worker ``number`` renders on among ``gpus`` (round robin), or
    None when there is nothing to choose (fewer than two GPUs)."""
    return number % gpus if gpus >= 2 else None


def assign_egl_device(number: int) -> int | None:
    """In a vector env's worker, before its first frame: set ``MUJOCO_EGL_DEVICE_ID`` to the
    worker's GPU when MuJoCo renders through EGL on a machine with several NVIDIA GPUs and
    the user has not set it. Returns the device set, or None."""
    if os.environ.get("MUJOCO_GL") != "egl" or "MUJOCO_EGL_DEVICE_ID" in os.environ:
        return None
    device = egl_device_for_worker(number, nvidia_gpu_count())
    if device is not None:
        os.environ["MUJOCO_EGL_DEVICE_ID"] = str(device)
    return device


def describe() -> dict[str, str]:
    """What renders in this process: the backend, the EGL device asked for, and the OpenGL
    vendor, renderer and version of a context made now (``"llvmpipe ..."`` is Mesa's
    software rasteriser on the CPU; an NVIDIA GPU names itself)."""
    context = context_class()(16, 16)
    # PyOpenGL, a dependency of MuJoCo's EGL and OSMesa backends, imported after them
    from OpenGL import GL
    try:
        context.make_current()
        info = {name: GL.glGetString(getattr(GL, f"GL_{name.upper()}")).decode()
                for name in ("vendor", "renderer", "version")}
    finally:
        context.free()
    return {"MUJOCO_GL": os.environ.get("MUJOCO_GL", "(MuJoCo's default)"),
            "MUJOCO_EGL_DEVICE_ID": os.environ.get("MUJOCO_EGL_DEVICE_ID", "(first device)"),
            "NVIDIA GPUs": str(nvidia_gpu_count()), **info}

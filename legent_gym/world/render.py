"""Rendering: egocentric RGB, depth and instance segmentation, top-down and free views.

Speed on a CPU (Mesa llvmpipe through EGL) comes from six choices, measured in
``benchmarks/render.py``:

* one OpenGL context per process, shared by every renderer (creating one costs hundreds of
  milliseconds); and a closed renderer's ``MjrContext`` and ``MjvScene`` are kept for the
  next renderer of the thread, which re-uploads only its model's meshes, textures and
  material table into them (a new house then pays about a millisecond instead of four
  for making and three for freeing them);
* the ``fast`` profile: no shadows, reflections or multisampling, and an offscreen buffer
  the size of the image;
* the builder's merged meshes coloured through one atlas texture (few draw calls, few
  triangles), sampled at the nearest texel;
* the renderer is created lazily, on the first frame, so that environments can be
  pickled and forked before any OpenGL exists;
* a frame sets only what changed since the last one: the context is made current, the
  renderer's framebuffer bound and the camera set up only when they are not already (at
  96 px these calls cost as much as a tenth of the render itself);
* fixed cameras (the agent's, the user's) leave out the geoms wholly outside their view
  (:mod:`legent_gym.world.culling`): the same pixels for about a quarter less time at
  96 px, since llvmpipe pays for every geom sent to it, in view or not.

Every call returns a new array (Gymnasium's checker requires it).
"""

from __future__ import annotations

import copy
import os
import threading
from collections.abc import Iterator
from dataclasses import dataclass
from typing import Literal

import mujoco
import numpy as np

from legent_gym.utils import gl_backend  # before mujoco
from legent_gym.world.builder import (
    GROUP_AGENT,
    GROUP_CEILING,
    GROUP_COLLISION,
    GROUP_USER,
    PALETTE_TEXTURE,
    SURFACE_TEXTURE_PREFIX,
    World,
)
from legent_gym.world.culling import FrustumCull

Profile = Literal["fast", "pretty"]


@dataclass(frozen=True)
class FreeCamera:
    """A camera looking at ``lookat`` from ``distance`` metres (azimuth/elevation degrees)."""

    lookat: tuple[float, float, float]
    distance: float = 6.0
    azimuth: float = 45.0
    elevation: float = -35.0
    orthographic: bool = False


CameraSpec = str | FreeCamera  # "agent", "user", "topdown", a model camera name, or a FreeCamera

#: The model's global fovy (MuJoCo's default), which free cameras use: "topdown" sets it to
#: the house's size, so a free camera must set it back.
FREE_FOVY = 45.0

_local = threading.local()

#: Whether this process made an OpenGL context here, and whether it was forked from one
#: that had (see :func:`_shared_gl_context`).
_made_gl = False
_forked_after_gl = False
#: GL objects of renderers inherited through a fork, kept so that they are never freed in
#: the child (freeing them calls into the inherited driver).
_inherited: list = []

FORK_AFTER_GL = (
    "this process was forked from one that had already rendered with OpenGL: the graphics driver's state "
    "came across the fork without its threads (llvmpipe's rasterisers), so rendering here would hang. Start "
    "worker processes with 'forkserver' or 'spawn' rather than 'fork': "
    "gym.make_vec(..., vectorization_mode='async', vector_kwargs={'context': 'forkserver'}), "
    "SubprocVecEnv(..., start_method='forkserver'), or multiprocessing.set_start_method('forkserver') "
    "under `if __name__ == '__main__':`; or make the vector env before rendering in the parent"
)


def _note_fork() -> None:
    global _forked_after_gl
    _forked_after_gl = _forked_after_gl or _made_gl


os.register_at_fork(after_in_child=_note_fork)


def _shared_gl_context(width: int, height: int, profile: Profile = "fast"):
    """The process's (thread's) OpenGL context, made once and made current.

    Made for a "fast" renderer, llvmpipe then draws in the calling thread
    (:func:`gl_backend.draw_in_calling_thread`): a 96 px frame costs about half the CPU and
    wall time it costs with llvmpipe's threads. Made for a "pretty" renderer, llvmpipe keeps
    its threads, which draw a 448 px frame with shadows and multisampling in about two
    thirds of the wall time (for more CPU time).

    Raises instead of hanging in a child forked after its parent rendered: such a child
    inherits the OpenGL driver's state but not its threads, so its first frame would wait
    forever for them (with or without a context of its own)."""
    global _made_gl
    if _forked_after_gl:
        raise RuntimeError(FORK_AFTER_GL)
    ctx = getattr(_local, "context", None)
    if ctx is None:
        if profile == "fast":
            gl_backend.draw_in_calling_thread()
        context_class = gl_backend.context_class()
        _made_gl = True
        ctx = context_class(max(width, 64), max(height, 64))
        gl_backend.track_context("gl", ctx)
        _local.context = ctx
        _local.is_current = _current_check(ctx)
    if not _local.is_current():
        ctx.make_current()
        _local.bound = None  # another context was current: rebind our framebuffer too, to be safe
    return ctx


def _current_check(ctx):
    """A cheap test of whether ``ctx`` is the thread's current context: ~1 us with EGL,
    against ~7 us for making it current again. Other backends (OSMesa, GLFW) always answer
    no, so they make it current every frame as before. Another library (a stock
    ``mujoco.Renderer``, a viewer) may have made its own context current in between, so
    this asks EGL rather than remembering."""
    egl_context = getattr(ctx, "_context", None)
    if type(ctx).__module__ != "mujoco.egl" or egl_context is None:
        return lambda: False
    # PyOpenGL's EGL, with the EGL backend alone
    from OpenGL import EGL

    address = egl_context.address

    def is_current() -> bool:
        current = EGL.eglGetCurrentContext()
        return bool(current) and current.address == address

    return is_current


#: Font scale of every renderer's context (the smallest: renderers draw no text).
FONT_SCALE = mujoco.mjtFontScale.mjFONTSCALE_50


def _context_key(model: mujoco.MjModel) -> tuple | None:
    """What a ``MjrContext`` made for ``model`` holds apart from the model's meshes,
    textures, material table and a few scalars (which :func:`_retargeting` rewrites): the
    offscreen and shadow buffers, the fonts and the built-in shapes. Two models with the
    same key can share a context. None for models whose contexts hold more (planes, height
    fields, skins, skyboxes are made per model): such contexts are never reused."""
    # (Enum members compared as ints: numpy compares an array with a MuJoCo enum object by
    # object, a hundred times slower.)
    if model.nhfield or model.nskin or model.nflex or (model.geom_type == int(mujoco.mjtGeom.mjGEOM_PLANE)).any():
        return None
    if (model.tex_type != int(mujoco.mjtTexture.mjTEXTURE_2D)).any():
        return None
    vis = model.vis
    quality = vis.quality
    return (vis.global_.offwidth, vis.global_.offheight, quality.offsamples, quality.shadowsize,
            quality.numslices, quality.numstacks, quality.numquads, float(vis.map.haze),
            tuple(vis.rgba.haze.tolist()), int(model.ntex))


#: Meshes uploaded per piece of :meth:`Renderer.prepare_step` (about a millisecond's work).
MESHES_PER_PIECE = 16


def _retargeting(context: mujoco.MjrContext, model: mujoco.MjModel) -> Iterator[None]:
    """Make a context made for another model of the same :func:`_context_key` draw
    ``model``: what ``mjr_makeContext`` takes from the model, set again (its scalars, the
    material table, the textures, the meshes' display lists), yielding after the textures
    and after every :data:`MESHES_PER_PIECE` meshes."""
    stat, vis = model.stat, model.vis
    context.shadowClip = stat.extent * vis.map.shadowclip
    context.shadowScale = vis.map.shadowscale
    context.fogStart = stat.extent * vis.map.fogstart
    context.fogEnd = stat.extent * vis.map.fogend
    context.fogRGBA[:] = vis.rgba.fog
    context.lineWidth = vis.global_.linewidth
    roles = mujoco.mjtTextureRole.mjNTEXROLE
    context.mat_texid[:] = -1
    context.mat_texuniform[:] = 0
    context.mat_texrepeat[:] = 0
    for i in np.flatnonzero(model.mat_texid[:, mujoco.mjtTextureRole.mjTEXROLE_RGB] >= 0).tolist():
        context.mat_texid[i * roles:(i + 1) * roles] = model.mat_texid[i]
        context.mat_texuniform[i] = model.mat_texuniform[i]
        context.mat_texrepeat[2 * i:2 * i + 2] = model.mat_texrepeat[i]
    for i in range(model.ntex):
        context.textureType[i] = model.tex_type[i]
        mujoco.mjr_uploadTexture(model, context, i)
    for i in range(model.nmesh):
        if i % MESHES_PER_PIECE == 0:
            yield
        mujoco.mjr_uploadMesh(model, context, i)


def set_texture_filters(context: mujoco.MjrContext, model: mujoco.MjModel, profile: Profile) -> None:
    """Sample the atlas at its nearest texel, not trilinearly from mipmaps; in the "fast"
    profile the patterned floors' and walls' textures too.

    Every flat face of a merged mesh has its texture coordinates at the centre of its
    colour's texel, and a patterned face's corners at texel centres inside its tile, so the
    nearest texel is the colour itself and a tile is never blended with its neighbours (a
    mipmap of a far face blends neighbouring colours and tiles). Nearest texels cost less
    work per fragment, which llvmpipe pays for on the CPU (about a tenth of a 96 px frame).
    "pretty" samples the atlas linearly (within a tile: its corners keep half a texel in)
    and the floors and walls trilinearly. MuJoCo sets trilinear filtering when it uploads
    a texture, so this runs after every upload."""
    from OpenGL import GL  # after the backend is chosen (legent_gym.utils.gl_backend)

    nearest = profile == "fast"
    for tid in range(model.ntex):
        name = model.texture(tid).name
        if name == PALETTE_TEXTURE:
            mode = GL.GL_NEAREST if nearest else GL.GL_LINEAR
        elif name.startswith(SURFACE_TEXTURE_PREFIX) and nearest:
            mode = GL.GL_NEAREST
        else:
            continue
        GL.glBindTexture(GL.GL_TEXTURE_2D, int(context.texture[tid]))
        GL.glTexParameteri(GL.GL_TEXTURE_2D, GL.GL_TEXTURE_MIN_FILTER, mode)
        GL.glTexParameteri(GL.GL_TEXTURE_2D, GL.GL_TEXTURE_MAG_FILTER, mode)


#: The sides the "pretty" profile's shadow maps may have (texels).
SHADOW_MAP_SIDES = (512, 2048)


def shadow_map_size(width: int, height: int) -> int:
    """The side of the "pretty" profile's shadow maps for images of this size: about eight
    texels per image pixel across, a power of two within :data:`SHADOW_MAP_SIDES` (2048
    above 128 px). Drawing the shadow maps is most of a "pretty" frame on a CPU: at
    96 px a 1024 map (the size given) draws about three times as fast as a 2048 one, and
    0.1% of the pixels then differ by more than 16 levels (``docs/performance.md``)."""
    side = 8 * max(width, height)
    low, high = SHADOW_MAP_SIDES
    return min(high, max(low, 1 << (side - 1).bit_length()))


def _scene_size(model: mujoco.MjModel) -> int:
    return max(1000, model.ngeom + 100)


def _keep_spare(key: tuple | None, context: mujoco.MjrContext, scene: mujoco.MjvScene) -> None:
    """Keep a closed renderer's context and scene for the next renderer of this thread
    (one pair is kept: the one that holds the most meshes; the other is freed)."""
    spare = getattr(_local, "spare", None)
    if key is None or (spare is not None and spare[0] == key and spare[1].rangeMesh > context.rangeMesh):
        context.free()
        return
    if spare is not None:
        spare[1].free()
    _local.spare = (key, context, scene)


def _take_spare(key: tuple | None, model: mujoco.MjModel):
    """The kept (context, scene) if they can draw ``model`` once retargeted to it (see
    :func:`_retargeting`); else None."""
    spare = getattr(_local, "spare", None)
    if key is None or spare is None or spare[0] != key:
        return None
    _, context, scene = spare
    if context.rangeMesh < 2 * model.nmesh or scene.maxgeom < _scene_size(model):
        return None
    _local.spare = None
    scene.flags[:] = _local.scene_flags  # as a new scene has them
    return context, scene


def free_spare() -> None:
    """Free the context and scene kept for the next renderer of this thread, if any."""
    spare = getattr(_local, "spare", None)
    if spare is not None and not _forked_after_gl:
        _local.spare = None
        _shared_gl_context(64, 64)
        spare[1].free()


class Renderer:
    """Renders a :class:`World` at one image size and profile.

    ``camera`` arguments: ``"agent"`` (egocentric, the agent's own avatar hidden),
    ``"user"`` (the user's eyes, the user's avatar hidden), ``"topdown"`` (orthographic,
    the ceiling hidden), the name of any camera in the model, or a :class:`FreeCamera`.
    """

    def __init__(self, world: World, width: int = 96, height: int = 96, profile: Profile = "fast"):
        self._context: mujoco.MjrContext | None = None  # first: __del__ runs even if we raise below
        #: The pieces of work left before the context can draw (see prepare_step); None when none are.
        self._preparation: Iterator[None] | None = None
        self._key: tuple | None = None  # what its context can be shared by (see _context_key)
        if width < 1 or height < 1:
            raise ValueError(f"image size must be positive, got {width}x{height}")
        if profile not in ("fast", "pretty"):
            raise ValueError(f"unknown render profile {profile!r}: use 'fast' or 'pretty'")
        self.world = world
        self.width, self.height = int(width), int(height)
        self.profile = profile
        self._scene: mujoco.MjvScene | None = None
        self._option = mujoco.MjvOption()
        self._camera = mujoco.MjvCamera()
        self._perturb = mujoco.MjvPerturb()
        self._camera_spec: CameraSpec | None = None  # what _camera and _option are set up for
        self._segmented = False
        self._cull: FrustumCull | None = None  # the current camera's culling test, if it culls
        #: Geoms the current camera never shows whatever their group: the ceilings, in free
        #: and top-down views (their group also holds the people's hands, which these show).
        self._left_out = np.zeros(0, dtype=np.intp)
        self._ceiling_geoms: np.ndarray | None = None  # looked up on first use
        self._culls: dict[int, FrustumCull] = {}  # by fixed camera id
        self._rect = mujoco.MjrRect(0, 0, self.width, self.height)
        self._rgb = np.empty((self.height, self.width, 3), dtype=np.uint8)
        self._depth = np.empty((self.height, self.width), dtype=np.float32)

    # -- lifecycle -------------------------------------------------------------------------
    def _ensure(self) -> None:
        if self._context is None or self._preparation is not None:
            while not self.prepare_step():
                pass
        _shared_gl_context(self.width, self.height)
        # Every renderer has its own framebuffer in the one GL context, and another
        # renderer may have bound its own since: bind ours, or we draw into theirs.
        if getattr(_local, "bound", None) is not self._context:
            mujoco.mjr_setBuffer(mujoco.mjtFramebuffer.mjFB_OFFSCREEN, self._context)
            _local.bound = self._context

    def prepare_step(self) -> bool:
        """Do the next piece of what the first frame needs done (take the thread's kept
        context or make one, upload the model's textures and then its meshes, about a
        millisecond a piece); True once nothing is left. An env calls it between the steps
        of one house's episode to have the next house's renderer ready before its reset
        (``Episode.stage``); the first frame does whatever is left."""
        if self._preparation is None:
            if self._context is not None:
                return True
            self._preparation = self._prepare()
        _shared_gl_context(self.width, self.height, self.profile)
        done = next(self._preparation, True)
        # Making or filling a context may bind its buffers: the next frame of any renderer
        # binds its own framebuffer again.
        _local.bound = None
        if done:
            self._preparation = None
        return bool(done)

    def _prepare(self) -> Iterator[None]:
        model = self.world.model
        vis = model.vis
        # The offscreen buffer is sized when the context is made: size it to the image.
        vis.global_.offwidth = max(self.width, vis.global_.offwidth if self.profile == "pretty" else 0)
        vis.global_.offheight = max(self.height, vis.global_.offheight if self.profile == "pretty" else 0)
        if self.profile == "pretty":
            vis.quality.shadowsize = shadow_map_size(self.width, self.height)
            vis.quality.offsamples = 4
        else:
            vis.quality.shadowsize = 0
            vis.quality.offsamples = 0
        self._key = _context_key(model)
        kept = _take_spare(self._key, model)
        if kept is None:
            self._context = mujoco.MjrContext(model, FONT_SCALE)
            gl_backend.track_context("mjr", self._context)
            self._scene = mujoco.MjvScene(model, maxgeom=_scene_size(model))
            if getattr(_local, "scene_flags", None) is None:
                _local.scene_flags = self._scene.flags.copy()
        else:
            # Held from here on, so that close() keeps or frees it even if unfinished.
            self._context, self._scene = kept
            for _ in _retargeting(self._context, model):
                yield
                _shared_gl_context(self.width, self.height)
        self._context.readDepthMap = mujoco.mjtDepthMap.mjDEPTH_ZEROFAR
        set_texture_filters(self._context, model, self.profile)
        self._segmented = False  # a new (or reset) scene has the default flags
        fast = self.profile == "fast"
        flags = self._made_scene().flags
        flags[mujoco.mjtRndFlag.mjRND_SHADOW] = not fast
        flags[mujoco.mjtRndFlag.mjRND_REFLECTION] = False
        flags[mujoco.mjtRndFlag.mjRND_SKYBOX] = False
        flags[mujoco.mjtRndFlag.mjRND_HAZE] = False
        self._option.geomgroup[GROUP_COLLISION] = 0

    def close(self) -> None:
        """Release the renderer's GL resources (kept for the next renderer of this thread:
        see :func:`free_spare`)."""
        self._preparation = None
        if self._context is not None:
            if _forked_after_gl:
                _inherited.append((self._context, self._scene))
            else:
                try:
                    _shared_gl_context(self.width, self.height)
                    _keep_spare(self._key, self._context, self._scene)
                except Exception:  # the GL context may already be gone at interpreter exit
                    pass
            if getattr(_local, "bound", None) is self._context:
                _local.bound = None
            self._context = None
            self._scene = None
            self._camera_spec = None

    def __del__(self) -> None:
        self.close()

    def _made_scene(self) -> mujoco.MjvScene:
        """The scene :meth:`_ensure` made (or took over)."""
        scn = self._scene
        if scn is None:
            raise RuntimeError("the renderer has no scene yet: _ensure() makes it")
        return scn

    def upload_textures(self) -> None:
        """Send changed texture data (e.g. a re-coloured palette) to the GPU."""
        if self._context is None:
            return
        _shared_gl_context(self.width, self.height)
        for tid in range(self.world.model.ntex):
            mujoco.mjr_uploadTexture(self.world.model, self._context, tid)
        set_texture_filters(self._context, self.world.model, self.profile)

    # -- cameras -------------------------------------------------------------------------
    def _setup_camera(self, camera: CameraSpec) -> None:
        cam, opt, model = self._camera, self._option, self.world.model
        groups = opt.geomgroup
        groups[GROUP_AGENT] = groups[GROUP_USER] = groups[GROUP_CEILING] = 1
        cam.orthographic = 0
        self._cull = None
        self._left_out = self._no_geoms
        if isinstance(camera, FreeCamera):
            cam.type = mujoco.mjtCamera.mjCAMERA_FREE
            cam.lookat[:] = camera.lookat
            cam.distance, cam.azimuth, cam.elevation = camera.distance, camera.azimuth, camera.elevation
            cam.orthographic = int(camera.orthographic)
            model.vis.global_.fovy = FREE_FOVY
            self._left_out = self._ceilings()
            return
        if camera == "topdown":
            (lo_x, lo_y), (hi_x, hi_y) = self.world.scene.bounds()
            span = max(hi_x - lo_x, (hi_y - lo_y) * self.width / self.height) * 1.08
            cam.type = mujoco.mjtCamera.mjCAMERA_FREE
            cam.lookat[:] = ((lo_x + hi_x) / 2, (lo_y + hi_y) / 2, 0.0)
            cam.distance, cam.azimuth, cam.elevation = 30.0, 90.0, -90.0
            cam.orthographic = 1
            model.vis.global_.fovy = span  # orthographic: fovy is the view height in metres
            self._left_out = self._ceilings()
            return
        name = {"agent": "agent_camera", "user": "user_camera"}.get(camera, camera)
        cid = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_CAMERA, name)
        if cid < 0:
            raise ValueError(f"unknown camera {camera!r}: use 'agent', 'user', 'topdown' or a FreeCamera")
        cam.type = mujoco.mjtCamera.mjCAMERA_FIXED
        cam.fixedcamid = cid
        if camera == "agent":
            groups[GROUP_AGENT] = 0
        elif camera == "user":
            groups[GROUP_USER] = 0
        if self.profile == "fast":  # with shadows or reflections an unseen geom can still show
            if cid not in self._culls:
                self._culls[cid] = FrustumCull(model, cid, self.width, self.height, groups)
            self._cull = self._culls[cid]

    _no_geoms = np.zeros(0, dtype=np.intp)

    def _ceilings(self) -> np.ndarray:
        """The ceiling geoms (what free and top-down views leave out), looked up once: free
        and top-down cameras are set up again every frame."""
        if self._ceiling_geoms is None:
            found = mujoco.mj_name2id(self.world.model, mujoco.mjtObj.mjOBJ_GEOM, "ceilings")
            self._ceiling_geoms = np.array([found] if found >= 0 else [], dtype=np.intp)
        return self._ceiling_geoms

    def _draw(self, camera: CameraSpec, segmentation: bool = False) -> None:
        self._ensure()
        # "topdown" and free cameras set the model's global fovy, which another renderer
        # of the same world may have changed since: set them up every time.
        if camera != self._camera_spec or camera == "topdown" or isinstance(camera, FreeCamera):
            self._setup_camera(camera)
            self._camera_spec = camera
        scn, model, data = self._made_scene(), self.world.model, self.world.data
        if self._cull is None and not len(self._left_out):
            mujoco.mjv_updateScene(model, data, self._option, self._perturb, self._camera, mujoco.mjtCatBit.mjCAT_ALL, scn)
        else:
            # Culled geoms go, for this one call, to a group the option hides: the scene then
            # simply lacks them (MuJoCo has no other per-geom switch that costs nothing).
            hidden = self._cull.outside(data) if self._cull is not None else self._left_out
            groups = model.geom_group
            their_groups = groups[hidden]
            groups[hidden] = GROUP_COLLISION
            try:
                mujoco.mjv_updateScene(model, data, self._option, self._perturb, self._camera,
                                       mujoco.mjtCatBit.mjCAT_ALL, scn)
            finally:
                groups[hidden] = their_groups
        if segmentation != self._segmented:
            scn.flags[mujoco.mjtRndFlag.mjRND_SEGMENT] = segmentation
            scn.flags[mujoco.mjtRndFlag.mjRND_IDCOLOR] = segmentation
            self._segmented = segmentation
        mujoco.mjr_render(self._rect, scn, self._context)

    def mujoco_settings(self, camera: CameraSpec = "agent") -> tuple[mujoco.MjvOption, mujoco.MjvCamera, np.ndarray]:
        """Copies of what this renderer draws ``camera`` with: the visual option, the
        camera and the scene's render flags. MuJoCo's own ``mujoco.Renderer`` of the same
        model, given these, draws the same image (the benchmarks' reference)."""
        self._ensure()
        self._setup_camera(camera)
        self._camera_spec = camera
        flags = self._made_scene().flags.copy()  # as for rgb(), whatever the last frame was
        flags[mujoco.mjtRndFlag.mjRND_SEGMENT] = flags[mujoco.mjtRndFlag.mjRND_IDCOLOR] = 0
        return copy.copy(self._option), copy.copy(self._camera), flags

    # -- images --------------------------------------------------------------------------
    def rgb(self, camera: CameraSpec = "agent") -> np.ndarray:
        """(H, W, 3) uint8."""
        self._draw(camera)
        mujoco.mjr_readPixels(self._rgb, None, self._rect, self._context)
        return self._rgb[::-1].copy()

    def depth(self, camera: CameraSpec = "agent") -> np.ndarray:
        """(H, W) float32 distance along the view axis in metres."""
        self._draw(camera, segmentation=True)  # segment mode: no lighting, exact depth
        mujoco.mjr_readPixels(None, self._depth, self._rect, self._context)
        model = self.world.model
        extent = model.stat.extent
        near, far = model.vis.map.znear * extent, model.vis.map.zfar * extent
        z = self._depth[::-1].astype(np.float64)
        if self._camera.orthographic:
            out = far - z * (far - near)
        else:
            # Reverse-Z perspective (mjDEPTH_ZEROFAR): undo the projection.
            c = -0.5 * (-(far + near) / (far - near)) - 0.5
            d = -0.5 * (-(2.0 * far * near) / (far - near))
            out = d / (z + c)
        return out.astype(np.float32)

    def segmentation(self, camera: CameraSpec = "agent") -> np.ndarray:
        """(H, W) int32 scene object id per pixel; a person's pixels carry that person's
        :data:`~legent_gym.world.builder.PERSON_SEGMENTATION_ID` (user -2, agent -3); -1 for
        house, doors and background."""
        return self.world.geom_segment_lookup(self._geom_ids(camera))

    def geom_ids(self, camera: CameraSpec = "agent") -> np.ndarray:
        """(H, W) int32 MuJoCo geom id per pixel, -1 for background."""
        return self._geom_ids(camera)

    def _geom_ids(self, camera: CameraSpec) -> np.ndarray:
        self._draw(camera, segmentation=True)
        mujoco.mjr_readPixels(self._rgb, None, self._rect, self._context)
        img = self._rgb[::-1].astype(np.int32)
        segid = img[..., 0] + (img[..., 1] << 8) + (img[..., 2] << 16)
        scn = self._made_scene()
        lookup = np.full(scn.ngeom + 1, -1, dtype=np.int32)
        for i in range(scn.ngeom):
            g = scn.geoms[i]
            if g.objtype == mujoco.mjtObj.mjOBJ_GEOM and g.segid >= 0:
                lookup[g.segid + 1] = g.objid
        return lookup[np.clip(segid, 0, scn.ngeom)]


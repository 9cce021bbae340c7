"""Builder: scene -> MjSpec -> compiled model, built for rendering speed on a CPU.

What it makes (see ``docs/architecture.md``):

* The house shell (all floors, all walls, all ceilings) as three merged meshes, coloured
  through the house's atlas texture (palette colours and pattern tiles:
  :mod:`legent_gym.world.meshing`), but for patterned floors and papered or tiled walls:
  one geom per (pattern, colour) on the pattern's repeating texture; collision from boxes.
* One body per object. Its visual is one mesh geom per link (so identity survives for
  segmentation); collision geoms from the asset parts (exact boxes or convex hulls),
  invisible. Interactable objects get a free joint; furniture is welded to the world;
  doors and drawers of furniture are child bodies with hinge or slide joints.
* One body per door leaf, on a hinge joint in its wall opening.
* The agent and the user: mocap bodies (kinematic, moved by the environment) carrying an
  articulated humanoid each (:mod:`legent_gym.world.humanoid`), and a head camera each
  (``agent_camera``, ``user_camera``) on separate head mocap bodies so yaw and pitch are
  set directly.

Geom groups (used to show or hide things per view): 0 house and furniture, 1 small
objects, 2 ceilings, the outside's ground and sky and the agent's hands (``GROUP_HANDS``: every
camera shows them, view rays pass through them; free and top-down views leave the ceilings out
geom by geom), 3 collision only (never drawn), 4 the agent's body but its hands, 5 the user's
body.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from functools import lru_cache

import mujoco
import numpy as np

from legent_gym.world import materials, outside
from legent_gym.world.assets import registry
from legent_gym.world.assets.gltf import load_imported_asset
from legent_gym.world.assets.model import AssetModel, Link, Part, box_part, cylinder_part
from legent_gym.world.geometry import (
    door_hinge_point,
    door_leads_outside,
    heading_deg,
    points_in_polygon,
    wall_frame,
)
from legent_gym.world.humanoid import add_humanoid, appearance_for, element_id
from legent_gym.world.meshing import (
    Atlas,
    ColouredMesh,
    MeshAccumulator,
    SurfaceAccumulator,
    SurfaceMesh,
    link_geometry,
    pattern_variant,
    placed_together,
    polygon_surface,
    prepare_link_geometry,
    wall_piece_box,
    wall_pieces,
)
from legent_gym.world.scene import ObjectInstance, Scene, Surface, scene_base_dir
from legent_gym.world.styles import get_style, styled_palette

#: The version of what a scene builds into: it changes whenever the same scene and options
#: give another model (stored houses are keyed by it, :mod:`legent_gym.envs.house_store`).
#: 2: patterned materials (the atlas, patterned floors and walls), ceiling lamps, and doors
#: and drawers on kitchen counters, desks, sideboards and tv stands. 3: set dressing drawn
#: in the mesh of the piece it rests on.
BUILD_VERSION = 3

GROUP_HOUSE, GROUP_OBJECTS, GROUP_CEILING, GROUP_COLLISION, GROUP_AGENT, GROUP_USER = range(6)
#: The agent's hands share the ceilings' group: every head camera shows it and no view ray
#: meets it (see the module docstring).
GROUP_HANDS = GROUP_CEILING
#: What a person's pixels carry in segmentation images (scene objects carry their ids,
#: which are never negative; -1 is house, doors and background).
PERSON_SEGMENTATION_ID = {"user": -2, "agent": -3}
#: The texture (and material) every merged mesh takes its colours from: the house's atlas
#: of palette colours and pattern tiles (:class:`legent_gym.world.meshing.Atlas`).
PALETTE_TEXTURE = "palette"
#: The surface patterns drawn on repeating textures (painted walls are flat colours of the
#: atlas), and how many (pattern, colour) surfaces a house can have so drawn: one texture
#: each, in every house as many (a renderer's context is reused for a house with as many
#: textures); the surfaces after them are drawn flat.
SURFACE_TEXTURE_PATTERNS = ("floorboards", "tile", "carpet", "stone_slabs", "wallpaper")
SURFACE_TEXTURE_SLOTS = 10
SURFACE_TEXTURE_PREFIX = "surface_"

FLOOR_THICKNESS = 0.05
DOOR_LEAF_THICKNESS = 0.04


@dataclass(frozen=True)
class BodyOptions:
    """The agent's (and user's) body: its collision disc (``radius``), its height (the
    humanoid's nominal height) and its head camera."""

    radius: float = 0.25
    height: float = 1.6
    camera_height: float = 1.5
    fovy: float = 90.0


@dataclass(frozen=True)
class BuildOptions:
    agent: BodyOptions = BodyOptions()
    user: BodyOptions = BodyOptions(radius=0.22, height=1.7, camera_height=1.6)
    with_ceiling: bool = True
    #: Offscreen buffer size the model asks for; renderers resize it to their image size.
    offscreen_size: int = 96
    timestep: float = 0.004
    max_hull_vertices: int = 32
    #: Whether the user moves its limbs (the PettingZoo envs): an articulated body; else
    #: (the single-agent envs, where the user stands still) one mesh in the idle pose.
    user_articulated: bool = True
    #: Ground and sky around the house (:mod:`legent_gym.world.outside`), seen through its
    #: windows and exterior doors; without them those show black.
    with_outside: bool = True
    #: One geom per part with plain colours and default visual settings: the slow reference
    #: the render benchmark compares against. Never use it for observations.
    naive: bool = False


@dataclass
class World:
    """A built scene: the MuJoCo model and data, and maps back to scene ids.

    The map arrays are what tasks, experts and segmentation read: ``geom_object[g]`` is the
    scene object id of geom ``g`` (-1 for house, doors, avatars); ``object_body[id]`` the
    body of an object; ``door_joint[door_id]`` the hinge joint of a door leaf;
    ``geom_segment[g]`` what segmentation images show for geom ``g`` (the object id, a
    person's :data:`PERSON_SEGMENTATION_ID`, or -1).
    """

    scene: Scene
    model: mujoco.MjModel
    data: mujoco.MjData
    #: Object id -> its asset model (a house from an episode helper loads each on first use).
    assets: Mapping[int, AssetModel]
    object_body: dict[int, int]
    object_joints: dict[int, dict[str, int]]
    door_joint: dict[str, int]
    door_body: dict[str, int]
    geom_object: np.ndarray
    geom_door: dict[int, str]
    atlas: Atlas
    options: BuildOptions
    free_objects: list[int] = field(default_factory=list)
    geom_segment: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int32))
    #: Data derived from this world by other modules (e.g. the agent's clearance map),
    #: dropped with it.
    derived: dict[object, object] = field(default_factory=dict, init=False, repr=False, compare=False)
    #: avatar name -> (body mocap id, head mocap id): looked up once, used every step.
    _mocap_ids: dict[str, tuple[int, int]] = field(default_factory=dict, init=False, repr=False, compare=False)
    #: (data.mocap_pos, data.mocap_quat): views of the data's memory, made on first use.
    _mocap_views: tuple[np.ndarray, np.ndarray] | None = field(default=None, init=False, repr=False, compare=False)

    # -- poses of the kinematic bodies ---------------------------------------------------
    def set_body_pose(self, name: str, x: float, y: float, yaw_deg: float, pitch_deg: float = 0.0) -> None:
        """Place an avatar (``agent``/``user``) and its head camera. yaw 0 looks along +x."""
        body, head = self.avatar_mocap_ids(name)
        opts = self.options.agent if name == "agent" else self.options.user
        # Each read of data.mocap_pos makes a new array view: read them once per world.
        views = self._mocap_views
        if views is None:
            views = self._mocap_views = (self.data.mocap_pos, self.data.mocap_quat)
        pos, quat = views
        pos[body] = (x, y, 0.0)
        half = math.radians(yaw_deg) / 2
        quat[body] = (math.cos(half), 0.0, 0.0, math.sin(half))  # yaw_quat's values
        pos[head] = (x, y, opts.camera_height)
        # camera_quat's arithmetic, written straight into the mocap quaternion.
        mujoco.mju_mat2Quat(quat[head], _camera_matrix(yaw_deg, pitch_deg))

    def avatar_mocap_ids(self, name: str) -> tuple[int, int]:
        """(body, head) mocap ids of an avatar (``agent``/``user``), looked up once."""
        ids = self._mocap_ids.get(name)
        if ids is None:
            ids = self._mocap_ids[name] = (int(self.model.body(name).mocapid[0]),
                                           int(self.model.body(f"{name}_head").mocapid[0]))
        return ids

    def object_position(self, object_id: int) -> np.ndarray:
        """Where the object's body origin is now (a copy)."""
        return self.data.xpos[self.object_body[object_id]].copy()

    def object_centre(self, object_id: int) -> np.ndarray:
        """The centre of the object's bounds where it is now (world frame)."""
        lo, hi = self.assets[object_id].bounds()
        body = self.object_body[object_id]
        rot = self.data.xmat[body].reshape(3, 3)
        return self.data.xpos[body] + rot @ ((lo + hi) / 2)

    def geom_object_lookup(self, geom_ids: np.ndarray) -> np.ndarray:
        """Scene object ids for an array of geom ids (-1 stays -1)."""
        return np.where(geom_ids >= 0, self.geom_object[np.maximum(geom_ids, 0)], -1).astype(np.int32)

    def geom_segment_lookup(self, geom_ids: np.ndarray) -> np.ndarray:
        """Segmentation ids (see ``geom_segment``) for an array of geom ids (-1 stays -1)."""
        return np.where(geom_ids >= 0, self.geom_segment[np.maximum(geom_ids, 0)], -1).astype(np.int32)


def yaw_quat(yaw_deg: float) -> np.ndarray:
    half = math.radians(yaw_deg) / 2
    return np.array([math.cos(half), 0.0, 0.0, math.sin(half)])


def camera_quat(yaw_deg: float, pitch_deg: float) -> np.ndarray:
    """Orientation of a MuJoCo camera (looks along its -z, up +y) for a heading and pitch.

    yaw 0 looks along world +x; positive pitch looks down (LEGENT's rotate_down). Plain
    scalar maths: this runs several times per step.
    """
    quat = np.empty(4)
    mujoco.mju_mat2Quat(quat, _camera_matrix(yaw_deg, pitch_deg))
    return quat


def _camera_matrix(yaw_deg: float, pitch_deg: float) -> np.ndarray:
    yaw, pitch = math.radians(yaw_deg), math.radians(pitch_deg)
    cy, sy, cp, sp = math.cos(yaw), math.sin(yaw), math.cos(pitch), math.sin(pitch)
    # Columns: camera x (right), y (up), z (backward) in world coordinates.
    return np.array([sy, sp * cy, -cp * cy,
                     -cy, sp * sy, -cp * sy,
                     0.0, cp, sp])


def euler_deg_quat(rotation) -> np.ndarray:
    quat = np.empty(4)
    mujoco.mju_euler2Quat(quat, np.radians(np.asarray(rotation, dtype=np.float64)), "xyz")
    return quat


def euler_deg_matrix(rotation) -> np.ndarray:
    """The 3x3 matrix of a scene object's rotation (XYZ Euler degrees, as :func:`euler_deg_quat`)."""
    mat = np.empty(9)
    mujoco.mju_quat2Mat(mat, euler_deg_quat(rotation))
    return mat.reshape(3, 3)


class SceneBuildError(ValueError):
    """A valid scene that MuJoCo cannot build (e.g. a degenerate imported mesh)."""


# ---------------------------------------------------------------------------------------


class _SpecBuilder:
    def __init__(self, scene: Scene, options: BuildOptions):
        self.scene = scene
        self.options = options
        self.spec = mujoco.MjSpec()
        self.atlas = Atlas()
        self.assets: dict[int, AssetModel] = {}
        # Meshes and their texture coordinates in texels of the atlas, whose size is known
        # once every mesh asked for its colours and tiles (_finish_palette).
        self._atlas_texcoords: list[tuple[mujoco.MjsMesh, np.ndarray]] = []
        #: door id -> initial hinge angle (radians), set on the compiled model's data
        self.door_initial: dict[str, float] = {}
        self._mesh_count = 0
        self._texture_count = 0
        self._imported = {a.id: a for a in scene.assets}

    # -- top level ----------------------------------------------------------------------
    def build(self) -> tuple[mujoco.MjSpec, Atlas]:
        self._configure()
        self._add_shell()
        for door in self.scene.doors:
            if door.leaf:
                self._add_door_leaf(door)
        assets = [self._asset_for(obj) for obj in self.scene.objects]
        # The links' merged meshes and collision shapes, for all objects at once.
        prepare_link_geometry([(link, obj.kind == "interactable" or link.joint is not None)
                               for obj, asset in zip(self.scene.objects, assets) for link in asset.links])
        riders = self._riders(assets)
        ridden = {rider.id for group in riders.values() for rider, _ in group}
        for obj, asset in zip(self.scene.objects, assets):
            self._add_object(obj, asset, riders.get(obj.id, ()), drawn=obj.id not in ridden)
        self._add_avatar("agent", self.options.agent, GROUP_AGENT)
        self._add_avatar("user", self.options.user, GROUP_USER)
        if self.options.with_outside:
            self._add_outside()
        self._add_lights()
        self._finish_palette()
        return self.spec, self.atlas

    def _configure(self) -> None:
        spec = self.spec
        spec.modelname = "house"
        spec.option.timestep = self.options.timestep
        spec.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
        spec.option.enableflags |= mujoco.mjtEnableBit.mjENBL_SLEEP  # resting objects cost nothing
        spec.compiler.degree = False
        # Compile on the calling thread: a house's few small meshes do not repay a thread
        # pool (measured: the same model for about a fifth less time, on one core or two).
        spec.compiler.usethread = False
        q = spec.visual.quality
        g = spec.visual.global_
        if not self.options.naive:
            q.shadowsize = 0
            q.offsamples = 0
            q.numslices = 8
            q.numstacks = 4
            g.offwidth = self.options.offscreen_size
            g.offheight = self.options.offscreen_size
        spec.visual.map.znear = 0.01
        spec.visual.map.zfar = 50
        style = get_style(self.scene.style.preset)
        self._style = style
        spec.visual.headlight.ambient = [min(a * style.headlight_ambient, 1.0) for a in self.scene.style.ambient]
        spec.visual.headlight.diffuse = [style.headlight_diffuse] * 3
        spec.visual.headlight.specular = [0.0, 0.0, 0.0]
        if not self.options.naive:
            # (sized when every mesh has asked for its colours and tiles)
            tex = spec.add_texture(name=PALETTE_TEXTURE, type=mujoco.mjtTexture.mjTEXTURE_2D,
                                   width=1, height=1, nchannel=3)
            self._palette_texture = tex
            mat = spec.add_material(name=PALETTE_TEXTURE, specular=0.1, shininess=0.2)
            mat.textures[mujoco.mjtTextureRole.mjTEXROLE_RGB] = PALETTE_TEXTURE
            # (filled by _surface_geom; an unused one is one black texel)
            self._surface_textures = []
            for k in range(SURFACE_TEXTURE_SLOTS):
                name = f"{SURFACE_TEXTURE_PREFIX}{k}"
                tex = spec.add_texture(name=name, type=mujoco.mjtTexture.mjTEXTURE_2D, width=1, height=1, nchannel=3)
                tex.data = bytes(3)
                self._surface_textures.append(tex)
                mat = spec.add_material(name=name, specular=0.1, shininess=0.2)
                mat.textures[mujoco.mjtTextureRole.mjTEXROLE_RGB] = name

    # -- geometry helpers ------------------------------------------------------------------
    def _mesh_geom(self, body, mesh: ColouredMesh, *, group: int, name: str, material: str = PALETTE_TEXTURE) -> None:
        """A visual-only mesh geom coloured through the atlas: a flat face at its colour's
        palette texel, a patterned face spanning its (pattern, colour) tile."""
        m = self.spec.add_mesh(name=f"mesh_{self._mesh_count}")
        self._mesh_count += 1
        m.uservert = mesh.vertices.reshape(-1).tolist()
        m.userface = mesh.faces.reshape(-1).tolist()
        m.usernormal = mesh.normals.reshape(-1).tolist()
        m.userfacenormal = _each_thrice(mesh.n_faces)
        # Each mesh carries only the texels it uses: small meshes compile fast.
        used, face_texel = mesh.palette_texels(self.atlas.palette)
        texcoords = self.atlas.palette_texel_origin(used) + 0.5
        corner_texcoord = np.repeat(face_texel, 3)
        if mesh.face_pattern is not None:
            texcoords, corner_texcoord = self._tile_texcoords(mesh, texcoords, corner_texcoord)
        self._atlas_texcoords.append((m, texcoords))
        m.userfacetexcoord = corner_texcoord.tolist()
        m.inertia = mujoco.mjtMeshInertia.mjMESH_INERTIA_SHELL
        body.add_geom(type=mujoco.mjtGeom.mjGEOM_MESH, meshname=m.name, material=material,
                      contype=0, conaffinity=0, group=group, density=0, name=name)

    def _tile_texcoords(self, mesh: ColouredMesh, texcoords: np.ndarray,
                        corner_texcoord: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The texture coordinates (texels) and each face corner's index into them, with the
        patterned faces' corners moved into their tiles (those of a full atlas stay flat)."""
        assert mesh.face_uv is not None
        tiles, faces, which = mesh.tile_keys
        origins = np.full((len(tiles), 2), np.nan)
        for i, (pattern, colour) in enumerate(tiles):
            slot = self.atlas.tile_slot(pattern, colour)
            if slot is not None:
                origins[i] = self.atlas.slot_origin(slot)
        keep = ~np.isnan(origins[which, 0])
        if not keep.all():
            faces, which = faces[keep], which[keep]
        if len(faces) == 0:
            return texcoords, corner_texcoord
        # The corners land on texel centres of the tile's outer texels: sampling never
        # reaches the next tile, with linear filtering either.
        corners = origins[which][:, None, :] + 0.5 + mesh.face_uv[faces] * (materials.TILE - 1)
        first = len(texcoords)
        corner_texcoord = corner_texcoord.copy()
        corner_texcoord[(faces[:, None] * 3 + np.arange(3)).reshape(-1)] = first + np.arange(3 * len(faces))
        return np.concatenate([texcoords, corners.reshape(-1, 2)]), corner_texcoord

    def _surface_geom(self, body, mesh: SurfaceMesh, slot: int, *, name: str) -> None:
        """A floor's or wall's patterned surface on texture ``slot``: its pattern's tile in
        its colour (styled like the atlas), repeating."""
        image = styled_palette(materials.tile(mesh.pattern, pattern_variant(mesh.rgb8), mesh.rgb8), self._style)
        tex = self._surface_textures[slot]
        tex.width, tex.height = image.shape[1], image.shape[0]
        tex.data = image.tobytes()
        m = self.spec.add_mesh(name=f"mesh_{self._mesh_count}")
        self._mesh_count += 1
        m.uservert = mesh.vertices.reshape(-1).tolist()
        m.userface = mesh.faces.reshape(-1).tolist()
        m.usernormal = mesh.normals.reshape(-1).tolist()
        m.userfacenormal = _each_thrice(len(mesh.faces))
        # Part.uv's convention (v up) for a texture whose rows MuJoCo samples top down.
        m.usertexcoord = np.column_stack([mesh.uv[:, 0], -mesh.uv[:, 1]]).reshape(-1).tolist()
        m.inertia = mujoco.mjtMeshInertia.mjMESH_INERTIA_SHELL
        body.add_geom(type=mujoco.mjtGeom.mjGEOM_MESH, meshname=m.name, material=f"{SURFACE_TEXTURE_PREFIX}{slot}",
                      contype=0, conaffinity=0, group=GROUP_HOUSE, density=0, name=name)

    def _plain_geom(self, body, part: Part, *, group: int, name: str) -> None:
        """Naive build: one geom per part with its own colour."""
        m = self.spec.add_mesh(name=f"mesh_{self._mesh_count}")
        self._mesh_count += 1
        m.uservert = part.vertices.reshape(-1).tolist()
        m.userface = part.faces.reshape(-1).tolist()
        m.inertia = mujoco.mjtMeshInertia.mjMESH_INERTIA_SHELL
        body.add_geom(type=mujoco.mjtGeom.mjGEOM_MESH, meshname=m.name, rgba=list(part.rgba),
                      contype=0, conaffinity=0, group=group, density=0, name=name)

    def _textured_geom(self, body, part: Part, *, group: int, name: str) -> None:
        """An imported part with its own base-colour texture."""
        if part.texture is None or part.uv is None:
            raise ValueError(f"{name}: a textured part needs a texture and uv coordinates")
        tname = f"tex_{self._texture_count}"
        self._texture_count += 1
        img = np.ascontiguousarray(part.texture[..., :3], dtype=np.uint8)
        tex = self.spec.add_texture(name=tname, type=mujoco.mjtTexture.mjTEXTURE_2D,
                                    width=img.shape[1], height=img.shape[0], nchannel=3)
        tex.data = img.tobytes()
        mat = self.spec.add_material(name=f"mat_{tname}", rgba=[*part.rgba[:3], 1.0])
        mat.textures[mujoco.mjtTextureRole.mjTEXROLE_RGB] = tname
        m = self.spec.add_mesh(name=f"mesh_{self._mesh_count}")
        self._mesh_count += 1
        m.uservert = part.vertices.reshape(-1).tolist()
        m.userface = part.faces.reshape(-1).tolist()
        # Part.uv has v pointing up; MuJoCo samples v = 0 at the image's first (top) row.
        uv = part.uv.copy()
        uv[:, 1] = 1.0 - uv[:, 1]
        m.usertexcoord = uv.reshape(-1).tolist()
        m.inertia = mujoco.mjtMeshInertia.mjMESH_INERTIA_SHELL
        body.add_geom(type=mujoco.mjtGeom.mjGEOM_MESH, meshname=m.name, material=mat.name,
                      contype=0, conaffinity=0, group=group, density=0, name=name)

    def _link_geoms(self, body, link: Link, *, group: int, name: str, movable: bool,
                    friction=(1.0, 0.005, 0.0001), cache: bool = True, drawn: bool = True,
                    with_meshes: list[tuple[ColouredMesh, np.ndarray]] | None = None) -> None:
        """Visual and collision geoms of one link; ``with_meshes``: more meshes (in the body's
        frame) drawn in its mesh geom; ``drawn=False``: collision geoms only."""
        geometry = link_geometry(link, movable, cache=cache)
        if self.options.naive:
            for i, part in enumerate(link.parts):
                self._plain_geom(body, part, group=group, name=f"{name}_{i}")
        elif drawn:
            for i, part in enumerate(geometry.textured):
                self._textured_geom(body, part, group=group, name=f"{name}_tex{i}")
            mesh = geometry.mesh
            if with_meshes:
                own: list[tuple[ColouredMesh, np.ndarray | None]] = [(mesh, None)] if mesh is not None else []
                mesh = placed_together(own + list(with_meshes))
            if mesh is not None:
                self._mesh_geom(body, mesh, group=group, name=name)
        self._collision_geoms(body, geometry.collision, name=name, friction=friction)

    def _collision_geoms(self, body, shapes, *, name: str, friction) -> None:
        for i, shape in enumerate(shapes):
            if shape.kind == "box":
                body.add_geom(type=mujoco.mjtGeom.mjGEOM_BOX, size=shape.half_size.tolist(),
                              pos=shape.centre.tolist(), group=GROUP_COLLISION, friction=list(friction),
                              name=f"{name}_c{i}")
            else:
                m = self.spec.add_mesh(name=f"hull_{self._mesh_count}")
                self._mesh_count += 1
                m.uservert = shape.vertices.reshape(-1).tolist()
                m.maxhullvert = self.options.max_hull_vertices
                body.add_geom(type=mujoco.mjtGeom.mjGEOM_MESH, meshname=m.name, group=GROUP_COLLISION,
                              friction=list(friction), name=f"{name}_c{i}")

    # -- house shell ------------------------------------------------------------------------
    def _add_shell(self) -> None:
        scene, wb = self.scene, self.spec.worldbody
        floors, ceilings, walls = (MeshAccumulator() for _ in range(3))
        # Patterned floors and walls (none in the naive reference build).
        surfaces = SurfaceAccumulator(0 if self.options.naive else SURFACE_TEXTURE_SLOTS)

        def patterned(kind: str, surface: Surface) -> str | None:
            pattern = _surface_pattern(surface)
            return pattern if pattern is not None and surfaces.takes(kind, pattern, surface.rgba) else None

        room_wall = {r.id: r.wall for r in scene.rooms}
        default_wall = scene.rooms[0].wall
        max_height = max((w.height for w in scene.walls), default=3.0)
        for room in scene.rooms:
            v, f = polygon_surface(room.polygon, 0.0)
            pattern = patterned("floors", room.floor)
            if pattern is None:
                floors.add(v, f, room.floor.rgba)
            else:
                surfaces.add("floors", pattern, room.floor.rgba, v, f, v[:, :2] / materials.SURFACE_PERIOD)
            v, f = polygon_surface(room.polygon, max_height, facing_up=False)
            ceilings.add(v, f, (0.95, 0.95, 0.93, 1.0))
        for wall in scene.walls:
            openings = [(d.offset, d.width, 0.0, d.height) for d in scene.doors if d.wall == wall.id]
            openings += [(w.offset, w.width, w.sill, w.sill + w.height) for w in scene.windows if w.wall == wall.id]
            left, right = self._wall_side_surfaces(wall, room_wall, default_wall)
            sides = [(faces, patterned("walls", surface), surface)
                     for faces, surface in ((_LEFT_FACES, left), (_RIGHT_FACES, right))]
            start, along, _, _ = wall_frame(wall)
            for piece in wall_pieces(wall.length, wall.height, openings):
                v, f, colours = wall_piece_box(wall.start, wall.end, wall.thickness, piece, left.rgba, right.rgba)
                flat = np.ones(len(f), dtype=bool)
                for faces, pattern, surface in sides:
                    if pattern is not None:
                        flat[faces] = False
                        uv = np.column_stack([(v[:, :2] - start) @ along, v[:, 2]]) / materials.SURFACE_PERIOD
                        surfaces.add("walls", pattern, surface.rgba, v, f[faces], uv)
                walls.add(v, f[flat], colours[flat])
                self._wall_collision(wall, piece)
            for door in scene.doors:
                if door.wall == wall.id and door_leads_outside(wall, door):
                    self._doorway_barrier(wall, door)
        if self.options.naive:
            # The reference build: a plane floor (drawn as a grid of many quads) and plain geoms.
            (lo_x, lo_y), (hi_x, hi_y) = scene.bounds()
            wb.add_geom(type=mujoco.mjtGeom.mjGEOM_PLANE, size=[(hi_x - lo_x) / 2 + 1, (hi_y - lo_y) / 2 + 1, 0.1],
                        pos=[(lo_x + hi_x) / 2, (lo_y + hi_y) / 2, 0], rgba=list(scene.rooms[0].floor.rgba),
                        contype=0, conaffinity=0, name="floor_plane")
            for acc, name in ((walls, "walls"), (ceilings, "ceilings")):
                if not acc.empty():
                    mesh = acc.build()
                    self._plain_geom(wb, Part(mesh.vertices, mesh.faces, (0.9, 0.88, 0.84, 1.0)),
                                     group=GROUP_HOUSE, name=name)
        else:
            if not floors.empty():
                self._mesh_geom(wb, floors.build(), group=GROUP_HOUSE, name="floors")
            for slot, surface_mesh in enumerate(surfaces.meshes()):
                self._surface_geom(wb, surface_mesh, slot, name=f"{surface_mesh.kind}_{slot}")
            if not walls.empty():
                self._mesh_geom(wb, walls.build(), group=GROUP_HOUSE, name="walls")
            if self.options.with_ceiling:
                self._mesh_geom(wb, ceilings.build(), group=GROUP_CEILING, name="ceilings")
        # Collision floor: one box under the whole house (invisible).
        (lo_x, lo_y), (hi_x, hi_y) = scene.bounds()
        wb.add_geom(type=mujoco.mjtGeom.mjGEOM_BOX, name="floor_collision", group=GROUP_COLLISION,
                    size=[(hi_x - lo_x) / 2 + 1.0, (hi_y - lo_y) / 2 + 1.0, FLOOR_THICKNESS / 2],
                    pos=[(lo_x + hi_x) / 2, (lo_y + hi_y) / 2, -FLOOR_THICKNESS / 2])

    def _wall_side_surfaces(self, wall, room_wall: Mapping[str, Surface], default: Surface) -> tuple[Surface, Surface]:
        """Which room lies left and right of the wall's direction, and their walls' surfaces."""
        rooms = [r for r in wall.rooms if r in room_wall]
        if not rooms:
            return default, default
        if len(rooms) == 1:
            return room_wall[rooms[0]], room_wall[rooms[0]]
        # Probe a point just left of the wall's middle and see which room polygon holds it.
        (x0, y0), (x1, y1) = wall.start, wall.end
        _, _, left, _ = wall_frame(wall)
        probe = np.array([[(x0 + x1) / 2 + left[0] * 0.2, (y0 + y1) / 2 + left[1] * 0.2]])
        left_of_wall = points_in_polygon(probe, np.asarray(self.scene.room(rooms[0]).polygon))[0]
        left_room = rooms[0] if left_of_wall else rooms[1]
        right_room = rooms[1] if left_room == rooms[0] else rooms[0]
        return room_wall[left_room], room_wall[right_room]

    def _wall_collision(self, wall, piece) -> None:
        start, u, _, _ = wall_frame(wall)
        centre = start + u * ((piece.a + piece.b) / 2)
        self.spec.worldbody.add_geom(
            type=mujoco.mjtGeom.mjGEOM_BOX, group=GROUP_COLLISION,
            size=[(piece.b - piece.a) / 2, wall.thickness / 2, (piece.z1 - piece.z0) / 2],
            pos=[*centre.tolist(), (piece.z0 + piece.z1) / 2],
            quat=yaw_quat(heading_deg(u)).tolist(),
        )

    def _doorway_barrier(self, wall, door) -> None:
        """An invisible slab across a door to the outside, seen by the avatars' collision
        only (no contacts, no rendering): the house has no floor beyond it, so walking out
        would leave the agent where nothing can be done (the door itself still opens)."""
        start, u, _, _ = wall_frame(wall)
        centre = start + u * door.offset
        self.spec.worldbody.add_geom(
            type=mujoco.mjtGeom.mjGEOM_BOX, group=GROUP_COLLISION, contype=0, conaffinity=0,
            name=f"doorway_barrier_{door.id}",
            size=[door.width / 2, wall.thickness / 2, door.height / 2],
            pos=[*centre.tolist(), door.height / 2],
            quat=yaw_quat(heading_deg(u)).tolist(),
        )

    # -- doors -----------------------------------------------------------------------------
    def _add_door_leaf(self, door) -> None:
        wall = self.scene.wall(door.wall)
        _, u, _, _ = wall_frame(wall)
        hinge = door_hinge_point(wall, door)
        wall_angle = heading_deg(u)
        # Leaf frame: x along the closed leaf from the hinge toward the opening's other end.
        leaf_yaw = wall_angle if door.hinge == "start" else wall_angle + 180
        body = self.spec.worldbody.add_body(name=f"door_{door.id}", pos=[*hinge.tolist(), 0.0],
                                            quat=yaw_quat(leaf_yaw).tolist())
        # Swinging to the left of the wall direction is +yaw for a start hinge, and mirrored.
        to_left = (door.swing == "left") == (door.hinge == "start")
        limit = math.pi / 2
        joint = body.add_joint(type=mujoco.mjtJoint.mjJNT_HINGE, axis=[0, 0, 1], name=f"door_{door.id}_hinge",
                               range=[0, limit] if to_left else [-limit, 0], damping=5.0)
        joint.ref = 0.0
        leaf_w = door.width - 0.02
        self._link_geoms(body, _door_leaf_link(leaf_w, door.height), group=GROUP_HOUSE,
                         name=f"door_{door.id}", movable=True)
        body.mass = 20.0
        body.ipos = [leaf_w / 2, 0.0, door.height / 2]  # the leaf's centre: what "the door" is
        body.inertia = [2.0, 2.0, 2.0]
        body.explicitinertial = True
        self.door_initial[door.id] = door.openness * (limit if to_left else -limit)

    # -- objects -------------------------------------------------------------------------
    def _asset_for(self, obj) -> AssetModel:
        imported = self._imported
        if obj.asset in imported:
            model = load_imported_asset(imported[obj.asset], scene_base_dir(self.scene))
        else:
            model = registry.make(obj.asset, obj.variant)
        return model.scaled(obj.scale)

    def _riders(self, assets: list[AssetModel]) -> dict[int, list[tuple[ObjectInstance, AssetModel]]]:
        """Set dressing drawn with the piece it rests on (:attr:`AssetModel.drawn_with_support`),
        by that piece's id: a static object of one plain link on a static piece that is not
        set dressing itself, drawn in that piece's base link. A shelf of books is then one
        draw, not one per book (and one mesh to build)."""
        if self.options.naive:
            return {}
        objects = {obj.id: (obj, asset) for obj, asset in zip(self.scene.objects, assets)}
        out: dict[int, list[tuple[ObjectInstance, AssetModel]]] = {}
        for obj, asset in objects.values():
            support = objects.get(obj.on) if obj.on is not None and asset.drawn_with_support else None
            if support is None or obj.kind != "static" or support[0].kind != "static" or support[1].drawn_with_support:
                continue
            link = asset.links[0]
            if (len(asset.links) == 1 and link.joint is None and not any(link.pos)
                    and all(p.texture is None for p in link.parts)):
                out.setdefault(support[0].id, []).append((obj, asset))
        return out

    def _rider_meshes(self, support: ObjectInstance,
                      riders: Sequence[tuple[ObjectInstance, AssetModel]]) -> list[tuple[ColouredMesh, np.ndarray]]:
        """Each rider's visual mesh with its transform into the support's body frame."""
        to_support = np.eye(4)
        to_support[:3, :3] = euler_deg_matrix(support.rotation).T
        to_support[:3, 3] = -to_support[:3, :3] @ np.asarray(support.position, dtype=np.float64)
        out = []
        for rider, asset in riders:
            mesh = link_geometry(asset.links[0], False).mesh
            if mesh is None:
                continue
            placed = np.eye(4)
            placed[:3, :3] = euler_deg_matrix(rider.rotation)
            placed[:3, 3] = rider.position
            out.append((mesh, to_support @ placed))
        return out

    def _add_object(self, obj: ObjectInstance, asset: AssetModel,
                    riders: Sequence[tuple[ObjectInstance, AssetModel]] = (), *, drawn: bool = True) -> None:
        """One scene object: its body, joints and geoms. ``riders``: the set dressing drawn
        with it (see :meth:`_riders`); ``drawn=False``: a rider, which gets no visual geom."""
        self.assets[obj.id] = asset
        interactable = obj.kind == "interactable"
        body = self.spec.worldbody.add_body(name=f"obj_{obj.id}", pos=list(obj.position),
                                            quat=euler_deg_quat(obj.rotation).tolist())
        group = GROUP_OBJECTS if interactable else GROUP_HOUSE
        if interactable:
            body.add_freejoint(name=f"obj_{obj.id}_free")
            lo, hi = asset.bounds()
            size = hi - lo
            mass = max(asset.mass, 0.01)
            body.mass = mass
            body.ipos = ((lo + hi) / 2).tolist()
            body.inertia = (mass / 12 * np.array([size[1] ** 2 + size[2] ** 2, size[0] ** 2 + size[2] ** 2,
                                                  size[0] ** 2 + size[1] ** 2])).clip(1e-6).tolist()
            body.explicitinertial = True
        for link in asset.links:
            target = body
            if link.joint is not None:
                target = body.add_body(name=f"obj_{obj.id}_{link.name}", pos=list(link.pos))
                j = link.joint
                jtype = mujoco.mjtJoint.mjJNT_HINGE if j.kind == "hinge" else mujoco.mjtJoint.mjJNT_SLIDE
                target.add_joint(type=jtype, axis=list(j.axis), range=list(j.range), damping=j.damping,
                                 name=f"obj_{obj.id}_{link.name}_joint")
                target.mass = 2.0
                target.ipos = [0.0, 0.0, 0.0]
                target.inertia = [0.05, 0.05, 0.05]
                target.explicitinertial = True
            elif any(abs(c) > 0 for c in link.pos):
                target = body.add_body(name=f"obj_{obj.id}_{link.name}", pos=list(link.pos))
            friction = (1.2, 0.01, 0.001) if interactable else (1.0, 0.005, 0.0001)
            with_meshes = self._rider_meshes(obj, riders) if riders and link.name == "base" and target is body else []
            self._link_geoms(target, link, group=group, name=f"obj_{obj.id}_{link.name}",
                             movable=interactable or link.joint is not None, friction=friction,
                             drawn=drawn, with_meshes=with_meshes)

    # -- avatars and lights ------------------------------------------------------------
    def _add_avatar(self, name: str, opts: BodyOptions, group: int) -> None:
        wb = self.spec.worldbody
        body = wb.add_body(name=name, mocap=True)
        add_humanoid(body, name, opts.height, appearance_for(name, self.scene.seed), body_group=group,
                     hand_group=GROUP_HANDS, add_visual=self._person_part, separate_hands=name == "agent",
                     articulated=name == "agent" or self.options.user_articulated)
        head = wb.add_body(name=f"{name}_head", mocap=True, pos=[0, 0, opts.camera_height])
        cam = head.add_camera(name=f"{name}_camera", fovy=opts.fovy)
        cam.pos = [0, 0, 0]

    def _person_part(self, body, link: Link, group: int, name: str) -> None:
        """A person's part: its link merged into one mesh geom (the parts collide with nothing)."""
        self._link_geoms(body, link, group=group, name=name, movable=True)

    def _add_outside(self) -> None:
        """Ground and sky (:mod:`legent_gym.world.outside`) on a body added after every
        other, so no id moves; in the ceilings' group, which no view ray meets; colliding
        with nothing and with no object id. The sky's material glows (it looks unlit), the
        ground's a little (a meadow in daylight; shadows still fall on it)."""
        lo, hi = self.scene.bounds()
        ground, sky = outside.ground_mesh(lo, hi), outside.sky_mesh(lo, hi)
        # A static body of their own, the last: its geoms come after every other geom.
        wb = self.spec.worldbody.add_body(name=outside.BODY)
        if self.options.naive:
            for mesh, name in ((ground, "ground"), (sky, "sky")):
                rgba = (*(mesh.face_rgb[0] / 255.0), 1.0)
                self._plain_geom(wb, Part(mesh.vertices, mesh.faces, rgba), group=GROUP_CEILING, name=name)
            return
        for name, emission in (("sky", 1.0), ("ground", outside.GROUND_GLOW)):
            material = self.spec.add_material(name=name, emission=emission, specular=0.0, shininess=0.0)
            material.textures[mujoco.mjtTextureRole.mjTEXROLE_RGB] = PALETTE_TEXTURE
        self._mesh_geom(wb, ground, group=GROUP_CEILING, name="ground", material="ground")
        self._mesh_geom(wb, sky, group=GROUP_CEILING, name="sky", material="sky")

    def _add_lights(self) -> None:
        wb = self.spec.worldbody
        lights = self.scene.lights
        if not lights:
            (lo_x, lo_y), (hi_x, hi_y) = self.scene.bounds()
            wb.add_light(pos=[(lo_x + hi_x) / 2, (lo_y + hi_y) / 2, 6.0], dir=[0.2, 0.3, -1.0],
                         diffuse=[0.6 * self._style.light_scale] * 3, castshadow=False, name="sun")
            return
        # OpenGL's fixed pipeline draws at most 8 lights: the first 8, or with an outside the
        # first 7 and the daylight.
        daylight = self.options.with_outside and not self.options.naive
        scale = self._style.light_scale
        for i, light in enumerate(lights[:7 if daylight else 8]):
            wb.add_light(pos=list(light.position), dir=list(light.direction),
                         diffuse=[min(c * scale, 1.0) for c in light.diffuse],
                         type=mujoco.mjtLightType.mjLIGHT_DIRECTIONAL if light.directional else mujoco.mjtLightType.mjLIGHT_SPOT,
                         castshadow=light.cast_shadow, cutoff=80.0, exponent=1.0, attenuation=[1.0, 0.05, 0.0],
                         name=f"light_{i}")
        if daylight:
            self._add_daylight()
        if self.options.with_ceiling and not self.options.naive:
            self._add_light_fixtures(lights[:7 if daylight else 8])

    def _add_light_fixtures(self, lights) -> None:
        """A glowing round ceiling lamp above each light hung under the ceiling (within
        :data:`FIXTURE_DROP` of it, inside a room), all in one mesh in the ceilings' group
        (every head camera shows it; no view ray meets it; top-down views leave it out). The
        lamp is above its light, so it never shades what the light lights."""
        ceiling = max((w.height for w in self.scene.walls), default=3.0)
        polygons = [np.asarray(r.polygon, dtype=np.float64) for r in self.scene.rooms]
        parts = []
        for light in lights:
            x, y, z = light.position
            if light.directional or not 0.0 < ceiling - z <= FIXTURE_DROP:
                continue
            if not any(points_in_polygon(np.array([[x, y]]), p)[0] for p in polygons):
                continue
            parts.append(cylinder_part((x, y, ceiling - 0.015), 0.08, 0.03, FIXTURE_CANOPY_RGBA, segments=12))
            parts.append(cylinder_part((x, y, ceiling - 0.07), 0.2, 0.07, FIXTURE_GLOW_RGBA, segments=16,
                                       radius_top=0.17))
        if not parts:
            return
        acc = MeshAccumulator()
        for part in parts:
            acc.add_part(part)
        material = self.spec.add_material(name="light_fixtures", emission=0.8, specular=0.0, shininess=0.0)
        material.textures[mujoco.mjtTextureRole.mjTEXROLE_RGB] = PALETTE_TEXTURE
        self._mesh_geom(self.spec.worldbody, acc.build(), group=GROUP_CEILING, name="light_fixtures",
                        material="light_fixtures")

    def _add_daylight(self) -> None:
        """A directional light from the sky, slanting in through the windows (its shadows
        drawn in the "pretty" profile), as strong as the style's lights and ambient allow:
        none in "flat", dim at "night"."""
        (lo_x, lo_y), (hi_x, hi_y) = self.scene.bounds()
        top = max((w.height for w in self.scene.walls), default=3.0) + 3.0
        strength = outside.DAYLIGHT * min(self._style.light_scale, self._style.headlight_ambient)
        self.spec.worldbody.add_light(
            pos=[(lo_x + hi_x) / 2, (lo_y + hi_y) / 2, top], dir=list(outside.DAYLIGHT_DIRECTION),
            diffuse=[strength * c for c in outside.DAYLIGHT_RGB], type=mujoco.mjtLightType.mjLIGHT_DIRECTIONAL,
            castshadow=True, name="daylight")

    def _finish_palette(self) -> None:
        if self.options.naive:
            return
        width, height = self.atlas.size()
        tex = self._palette_texture
        tex.width, tex.height = width, height
        tex.data = styled_palette(self.atlas.image(), self._style).tobytes()
        scale = np.array([width, height], dtype=np.float64)
        for mesh, texcoords in self._atlas_texcoords:
            mesh.usertexcoord = (texcoords / scale).reshape(-1).tolist()


#: How far below the ceiling a light may hang and still get a lamp drawn above it (metres).
FIXTURE_DROP = 0.5
FIXTURE_CANOPY_RGBA = (0.85, 0.85, 0.82, 1.0)
FIXTURE_GLOW_RGBA = (1.0, 0.96, 0.86, 1.0)
#: Faces of :func:`wall_piece_box`'s box on each side of the wall (+y is its left).
_LEFT_FACES, _RIGHT_FACES = np.array([6, 7]), np.array([4, 5])


def _surface_pattern(surface: Surface) -> str | None:
    """The repeating pattern a floor or wall surface is drawn with, or None (flat)."""
    pattern = materials.surface_pattern(surface.material)
    return pattern if pattern in SURFACE_TEXTURE_PATTERNS else None


#: [0, 0, 0, 1, 1, 1, ...] for the most faces asked for yet (see :func:`_each_thrice`).
_THRICE: list[int] = []


def _each_thrice(n: int) -> list[int]:
    """[0, 0, 0, 1, 1, 1, ..., n-1]: a flat-shaded mesh's per-corner normal indices, a slice
    of one list kept for the largest mesh yet (its int objects shared). A list per face
    count, cached, held a new one for almost every merged mesh of every house."""
    global _THRICE
    if len(_THRICE) < 3 * n:
        _THRICE = np.repeat(np.arange(max(n, 2 * len(_THRICE) // 3)), 3).tolist()
    return _THRICE[:3 * n]


# Avatars and door leaves are the same few shapes in every house: one Link object per shape,
# so their merged geometry is cached like an asset's (link_geometry caches per Link).


@lru_cache(maxsize=256)
def _door_leaf_link(leaf_w: float, height: float) -> Link:
    panel = box_part((leaf_w / 2 + 0.01, 0, height / 2), (leaf_w, DOOR_LEAF_THICKNESS, height - 0.01),
                     (0.55, 0.4, 0.28, 1.0), collision="box", material="wood")
    handle_y = DOOR_LEAF_THICKNESS / 2 + 0.03
    handles = [box_part((leaf_w - 0.08, s * handle_y, 1.0), (0.12, 0.02, 0.03), (0.75, 0.75, 0.7, 1),
                        collision="none", material="metal") for s in (-1, 1)]
    return Link("leaf", [panel, *handles])


# ---------------------------------------------------------------------------------------


def build_spec(scene: Scene, options: BuildOptions | None = None) -> tuple[mujoco.MjSpec, _SpecBuilder]:
    builder = _SpecBuilder(scene, options or BuildOptions())
    builder.build()
    return builder.spec, builder


def _ids(model: mujoco.MjModel, kind: mujoco.mjtObj):
    """A function from a name to the id of the model's element of ``kind`` (:func:`element_id`)."""
    return lambda name: element_id(model, kind, name)


def build_world(scene: Scene, options: BuildOptions | None = None) -> World:
    """Build a scene into a MuJoCo model and data, with its maps back to scene ids."""
    options = options or BuildOptions()
    spec, b = build_spec(scene, options)
    try:
        model = spec.compile()
    except ValueError as err:  # MuJoCo reports compile errors as ValueError
        raise SceneBuildError(f"MuJoCo could not compile scene {scene.name!r}: {err}") from None
    data = mujoco.MjData(model)
    if options.with_outside:
        outside.house_statistics(model, data)

    geom_object = np.full(model.ngeom, -1, dtype=np.int32)
    geom_door: dict[int, str] = {}
    # Every geom's name, read off the model's name buffer at once (model.geom(i) makes an
    # accessor object per geom, which costs more than the rest of this loop).
    raw = model.names
    geom_names = [raw[a:raw.index(b"\0", a)].decode() for a in model.name_geomadr.tolist()]
    for gid, name in enumerate(geom_names):
        if name.startswith("obj_"):
            geom_object[gid] = int(name.split("_", 2)[1])
        elif name.startswith("door_"):
            for door in scene.doors:
                if name.startswith(f"door_{door.id}_") or name == f"door_{door.id}":
                    geom_door[gid] = door.id
    body_id = _ids(model, mujoco.mjtObj.mjOBJ_BODY)
    joint_id = _ids(model, mujoco.mjtObj.mjOBJ_JOINT)
    object_body = {o.id: body_id(f"obj_{o.id}") for o in scene.objects}
    object_joints: dict[int, dict[str, int]] = {}
    for obj in scene.objects:
        for link in b.assets[obj.id].links:
            if link.joint is not None:
                jid = joint_id(f"obj_{obj.id}_{link.name}_joint")
                object_joints.setdefault(obj.id, {})[link.name] = jid
                if link.name in obj.joints:
                    data.qpos[model.jnt_qposadr[jid]] = obj.joints[link.name]
    door_joint, door_body = {}, {}
    for door in scene.doors:
        if door.leaf:
            jid = joint_id(f"door_{door.id}_hinge")
            door_joint[door.id] = jid
            door_body[door.id] = body_id(f"door_{door.id}")
            data.qpos[model.jnt_qposadr[jid]] = b.door_initial[door.id]
    free = [o.id for o in scene.objects if o.kind == "interactable"]
    geom_segment = geom_object.copy()
    for who, segment_id in PERSON_SEGMENTATION_ID.items():
        root = body_id(who)
        geom_segment[model.body_rootid[model.geom_bodyid] == root] = segment_id
    world = World(scene, model, data, b.assets, object_body, object_joints, door_joint, door_body,
                  geom_object, geom_door, b.atlas, options, free, geom_segment)
    world.set_body_pose("agent", *scene.agent.position, scene.agent.yaw)
    user = scene.user or scene.agent
    world.set_body_pose("user", *user.position, user.yaw)
    if scene.user is None:  # no user: park the avatar far below the floor, out of every view
        world.data.mocap_pos[model.body("user").mocapid[0]] = (0, 0, -100)
    mujoco.mj_forward(model, data)
    return world

"""What an asset is once made: low-poly coloured meshes grouped into links, plus annotations.

An :class:`AssetModel` is engine-agnostic geometry. The builder turns each link into a
MuJoCo body (the ``base`` link, plus one body per door or drawer with its joint), each
link's visual parts into one mesh geom (coloured through a shared palette texture, so one
geom per link keeps the draw count low and the object's identity for segmentation), and
each part's collision shape into a collision geom.

Asset frame: z up, origin at the centre of the footprint on the floor, the front (where a
person stands to use it) facing +y. Units: metres.
"""

from __future__ import annotations

from collections.abc import Hashable
from dataclasses import dataclass, field
from functools import lru_cache
from typing import Literal

import numpy as np

#: Where generators put an asset: against a wall, in a corner, in the middle of a room, on a
#: surface, hanging on a wall above the floor (a picture: it blocks no floor), or flat on the
#: floor as a covering people walk over (a rug: a scene object of kind ``covering``).
Placement = Literal["wall", "corner", "middle", "surface", "hanging", "floor"]
#: A part's collision shape (see :attr:`Part.collision`).
Collision = Literal["box", "hull", "none"]


@dataclass
class Part:
    """One rigid piece of geometry with one colour (or one texture), in its link's frame."""

    vertices: np.ndarray  # (N, 3) float64
    faces: np.ndarray  # (M, 3) int32
    rgba: tuple[float, float, float, float] = (0.7, 0.7, 0.7, 1.0)
    #: "box": collide with the part's axis-aligned bounding box (exact for box parts);
    #: "hull": its convex hull; "none": visual only.
    collision: Collision = "hull"
    uv: np.ndarray | None = None  # (N, 2) texture coordinates, v pointing up
    texture: np.ndarray | None = None  # (H, W, 3) uint8 image, for imported assets
    material: str = "plain"  # style hint: wood, fabric, metal, plastic, ceramic, glass, ...

    def __post_init__(self) -> None:
        self.vertices = np.asarray(self.vertices, dtype=np.float64).reshape(-1, 3)
        self.faces = np.asarray(self.faces, dtype=np.int32).reshape(-1, 3)
        if self.uv is not None:
            self.uv = np.asarray(self.uv, dtype=np.float64).reshape(-1, 2)

    @classmethod
    def exact(cls, vertices: np.ndarray, faces: np.ndarray, rgba: tuple[float, float, float, float],
              collision: Collision, uv: np.ndarray | None = None, texture: np.ndarray | None = None,
              material: str = "plain") -> Part:
        """``Part(...)`` of arrays already in its types and shapes (float64 (N, 3), int32
        (M, 3), float64 (N, 2) or None), taken as they are: the asset factories make
        thousands of parts while houses are generated, and the conversions cost more than
        the rest of a small part."""
        part = cls.__new__(cls)
        part.__dict__.update(vertices=vertices, faces=faces, rgba=rgba, collision=collision, uv=uv,
                             texture=texture, material=material)
        return part

    def bounds(self) -> np.ndarray:
        return np.stack([self.vertices.min(axis=0), self.vertices.max(axis=0)])

    def transformed(self, matrix: np.ndarray) -> Part:
        """A copy with vertices mapped by a 4x4 homogeneous transform."""
        v = self.vertices @ matrix[:3, :3].T + matrix[:3, 3]
        faces = self.faces if _det3(matrix[:3, :3].tolist()) > 0 else self.faces[:, ::-1]
        return Part.exact(v, faces.copy(), self.rgba, self.collision, self.uv, self.texture, self.material)


def _bounds(model: AssetModel) -> np.ndarray:
    pts = [p.vertices + np.asarray(link.pos) for link in model.links for p in link.parts]
    allv = np.concatenate(pts)
    return np.stack([allv.min(axis=0), allv.max(axis=0)])


def _det3(m: list[list[float]]) -> float:
    """Determinant of a 3x3 matrix given as nested lists (np.linalg.det costs ~10x more
    for one small matrix, and asset factories transform thousands of parts)."""
    return (m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]))


@dataclass
class Joint:
    """The joint that moves a link relative to the base: a door hinge or a drawer slide."""

    kind: Literal["hinge", "slide"]
    axis: tuple[float, float, float]
    range: tuple[float, float]  # radians (hinge) or metres (slide); closed is 0
    damping: float = 2.0


@dataclass
class Link:
    name: str  # "base", "door_0", "drawer_1", ...
    parts: list[Part]
    #: Origin of the link frame in the asset frame (the hinge axis point for a door).
    pos: tuple[float, float, float] = (0.0, 0.0, 0.0)
    joint: Joint | None = None


@dataclass
class Receptacle:
    """A flat rectangle where things can be put, in the frame of ``link``.

    ``center`` is (x, y) of the rectangle, ``half_size`` its half extents, ``height`` the
    z of the surface. Inside a drawer or cabinet, ``clearance`` is the free height above.
    """

    name: str
    center: tuple[float, float]
    half_size: tuple[float, float]
    height: float
    link: str = "base"
    clearance: float = 1.0

    @property
    def area(self) -> float:
        return 4.0 * self.half_size[0] * self.half_size[1]


@dataclass
class AssetModel:
    asset_id: str
    category: str
    links: list[Link]
    names: list[str] = field(default_factory=list)  # what people call it, first is canonical
    receptacles: list[Receptacle] = field(default_factory=list)
    pickupable: bool = False
    mass: float = 10.0
    rooms: list[str] = field(default_factory=list)  # room types it belongs in ([] = any)
    placement: Placement = "wall"
    #: Extra free space needed in front of the asset (to use it: sit, open a door).
    front_clearance: float = 0.5
    #: Set dressing (books on a shelf, cushions on a sofa): a static object of this asset
    #: resting on a static piece is drawn as part of that piece's mesh, one draw for both;
    #: images, segmentation and view rays show it as that piece, and it keeps its own body
    #: and collision shapes (:mod:`legent_gym.world.builder`).
    drawn_with_support: bool = False

    def __post_init__(self) -> None:
        if not self.names:
            self.names = [self.category.replace("_", " ")]

    @property
    def base(self) -> Link:
        return self.link("base")

    def link(self, name: str) -> Link:
        for link in self.links:
            if link.name == name:
                return link
        raise KeyError(f"asset {self.asset_id!r} has no link {name!r}")

    def bounds(self) -> np.ndarray:
        """[[xmin, ymin, zmin], [xmax, ymax, zmax]] of all parts at the joints' zero."""
        return self.derived("bounds", _bounds).copy()  # a copy goes out

    def footprint(self) -> np.ndarray:
        """``(x0, y0, x1, y1)``: the bounds' box on the floor, in the asset frame (a copy)."""
        return self.derived("footprint", lambda m: m.derived("bounds", _bounds)[:, :2].reshape(-1)).copy()

    def footprint_radius(self) -> float:
        """Half the diagonal of the footprint: a circle round the asset however it is turned."""
        return float(self.derived("footprint radius", lambda m: float(np.hypot(*np.ptp(
            m.derived("bounds", _bounds)[:, :2], axis=0))) / 2))

    def derived(self, name: Hashable, compute):
        """``compute(self)``, kept with the model: generation and the agent ask for the same
        facts of a model (its bounds, footprint, turned footprints) many times. Models are
        immutable by convention; a replaced or extended link or part list still gives a
        fresh value (the cache is keyed by those lists). Callers must not change it."""
        key = tuple((id(link.parts), len(link.parts), link.pos) for link in self.links)
        store = self.__dict__.setdefault("_derived", {})
        hit = store.get(name)
        if hit is None or hit[0] != key:
            hit = store[name] = (key, compute(self))
        return hit[1]

    @property
    def size(self) -> np.ndarray:
        b = self.bounds()
        return b[1] - b[0]

    def triangle_count(self) -> int:
        return sum(len(p.faces) for link in self.links for p in link.parts)

    def scaled(self, scale: tuple[float, float, float]) -> AssetModel:
        """A copy with all geometry and annotations scaled (about the asset origin)."""
        s = np.asarray(scale, dtype=np.float64)
        # np.allclose(s, 1.0)'s test, without its overhead (every object of every house
        # passes through here).
        if all(abs(c - 1.0) <= 1e-08 + 1e-05 for c in s.tolist()):
            return self
        mat = np.diag([*s, 1.0])
        links = []
        for link in self.links:
            joint = link.joint
            if joint is not None and joint.kind == "slide":
                factor = float(np.abs(np.asarray(joint.axis) * s).sum())
                joint = Joint(joint.kind, joint.axis, (joint.range[0] * factor, joint.range[1] * factor), joint.damping)
            links.append(Link(link.name, [p.transformed(mat) for p in link.parts],
                              tuple(np.asarray(link.pos) * s), joint))
        recs = [Receptacle(r.name, (r.center[0] * s[0], r.center[1] * s[1]),
                           (r.half_size[0] * s[0], r.half_size[1] * s[1]), r.height * s[2], r.link,
                           r.clearance * s[2]) for r in self.receptacles]
        return AssetModel(self.asset_id, self.category, links, list(self.names), recs, self.pickupable,
                          self.mass * float(np.prod(s)), list(self.rooms), self.placement,
                          self.front_clearance, self.drawn_with_support)


# ---------------------------------------------------------------------------------------
# Low-poly primitive parts. Counts are kept small: triangles are what costs render time.


_BOX_CORNERS = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], dtype=np.float64)
_BOX_FACES = np.array([
    [0, 1, 3], [0, 3, 2],  # -x
    [4, 6, 7], [4, 7, 5],  # +x
    [0, 4, 5], [0, 5, 1],  # -y
    [2, 3, 7], [2, 7, 6],  # +y
    [0, 2, 6], [0, 6, 4],  # -z
    [1, 5, 7], [1, 7, 3],  # +z
], dtype=np.int32)


def box_part(center, size, rgba=(0.7, 0.7, 0.7, 1.0), *, collision="box", material="plain") -> Part:
    """An axis-aligned box, 12 triangles."""
    cx, cy, cz = center
    sx, sy, sz = size
    return Part.exact(box_vertices(float(cx), float(cy), float(cz), float(sx) / 2.0, float(sy) / 2.0,
                                   float(sz) / 2.0), _BOX_FACES.copy(), tuple(rgba), collision, material=material)


def box_between(lo, hi, rgba=(0.7, 0.7, 0.7, 1.0), *, collision="box", material="plain") -> Part:
    """The axis-aligned box spanning corners ``lo`` .. ``hi``: ``box_part((lo + hi) / 2,
    hi - lo, ...)``, in scalar arithmetic."""
    x0, y0, z0 = lo
    x1, y1, z1 = hi
    x0, y0, z0, x1, y1, z1 = float(x0), float(y0), float(z0), float(x1), float(y1), float(z1)
    vertices = box_vertices((x0 + x1) / 2, (y0 + y1) / 2, (z0 + z1) / 2,
                            (x1 - x0) / 2.0, (y1 - y0) / 2.0, (z1 - z0) / 2.0)
    return Part.exact(vertices, _BOX_FACES.copy(), tuple(rgba), collision, material=material)


#: Which of (x0, x1, y0, y1, z0, z1) each coordinate of the eight corners is.
_BOX_PICK = np.array([[0, 2, 4], [0, 2, 5], [0, 3, 4], [0, 3, 5], [1, 2, 4], [1, 2, 5], [1, 3, 4], [1, 3, 5]])


def box_vertices(cx: float, cy: float, cz: float, hx: float, hy: float, hz: float) -> np.ndarray:
    """The corners (in ``_BOX_CORNERS`` order) of the box centred at (cx, cy, cz) with half
    sizes (hx, hy, hz): ``c + _BOX_CORNERS * h`` in scalar arithmetic (``c + (-1 * h)`` is
    ``c - h`` to the bit), which costs a fraction of the array expression for one box."""
    return np.array([cx - hx, cx + hx, cy - hy, cy + hy, cz - hz, cz + hz]).take(_BOX_PICK)


@lru_cache(maxsize=64)
def _ring(segments: int) -> np.ndarray:
    """Unit circle points (segments, 2), the first on +x (read-only: shared)."""
    ang = np.linspace(0.0, 2 * np.pi, segments, endpoint=False)
    ring = np.stack([np.cos(ang), np.sin(ang)], axis=1)
    ring.flags.writeable = False
    return ring


@lru_cache(maxsize=64)
def _cylinder_faces(segments: int) -> np.ndarray:
    faces = []
    nb, nt = 2 * segments, 2 * segments + 1
    for i in range(segments):
        j = (i + 1) % segments
        faces += [[i, j, segments + j], [i, segments + j, segments + i], [nb, j, i], [nt, segments + i, segments + j]]
    out = np.array(faces, dtype=np.int32)
    out.flags.writeable = False
    return out


def cylinder_part(center, radius, height, rgba=(0.7, 0.7, 0.7, 1.0), *, segments=10,
                  collision="hull", material="plain", radius_top=None) -> Part:
    """A z-aligned cylinder (or a truncated cone with ``radius_top``) centred at ``center``."""
    c = np.asarray(center, dtype=np.float64)
    rt = radius if radius_top is None else radius_top
    ring = _ring(segments)
    bottom = np.column_stack([ring * radius, np.full(segments, -height / 2)])
    top = np.column_stack([ring * rt, np.full(segments, height / 2)])
    v = np.concatenate([bottom, top, [[0, 0, -height / 2], [0, 0, height / 2]]]) + c
    return Part.exact(v, _cylinder_faces(segments).copy(), tuple(rgba), collision, material=material)


def sphere_part(center, radius, rgba=(0.7, 0.7, 0.7, 1.0), *, scale=(1.0, 1.0, 1.0), subdivisions=1,
                collision="hull", material="plain") -> Part:
    """An icosphere (80 triangles at one subdivision), optionally stretched into an ellipsoid."""
    if subdivisions == 1:
        # trimesh's icosphere with one subdivision, without building a Trimesh each time:
        # the same arithmetic on its cached radius-independent arrays.
        base, unit, scalar, faces = _unit_icosphere()
        vertices = base + unit * (float(radius) - scalar).reshape((-1, 1))
    else:
        # trimesh takes seconds to import: only for icospheres it has not made before
        import trimesh

        mesh = trimesh.creation.icosphere(subdivisions=subdivisions, radius=radius)
        vertices, faces = np.asarray(mesh.vertices), mesh.faces
    v = vertices * np.asarray(scale) + np.asarray(center, dtype=np.float64)
    return Part(v, np.asarray(faces, dtype=np.int32), tuple(rgba), collision, material=material)


@lru_cache(maxsize=1)
def _unit_icosphere() -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """trimesh.creation.icosphere(1)'s inputs to its radius step: the subdivided
    icosahedron's vertices, their unit directions and lengths, and the faces."""
    # trimesh takes seconds to import: only for icospheres it has not made before
    import trimesh

    # icosphere() marks its icosahedron as not to be validated; Trimesh never validates
    # unless asked (validate=False by default), so the plain constructor is the same mesh.
    ico = trimesh.creation.icosahedron(validate=False)
    ico = ico.subdivide()
    base = np.array(ico.vertices, dtype=np.float64)
    scalar = np.sqrt(np.dot(base**2, [1, 1, 1]))
    unit = base / scalar.reshape((-1, 1))
    faces = np.array(ico.faces)
    for a in (base, unit, scalar, faces):
        a.flags.writeable = False
    return base, unit, scalar, faces


def mesh_part(vertices, faces, rgba=(0.7, 0.7, 0.7, 1.0), *, collision="hull", material="plain") -> Part:
    return Part(np.asarray(vertices), np.asarray(faces), tuple(rgba), collision, material=material)

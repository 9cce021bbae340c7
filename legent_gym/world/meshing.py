"""Mesh assembly for the builder: palette colouring, patterned faces, flat normals, and
the house shell.

Why a palette: every draw call costs render time on a CPU renderer, and a MuJoCo geom has
one colour. We merge all parts of a link (and all walls, all floors) into one mesh and give
each triangle its colour through texture coordinates into one small shared palette texture
(one texel per colour). One geom, many colours, one material.

Why an atlas: the faces of wooden, fabric, leather, metal, stone, ceramic and paper parts
show a seeded procedural pattern (:mod:`legent_gym.world.materials`) in their colour. Each
(pattern, colour) of a house is one tile of the same texture as the palette (the house's
:class:`Atlas`), and a patterned face's texture coordinates span its tile. The geoms stay
as few as before, with one material. Floors and papered or tiled walls repeat their
pattern every metre, which a tile cannot do: each (pattern, colour) of them is a geom of
its own on a small texture that repeats (:class:`SurfaceAccumulator`).
"""

from __future__ import annotations

import math
import weakref
from collections.abc import Sequence
from dataclasses import dataclass, field
from functools import cached_property, lru_cache

import mapbox_earcut
import numpy as np

from legent_gym.world import materials
from legent_gym.world.assets.model import Link, Part, box_part

PALETTE_SIZE = 64  # 64 x 64 texels: 4,096 distinct colours per scene
#: The object patterns in a fixed order: a face's pattern is an index into it.
OBJECT_PATTERN_NAMES: tuple[str, ...] = tuple(sorted(materials.OBJECT_PATTERNS))
_PATTERN_INDEX = {name: i for i, name in enumerate(OBJECT_PATTERN_NAMES)}
#: Parts whose largest side is shorter than this (metres) are drawn flat: handles, knobs and
#: small objects show too few pixels for a pattern, and each would take a tile.
PATTERN_MIN_SIZE = 0.12


class Palette:
    """Colours used in a scene, one texel each; colours are quantised to 8 bits."""

    def __init__(self, size: int = PALETTE_SIZE):
        self.size = size
        self._index: dict[tuple[int, int, int], int] = {}

    def index(self, rgba: Sequence[float]) -> int:
        r, g, b = (int(round(min(max(c, 0.0), 1.0) * 255)) for c in rgba[:3])
        return self.index_rgb8((r, g, b))

    def index_rgb8(self, key: tuple[int, int, int]) -> int:
        """The texel of an 8-bit colour (r, g, b), added if new."""
        idx = self._index.get(key)
        if idx is None:
            if len(self._index) >= self.size * self.size:
                # Full: reuse the nearest colour rather than fail on a very colourful scene.
                colours = np.array(list(self._index), dtype=np.int32)
                idx = int(np.argmin(((colours - np.array(key)) ** 2).sum(axis=1)))
                return idx
            idx = len(self._index)
            self._index[key] = idx
        return idx

    def image(self) -> np.ndarray:
        img = np.zeros((self.size * self.size, 3), dtype=np.uint8)
        for colour, idx in self._index.items():
            img[idx] = colour
        return img.reshape(self.size, self.size, 3)

    def __len__(self) -> int:
        return len(self._index)


class Atlas:
    """The one texture of a house's merged meshes: the :class:`Palette` in its top-left
    ``PALETTE_SIZE`` square, and after it one ``materials.TILE`` square per (pattern, colour)
    a patterned face asked for, :data:`WIDTH` texels a row, as many rows as needed (at most
    :data:`MAX_HEIGHT`; a face asking for a tile of a full atlas is drawn flat)."""

    WIDTH = 256
    MAX_HEIGHT = 1024

    def __init__(self) -> None:
        self.palette = Palette()
        self._slots: dict[tuple[str, tuple[int, int, int]], int] = {}
        #: Each tile's (pattern, 8-bit colour), in slot order.
        self.tiles: list[tuple[str, tuple[int, int, int]]] = []

    @staticmethod
    def slot_origin(slot: int) -> tuple[int, int]:
        """(x, y) texels of a tile slot's top-left corner: right of the palette in its rows,
        then whole rows below it."""
        t = materials.TILE
        beside = (Atlas.WIDTH - PALETTE_SIZE) // t  # slots in each tile row next to the palette
        rows_beside = PALETTE_SIZE // t
        if slot < beside * rows_beside:
            return PALETTE_SIZE + (slot % beside) * t, (slot // beside) * t
        slot -= beside * rows_beside
        per_row = Atlas.WIDTH // t
        return (slot % per_row) * t, PALETTE_SIZE + (slot // per_row) * t

    def tile_slot(self, pattern: str, rgb8: tuple[int, int, int]) -> int | None:
        """The slot of the (pattern, colour) tile, added if new; None when the atlas is full."""
        key = (pattern, rgb8)
        slot = self._slots.get(key)
        if slot is None:
            slot = len(self.tiles)
            if self.slot_origin(slot)[1] + materials.TILE > self.MAX_HEIGHT:
                return None
            self._slots[key] = slot
            self.tiles.append(key)
        return slot

    def size(self) -> tuple[int, int]:
        """(width, height) in texels."""
        bottom = max([PALETTE_SIZE] + [self.slot_origin(s)[1] + materials.TILE for s in range(len(self.tiles))])
        return self.WIDTH, bottom

    def palette_texel_origin(self, index: np.ndarray) -> np.ndarray:
        """(N, 2) texels (x, y) of palette colours' top-left corners."""
        return _texel_origins(self.palette.size)[index]

    def image(self) -> np.ndarray:
        """(height, width, 3) uint8: the palette's colours and every tile."""
        width, height = self.size()
        img = np.zeros((height, width, 3), dtype=np.uint8)
        img[:self.palette.size, :self.palette.size] = self.palette.image()
        t = materials.TILE
        for slot, (pattern, rgb8) in enumerate(self.tiles):
            x, y = self.slot_origin(slot)
            img[y:y + t, x:x + t] = materials.tile(pattern, pattern_variant(rgb8), rgb8)
        return img

    def tile_boxes(self) -> list[tuple[int, int, tuple[int, int, int]]]:
        """(x, y, colour) of every tile: what re-colouring shifts with its colour."""
        return [(*self.slot_origin(slot), rgb8) for slot, (_, rgb8) in enumerate(self.tiles)]


@lru_cache(maxsize=4)
def _texel_origins(size: int) -> np.ndarray:
    """(size * size, 2) texels (x, y) of each palette colour's top-left corner (read-only)."""
    index = np.arange(size * size)
    out = np.stack([index % size, index // size], axis=-1).astype(np.float64)
    out.flags.writeable = False
    return out


def pattern_variant(rgb8: tuple[int, int, int]) -> int:
    """Which variant of its pattern a colour shows: fixed by the colour, which the asset's
    seeded variant chose, so the same object looks the same in every house."""
    r, g, b = rgb8
    return (r * 7 + g * 13 + b * 31) % materials.PATTERN_VARIANTS


@dataclass(frozen=True)
class ColouredMesh:
    """A merged triangle mesh with one 8-bit colour per face (independent of any palette),
    and for faces of patterned parts their pattern and texture coordinates within a tile."""

    vertices: np.ndarray  # (N, 3)
    faces: np.ndarray  # (M, 3)
    normals: np.ndarray  # (M, 3): one per face, for flat shading
    face_rgb: np.ndarray  # (M, 3) uint8
    #: The distinct face colours packed as 0xRRGGBB, ascending, and each face's index into
    #: them: given by :func:`_merged`, which knows them per part; derived when None.
    colour_codes: np.ndarray | None = field(default=None, compare=False, repr=False)
    face_colour: np.ndarray | None = field(default=None, compare=False, repr=False)
    #: (M,) index into :data:`OBJECT_PATTERN_NAMES` of each face's pattern, -1 for flat
    #: faces; None when no face has one.
    face_pattern: np.ndarray | None = field(default=None, compare=False, repr=False)
    #: (M, 3, 2) each patterned face's corners within its tile, in [0, 1] (u along the
    #: part's longer side); None with ``face_pattern``.
    face_uv: np.ndarray | None = field(default=None, compare=False, repr=False)

    @property
    def n_faces(self) -> int:
        return len(self.faces)

    @cached_property
    def tile_keys(self) -> tuple[list[tuple[str, tuple[int, int, int]]], np.ndarray, np.ndarray]:
        """The distinct (pattern, colour) tiles the patterned faces ask for, those faces, and
        each one's index into the tiles (computed once per mesh: a link's mesh is made once
        per asset variant, its tiles' places in each house's atlas differ)."""
        assert self.face_pattern is not None
        faces = np.flatnonzero(self.face_pattern >= 0)
        codes, face_colour = self.colour_table()
        keys = self.face_pattern[faces].astype(np.int64) << 24 | codes[face_colour[faces]].astype(np.int64)
        distinct, which = np.unique(keys, return_inverse=True)
        tiles = [(OBJECT_PATTERN_NAMES[k >> 24], ((k >> 16) & 255, (k >> 8) & 255, k & 255))
                 for k in distinct.tolist()]
        return tiles, faces, which.reshape(-1)

    def colour_table(self) -> tuple[np.ndarray, np.ndarray]:
        """(distinct colour codes ascending, (M,) each face's index into them)."""
        if self.colour_codes is not None and self.face_colour is not None:
            return self.colour_codes, self.face_colour
        # Colours packed into one integer sort as the (r, g, b) rows do: the same order as
        # np.unique(face_rgb, axis=0), at a fraction of its cost.
        codes, inverse = np.unique(_packed(self.face_rgb), return_inverse=True)
        return codes, inverse.reshape(-1)

    def _texel_lookup(self, palette: Palette) -> tuple[np.ndarray, np.ndarray]:
        codes, face_colour = self.colour_table()
        lookup = np.array([palette.index_rgb8((c >> 16, (c >> 8) & 255, c & 255)) for c in codes.tolist()],
                          dtype=np.int32)
        return lookup, face_colour

    def texel_indices(self, palette: Palette) -> np.ndarray:
        """(M,) palette texel of each face (adds the mesh's colours to the palette, in the
        order of their codes)."""
        lookup, face_colour = self._texel_lookup(palette)
        return lookup[face_colour]

    def palette_texels(self, palette: Palette) -> tuple[np.ndarray, np.ndarray]:
        """``np.unique(self.texel_indices(palette), return_inverse=True)``: the texels the
        mesh uses, ascending, and each face's index into them; computed on the few distinct
        colours rather than on every face."""
        lookup, face_colour = self._texel_lookup(palette)
        # np.unique(lookup) of a few colours, without its sorting machinery.
        used = np.array(sorted(set(lookup.tolist())), dtype=lookup.dtype)
        return used, np.searchsorted(used, lookup)[face_colour]


def _packed(rgb8: np.ndarray) -> np.ndarray:
    """(..., 3) uint8 colours as 0xRRGGBB integers."""
    rgb = rgb8.astype(np.int32)
    return (rgb[..., 0] << 16) | (rgb[..., 1] << 8) | rgb[..., 2]


def face_normals(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    a = vertices[faces[:, 1]] - vertices[faces[:, 0]]
    b = vertices[faces[:, 2]] - vertices[faces[:, 0]]
    # np.cross's arithmetic, without its general-axis overhead.
    n = np.empty_like(a)
    n[:, 0] = a[:, 1] * b[:, 2] - a[:, 2] * b[:, 1]
    n[:, 1] = a[:, 2] * b[:, 0] - a[:, 0] * b[:, 2]
    n[:, 2] = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]
    length = np.linalg.norm(n, axis=1, keepdims=True)
    return n / np.where(length > 1e-12, length, 1.0)


def to_rgb8(rgba) -> np.ndarray:
    return np.round(np.clip(np.asarray(rgba, dtype=np.float64)[..., :3], 0.0, 1.0) * 255).astype(np.uint8)


@lru_cache(maxsize=8192)
def _rgb8_of(rgba: tuple) -> np.ndarray:
    """:func:`to_rgb8` of one colour, cached (parts share a few colours; read-only)."""
    out = to_rgb8(rgba)
    out.flags.writeable = False
    return out


@dataclass
class MeshAccumulator:
    """Collects coloured triangle sets and merges them into one :class:`ColouredMesh`."""

    _verts: list[np.ndarray] = field(default_factory=list)
    _faces: list[np.ndarray] = field(default_factory=list)
    _colours: list[np.ndarray] = field(default_factory=list)
    _count: int = 0

    def add(self, vertices: np.ndarray, faces: np.ndarray, rgba: Sequence[float] | np.ndarray) -> None:
        """Add triangles; ``rgba`` is one colour or one per face."""
        if len(faces) == 0:
            return
        rgb = _rgb8_of(rgba) if isinstance(rgba, tuple) else to_rgb8(rgba)
        if rgb.ndim == 1:
            rgb = np.broadcast_to(rgb, (len(faces), 3))
        self._verts.append(np.asarray(vertices, dtype=np.float64))
        self._faces.append(np.asarray(faces, dtype=np.int32) + self._count)
        self._colours.append(rgb)
        self._count += len(vertices)

    def add_part(self, part: Part) -> None:
        self.add(part.vertices, part.faces, part.rgba)

    def empty(self) -> bool:
        return self._count == 0

    def build(self) -> ColouredMesh:
        v = np.concatenate(self._verts)
        f = np.concatenate(self._faces)
        return ColouredMesh(v, f, face_normals(v, f), np.concatenate(self._colours))


def placed_together(meshes: Sequence[tuple[ColouredMesh, np.ndarray | None]]) -> ColouredMesh:
    """Meshes, each moved by a rigid 4x4 transform (None: where it is), as one mesh: a piece
    and the set dressing drawn with it, one draw for all. Faces keep their colours, patterns
    and tile coordinates; a rotation keeps their winding."""
    verts, faces, normals, rgb = [], [], [], []
    patterns: list[np.ndarray] = []
    uvs: list[np.ndarray] = []
    patterned = any(mesh.face_pattern is not None for mesh, _ in meshes)
    offset = 0
    for mesh, matrix in meshes:
        if matrix is None:
            verts.append(mesh.vertices)
            normals.append(mesh.normals)
        else:
            verts.append(mesh.vertices @ matrix[:3, :3].T + matrix[:3, 3])
            normals.append(mesh.normals @ matrix[:3, :3].T)
        faces.append(mesh.faces + np.int32(offset))
        offset += len(mesh.vertices)
        rgb.append(mesh.face_rgb)
        if patterned:
            if mesh.face_pattern is None or mesh.face_uv is None:
                patterns.append(np.full(mesh.n_faces, -1, dtype=np.int8))
                uvs.append(np.zeros((mesh.n_faces, 3, 2), dtype=np.float32))
            else:
                patterns.append(mesh.face_pattern)
                uvs.append(mesh.face_uv)
    return ColouredMesh(np.concatenate(verts), np.concatenate(faces), np.concatenate(normals), np.concatenate(rgb),
                        face_pattern=np.concatenate(patterns) if patterned else None,
                        face_uv=np.concatenate(uvs) if patterned else None)


@dataclass(frozen=True)
class SurfaceMesh:
    """Floor or wall triangles of one patterned surface: its texture repeats, each vertex's
    (u, v) is its position on the surface in periods of the pattern."""

    kind: str  # "floors" or "walls"
    pattern: str
    rgb8: tuple[int, int, int]
    vertices: np.ndarray  # (N, 3)
    faces: np.ndarray  # (M, 3)
    normals: np.ndarray  # (M, 3)
    uv: np.ndarray  # (N, 2)


class SurfaceAccumulator:
    """Collects patterned floor and wall triangles, one :class:`SurfaceMesh` per (kind,
    pattern, colour), for at most ``capacity`` of them: each is one geom on a repeating
    texture of its pattern in its colour."""

    def __init__(self, capacity: int) -> None:
        self.capacity = capacity
        self._groups: dict[tuple[str, str, tuple[int, int, int]], MeshAccumulator] = {}
        self._uvs: dict[tuple[str, str, tuple[int, int, int]], list[np.ndarray]] = {}

    @staticmethod
    def _key(kind: str, pattern: str, rgba: Sequence[float]) -> tuple[str, str, tuple[int, int, int]]:
        r, g, b = (int(c) for c in to_rgb8(rgba))
        return kind, pattern, (r, g, b)

    def takes(self, kind: str, pattern: str, rgba: Sequence[float]) -> bool:
        """Whether a surface of this kind ("floors" or "walls"), pattern and colour can be
        added (it is one already added, or there is room for one more)."""
        return self._key(kind, pattern, rgba) in self._groups or len(self._groups) < self.capacity

    def add(self, kind: str, pattern: str, rgba: Sequence[float], vertices: np.ndarray, faces: np.ndarray,
            uv: np.ndarray) -> None:
        key = self._key(kind, pattern, rgba)
        acc = self._groups.get(key)
        if acc is None:
            acc = self._groups[key] = MeshAccumulator()
            self._uvs[key] = []
        acc.add(vertices, faces, tuple(rgba))
        self._uvs[key].append(np.asarray(uv, dtype=np.float64))

    def meshes(self) -> list[SurfaceMesh]:
        out = []
        for key, acc in self._groups.items():
            mesh = acc.build()
            out.append(SurfaceMesh(*key, mesh.vertices, mesh.faces, mesh.normals, np.concatenate(self._uvs[key])))
        return out


@dataclass(frozen=True)
class CollisionShape:
    """A collision geom in a link's frame: a box (centre, half size) or a convex hull."""

    kind: str  # "box" or "hull"
    centre: np.ndarray | None = None
    half_size: np.ndarray | None = None
    vertices: np.ndarray | None = None


@dataclass(frozen=True)
class LinkGeometry:
    """What the builder needs of one asset link, computed once per asset variant."""

    mesh: ColouredMesh | None  # all untextured parts merged
    textured: tuple[Part, ...]  # imported parts with their own texture
    collision: tuple[CollisionShape, ...]


#: (id(link), movable) -> (a weak reference to the link, its geometry). An entry lives as
#: long as its link: a finalizer takes it out when the link is collected (so the id is
#: never reused while the entry is there), and the geometry is not kept for a link that no
#: one holds any more, such as a variant the asset registry's cache has let go.
_LINK_CACHE: dict[tuple[int, bool], tuple[weakref.ref, LinkGeometry]] = {}


def link_geometry(link, movable: bool, *, cache: bool = True) -> LinkGeometry:
    """Merged visual mesh and collision shapes of a link (cached per link object, for as
    long as the link lives).

    Collision is cheap where it can be: static furniture collides through the bounding box
    of each part (exact for box parts, and what things rest on are flat tops); a moving
    link gets box parts as boxes and all its round parts as one convex hull, because every
    hull costs compile time.
    """
    hit = _LINK_CACHE.get((id(link), movable)) if cache else None
    if hit is not None and hit[0]() is link:
        return hit[1]
    geometry = _geometries([(link, movable)])[0]
    if cache:
        _remember(link, movable, geometry)
    return geometry


def prepare_link_geometry(links: list[tuple[Link, bool]]) -> None:
    """Compute the :func:`link_geometry` of many ``(link, movable)`` at once (into its
    cache): the same arrays, with a few array operations for all of them rather than for
    each (a house's links are mostly new: their models are new variants)."""
    todo, seen = [], set()
    for link, movable in links:
        key = (id(link), movable)
        hit = _LINK_CACHE.get(key)
        if key not in seen and (hit is None or hit[0]() is not link):
            seen.add(key)
            todo.append((link, movable))
    for (link, movable), geometry in zip(todo, _geometries(todo)):
        _remember(link, movable, geometry)


def cached_links() -> int:
    """How many ``(link, movable)`` geometries :func:`link_geometry` holds now."""
    return len(_LINK_CACHE)


def _remember(link, movable: bool, geometry: LinkGeometry) -> None:
    key = (id(link), movable)
    if key not in _LINK_CACHE:
        weakref.finalize(link, _LINK_CACHE.pop, key, None)
    _LINK_CACHE[key] = (weakref.ref(link), geometry)


def _geometries(links: list[tuple[Link, bool]]) -> list[LinkGeometry]:
    """:class:`LinkGeometry` of each ``(link, movable)``."""
    textured, plain, boxes, hulls = [], [], [], []
    for link, movable in links:
        textured.append(tuple(p for p in link.parts if p.texture is not None and p.uv is not None))
        plain.append([p for p in link.parts if (p.texture is None or p.uv is None) and len(p.faces)])
        boxes.append([p for p in link.parts if p.collision != "none" and (p.collision == "box" or not movable)])
        hulls.append([p.vertices for p in link.parts if p.collision not in ("none", "box") and movable])
    meshes = iter(_merged_many([parts for parts in plain if parts]))
    box_shapes = iter(_box_shapes([parts for parts in boxes if parts]))
    out = []
    for k in range(len(links)):
        shapes = list(next(box_shapes)) if boxes[k] else []
        if hulls[k]:
            shapes.append(CollisionShape("hull", vertices=np.concatenate(hulls[k])))
        out.append(LinkGeometry(next(meshes) if plain[k] else None, textured[k], tuple(shapes)))
    return out


def _box_shapes(groups: list[list[Part]]) -> list[list[CollisionShape]]:
    """Each group's parts as collision boxes (:func:`_boxes`), for all groups at once."""
    if not groups:
        return []
    if any(len(p.vertices) == 0 for group in groups for p in group):
        # reduceat gives an empty part a neighbour's row: keep each link's parts to itself.
        return [_boxes(group) for group in groups]
    shapes = _boxes([p for group in groups for p in group])
    out, k = [], 0
    for group in groups:
        out.append(shapes[k:k + len(group)])
        k += len(group)
    return out


def _boxes(parts: list[Part]) -> list[CollisionShape]:
    """Each part's bounds as a collision box (grown to at least 0.1 mm): min and max over
    each part's rows of one array of all the parts."""
    allv = np.concatenate([p.vertices for p in parts])
    starts = np.cumsum([0] + [len(p.vertices) for p in parts[:-1]])
    lo, hi = np.minimum.reduceat(allv, starts), np.maximum.reduceat(allv, starts)
    centres, halves = (lo + hi) / 2, np.maximum((hi - lo) / 2, 1e-4)
    return [CollisionShape("box", centres[i], halves[i]) for i in range(len(parts))]


def _merged(parts: list[Part]) -> ColouredMesh:
    """The parts as one mesh, each face coloured by its part: what adding them one by one
    to a :class:`MeshAccumulator` builds, in a few array operations. Every part has faces."""
    return _merged_many([parts])[0]


def _merged_many(groups: list[list[Part]]) -> list[ColouredMesh]:
    """:func:`_merged` of each group of parts, with one array operation for all groups
    where the arithmetic is row by row (vertex offsets, face normals, colours): each mesh
    holds views of the shared arrays."""
    if not groups:
        return []
    parts = [p for group in groups for p in group]
    v = np.concatenate([p.vertices for p in parts])
    n_verts = [len(p.vertices) for p in parts]
    n_faces = [len(p.faces) for p in parts]
    # Each part's first vertex in the shared array, and in its own group's mesh.
    starts = np.cumsum([0] + n_verts[:-1])
    group_start = np.repeat(starts[np.cumsum([0] + [len(g) for g in groups[:-1]])], [len(g) for g in groups])
    faces = np.concatenate([p.faces for p in parts])
    shared = faces + np.repeat(starts.astype(np.int32), n_faces)[:, None]
    local = faces + np.repeat((starts - group_start).astype(np.int32), n_faces)[:, None]
    normals = face_normals(v, shared)
    part_rgb = to_rgb8([tuple(p.rgba)[:3] for p in parts])  # row by row what _rgb8_of gives
    rgb = np.repeat(part_rgb, n_faces, axis=0)
    packed = _packed(part_rgb)
    part_codes = packed.tolist()
    face_pattern, face_uv = _patterns(parts, v, shared, normals, starts, n_faces)
    out, k, f0 = [], 0, 0
    for group in groups:
        nf = sum(n_faces[k:k + len(group)])
        v0, v1 = int(starts[k]), int(starts[k]) + sum(n_verts[k:k + len(group)])
        # One colour per part: the faces' distinct colours are the parts' distinct colours
        # (np.unique(..., return_inverse=True) of a few codes, without its machinery).
        mine = part_codes[k:k + len(group)]
        distinct = sorted(set(mine))
        position = {code: i for i, code in enumerate(distinct)}
        codes = np.array(distinct, dtype=packed.dtype)
        part_colour = np.array([position[code] for code in mine], dtype=np.intp)
        mine_pattern = mine_uv = None
        if face_pattern is not None and face_uv is not None and (face_pattern[f0:f0 + nf] >= 0).any():
            mine_pattern, mine_uv = face_pattern[f0:f0 + nf], face_uv[f0:f0 + nf]
        out.append(ColouredMesh(v[v0:v1], local[f0:f0 + nf], normals[f0:f0 + nf], rgb[f0:f0 + nf], codes,
                                np.repeat(part_colour, n_faces[k:k + len(group)]), mine_pattern, mine_uv))
        k += len(group)
        f0 += nf
    return out


def _patterns(parts: list[Part], v: np.ndarray, faces: np.ndarray, normals: np.ndarray, starts: np.ndarray,
              n_faces: list[int]) -> tuple[np.ndarray | None, np.ndarray | None]:
    """Each face's pattern (or -1) and its corners' (u, v) within a tile, for all parts at
    once: a face is projected along its normal's largest axis onto its part's bounding box,
    u along the longer of the two sides left (wood grain along a board), so that each face
    of a box shows the whole tile. None, None when no part is patterned."""
    part_pattern = np.array([_PATTERN_INDEX.get(p.material, -1) for p in parts], dtype=np.int8)
    if not (part_pattern >= 0).any():
        return None, None
    lo, hi = np.minimum.reduceat(v, starts), np.maximum.reduceat(v, starts)
    extent = hi - lo
    part_pattern[extent.max(axis=1) < PATTERN_MIN_SIZE] = -1
    face_pattern = np.repeat(part_pattern, n_faces)
    patterned = np.flatnonzero(face_pattern >= 0)
    face_uv = np.zeros((len(faces), 3, 2), dtype=np.float32)
    if len(patterned) == 0:
        return None, None
    face_part = np.repeat(np.arange(len(parts)), n_faces)[patterned]
    axis = np.abs(normals[patterned]).argmax(axis=1)
    across = np.stack([np.array([1, 0, 0])[axis], np.array([2, 2, 1])[axis]], axis=1)  # (F, 2)
    rows = np.arange(len(patterned))[:, None]
    corners = v[faces[patterned]]  # (F, 3, 3)
    size = np.maximum(extent[face_part][rows, across], 1e-9)  # (F, 2)
    start = lo[face_part][rows, across]
    uv = (np.take_along_axis(corners, across[:, None, :], axis=2) - start[:, None, :]) / size[:, None, :]
    longer_second = size[:, 1] > size[:, 0]
    uv[longer_second] = uv[longer_second][..., ::-1]
    face_uv[patterned] = np.clip(uv, 0.0, 1.0)
    return face_pattern, face_uv


# ---------------------------------------------------------------------------------------
# House shell geometry


def triangulate_polygon(polygon: Sequence[Sequence[float]] | np.ndarray) -> np.ndarray:
    """Triangles (indices into the polygon) of a simple polygon, CCW from above."""
    pts = np.asarray(polygon, dtype=np.float64)
    tris = np.asarray(mapbox_earcut.triangulate_float64(pts, np.array([len(pts)], dtype=np.uint32)))
    tris = tris.reshape(-1, 3).astype(np.int32)
    # earcut's winding depends on the input; make every triangle face +z.
    a, b, c = pts[tris[:, 0]], pts[tris[:, 1]], pts[tris[:, 2]]
    cross = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
    tris[cross < 0] = tris[cross < 0][:, ::-1]
    return tris


def polygon_surface(polygon, z: float, *, facing_up: bool = True) -> tuple[np.ndarray, np.ndarray]:
    pts = np.asarray(polygon, dtype=np.float64)
    tris = triangulate_polygon(pts)
    verts = np.column_stack([pts, np.full(len(pts), z)])
    return verts, (tris if facing_up else tris[:, ::-1])


@dataclass(frozen=True)
class WallPiece:
    """A solid box of wall between openings: along-wall interval [a, b], height [z0, z1]."""

    a: float
    b: float
    z0: float
    z1: float


def wall_pieces(length: float, height: float, openings: Sequence[tuple[float, float, float, float]]) -> list[WallPiece]:
    """Split a wall into solid boxes around its openings.

    ``openings`` are (offset_centre, width, z_bottom, z_top) along the wall. The wall is cut
    into vertical strips at every opening edge; each strip keeps the parts of [0, height]
    not covered by an opening spanning it.
    """
    cuts = {0.0, length}
    for centre, width, _, _ in openings:
        cuts.add(min(max(centre - width / 2, 0.0), length))
        cuts.add(min(max(centre + width / 2, 0.0), length))
    xs = sorted(cuts)
    pieces = []
    for a, b in zip(xs, xs[1:]):
        if b - a < 1e-6:
            continue
        mid = (a + b) / 2
        holes = sorted((z0, z1) for c, w, z0, z1 in openings if c - w / 2 < mid < c + w / 2)
        z = 0.0
        for z0, z1 in holes:
            if z0 > z + 1e-6:
                pieces.append(WallPiece(a, b, z, z0))
            z = max(z, z1)
        if height > z + 1e-6:
            pieces.append(WallPiece(a, b, z, height))
    return pieces


def wall_piece_box(start, end, thickness: float, piece: WallPiece, colour_left, colour_right):
    """Vertices, faces and per-face colours of one wall piece (box), in world coordinates.

    Faces on the left of the direction start -> end take ``colour_left``, the right side
    ``colour_right``, so a wall shared by two rooms shows each room's paint.
    """
    start = np.asarray(start, dtype=np.float64)
    direction = np.asarray(end, dtype=np.float64) - start
    length = float(np.linalg.norm(direction))
    angle = math.atan2(direction[1], direction[0])
    centre_along = (piece.a + piece.b) / 2
    size = (piece.b - piece.a, thickness, piece.z1 - piece.z0)
    local = box_part((0.0, 0.0, 0.0), size)
    c, s = math.cos(angle), math.sin(angle)
    rot = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])
    origin = np.array([*(start + direction / max(length, 1e-12) * centre_along), (piece.z0 + piece.z1) / 2])
    verts = local.vertices @ rot.T + origin
    # box_part's face order: -x, +x, -y, +y, -z, +z (two triangles each); +y is the left.
    colours = np.array([colour_left] * 12)
    colours[4:6] = colour_right
    return verts, local.faces, colours

"""Mesh assembly for the builder: palette colouring, flat normals, and the house shell.

Why a palette: every draw call costs render time on a CPU renderer, and a MuJoCo geom has
one colour. We merge all parts of a link (and all walls, all floors) into one mesh and give
each triangle its colour through texture coordinates into one small shared palette texture
(one texel per colour). One geom, many colours, one material.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import mapbox_earcut
import numpy as np

from legent_gym.world.assets.model import Part, box_part

PALETTE_SIZE = 64  # 64 x 64 texels: 4,096 distinct colours per scene


class Palette:
    """Colours used in a scene, one texel each; colours are quantised to 8 bits."""

    def __init__(self, size: int = PALETTE_SIZE):
        self.size = size
        self._index: dict[tuple[int, int, int], int] = {}

    def index(self, rgba: Sequence[float]) -> int:
        key = tuple(int(round(min(max(c, 0.0), 1.0) * 255)) for c in rgba[:3])
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

    def uv(self, index: int) -> tuple[float, float]:
        """Texture coordinate of a texel's centre."""
        row, col = divmod(index, self.size)
        return (col + 0.5) / self.size, (row + 0.5) / self.size

    def all_uvs(self) -> np.ndarray:
        idx = np.arange(self.size * self.size)
        return np.stack([(idx % self.size + 0.5) / self.size, (idx // self.size + 0.5) / self.size], axis=1)

    def image(self) -> np.ndarray:
        img = np.zeros((self.size * self.size, 3), dtype=np.uint8)
        for colour, idx in self._index.items():
            img[idx] = colour
        return img.reshape(self.size, self.size, 3)

    def __len__(self) -> int:
        return len(self._index)


@dataclass
class MeshData:
    """Arrays for an MjSpec mesh with per-face normals (flat shading) and per-corner UVs."""

    vertices: np.ndarray  # (N, 3)
    faces: np.ndarray  # (M, 3)
    normals: np.ndarray  # (M, 3): one per face
    texcoord_index: np.ndarray  # (M, 3): palette texel index per face corner

    @property
    def n_faces(self) -> int:
        return len(self.faces)


def face_normals(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    n = np.cross(vertices[faces[:, 1]] - vertices[faces[:, 0]], vertices[faces[:, 2]] - vertices[faces[:, 0]])
    length = np.linalg.norm(n, axis=1, keepdims=True)
    return n / np.where(length > 1e-12, length, 1.0)


@dataclass
class MeshAccumulator:
    """Collects coloured triangle sets and merges them into one :class:`MeshData`."""

    palette: Palette
    _verts: list[np.ndarray] = field(default_factory=list)
    _faces: list[np.ndarray] = field(default_factory=list)
    _colours: list[np.ndarray] = field(default_factory=list)
    _count: int = 0

    def add(self, vertices: np.ndarray, faces: np.ndarray, rgba: Sequence[float] | np.ndarray) -> None:
        """Add triangles; ``rgba`` is one colour or one per face."""
        if len(faces) == 0:
            return
        rgba = np.asarray(rgba, dtype=np.float64)
        if rgba.ndim == 1:
            colour_idx = np.full(len(faces), self.palette.index(rgba), dtype=np.int32)
        else:
            colour_idx = np.array([self.palette.index(c) for c in rgba], dtype=np.int32)
        self._verts.append(np.asarray(vertices, dtype=np.float64))
        self._faces.append(np.asarray(faces, dtype=np.int32) + self._count)
        self._colours.append(colour_idx)
        self._count += len(vertices)

    def add_part(self, part: Part, transform: np.ndarray | None = None) -> None:
        p = part if transform is None else part.transformed(transform)
        self.add(p.vertices, p.faces, p.rgba)

    def empty(self) -> bool:
        return self._count == 0

    def build(self) -> MeshData:
        v = np.concatenate(self._verts)
        f = np.concatenate(self._faces)
        c = np.concatenate(self._colours)
        return MeshData(v, f, face_normals(v, f), np.repeat(c[:, None], 3, axis=1))


# ---------------------------------------------------------------------------------------
# House shell geometry


def triangulate_polygon(polygon: Sequence[Sequence[float]]) -> np.ndarray:
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

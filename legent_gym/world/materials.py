"""Surface patterns: seeded procedural textures for the materials of parts, floors and walls.

A material name (``wood``, ``fabric``, ``carpet``, ...) says little while every part is drawn
in one flat colour; this module gives each material a look: a small grey pattern of
brightness factors that the builder multiplies by the surface's colour. The builder packs one
texture atlas per house of ``TILE`` x ``TILE`` tiles, one tile per (pattern, colour) pair the
house uses (:func:`tile`). An object's part has its pattern stretched once over each face
(u along the face's longer side); floors and walls repeat theirs every ``SURFACE_PERIOD``
metres, so surface patterns tile seamlessly and object patterns need not.

Every pattern is made from a seed (``zlib.crc32`` of its name, and its variant) rather than
read from an image: nothing to download or ship, the same texels in every run, and
``PATTERN_VARIANTS`` looks per material so that two wooden tables need not share one grain.
Making every pattern of every variant takes about 30 ms for all of them on one core, once
per process (:func:`pattern` caches them); a tile of one colour then costs about 20 us.

Conventions: axis 0 of a pattern is its rows (v), axis 1 its columns (u); the "along"
direction of an object pattern (wood grain, brushed metal) runs along u. Factors lie within
[0.5, 1.4] and average 1, so a textured surface keeps its scene colour on the whole.
"""

from __future__ import annotations

import math
import zlib
from collections.abc import Callable
from functools import cache, lru_cache

import numpy as np

TILE = 32  # texels per side of every pattern
PATTERN_VARIANTS = 4  # variants per pattern name

#: Patterns of objects' parts: stretched over one face of a part (need not repeat seamlessly).
OBJECT_PATTERNS: frozenset[str] = frozenset({"wood", "fabric", "leather", "metal", "ceramic", "stone", "paper"})
#: Patterns of floors and walls: one tile covers SURFACE_PERIOD x SURFACE_PERIOD metres and
#: repeats, so it must tile seamlessly (its last column continues into its first, its last row
#: into its first).
SURFACE_PATTERNS: frozenset[str] = frozenset({"floorboards", "tile", "carpet", "stone_slabs", "paint", "wallpaper"})
SURFACE_PERIOD = 1.0  # metres of floor or wall one surface tile covers

#: The scene's floor and wall materials that have a pattern; the others are drawn flat.
_SURFACE_OF_MATERIAL: dict[str, str] = {
    "wood": "floorboards", "tile": "tile", "carpet": "carpet", "stone": "stone_slabs",
    "paint": "paint", "wallpaper": "wallpaper",
}
#: The range every factor is clipped to: darker or brighter and a surface stops reading as its
#: own colour.
_FACTOR_RANGE = (0.5, 1.4)
#: Factors are rounded to multiples of 1 / _QUANTUM: a factor then has at most 13 significant
#: bits, so an 8-bit colour times it is exact in float32 and :func:`tile` rounds exactly as
#: float64 arithmetic would.
_QUANTUM = 4096
_BLACK, _WHITE = np.float32(0.0), np.float32(255.0)

_V, _U = np.mgrid[0:TILE, 0:TILE].astype(np.float64)  # every texel's row (v) and column (u)

_Maker = Callable[[np.random.Generator, int], np.ndarray]  # (seeded generator, variant) -> raw factors


# ---------------------------------------------------------------------------------------
# Building blocks. Every noise is periodic over the tile (white noise blurred circularly),
# so the surface patterns built from it tile seamlessly with no blending at the edges.


def _noise(rng: np.random.Generator, scale_v: float, scale_u: float) -> np.ndarray:
    """(TILE, TILE) periodic noise, zero mean and unit deviation, smoothed over about
    ``scale_v`` rows and ``scale_u`` columns (0: white)."""
    return _standardise(_blur(scale_v) @ rng.standard_normal((TILE, TILE)) @ _blur(scale_u).T)


def _noise1(rng: np.random.Generator, scale: float) -> np.ndarray:
    """(TILE,) periodic 1-D noise, zero mean and unit deviation, smoothed over about ``scale``
    texels."""
    return _standardise(_blur(scale) @ rng.standard_normal(TILE))


@cache
def _blur(scale: float) -> np.ndarray:
    """(TILE, TILE) circular Gaussian blur of ``scale`` texels as a matrix (a texel's row
    blurs a column vector). Two small matrix products blur a tile several times faster than a
    round trip through an FFT, with the same periodic result."""
    kernel = np.fft.irfft(np.exp(-2.0 * math.pi**2 * (scale * np.fft.rfftfreq(TILE)) ** 2), n=TILE)
    offset = (np.arange(TILE)[:, None] - np.arange(TILE)[None, :]) % TILE
    return kernel[offset]


def _standardise(x: np.ndarray) -> np.ndarray:
    x = x - x.mean()
    std = x.std()
    return x / std if std > 0 else x


def _marble(rng: np.random.Generator, width: float) -> np.ndarray:
    """(TILE, TILE) veins in [0, 1] (1 on a vein, about ``width`` texels wide): the zero lines
    of ``|sin|`` of a wave bent by turbulence. The wave makes whole half cycles over the tile
    both ways, so ``|sin|`` and the veins are periodic; there are two to four of them."""
    a, b = [(1, 2), (2, 1), (1, -2), (2, -1), (2, 3), (3, -2)][rng.integers(6)]
    turbulence = 0.7 * _noise(rng, 5.0, 5.0) + 0.15 * _noise(rng, 2.0, 2.0)
    phase = math.pi * (a * _U + b * _V) / TILE + turbulence + rng.uniform(0.0, math.pi)
    # |sin| over the phase's slope is the distance to the nearest zero line in texels, so the
    # veins keep their width where the turbulence steepens or flattens the wave; a plain
    # power of |sin| makes veins thinner than a texel there, which alias into dots.
    slope_u = math.pi * a / TILE + (np.roll(turbulence, -1, axis=1) - np.roll(turbulence, 1, axis=1)) / 2.0
    slope_v = math.pi * b / TILE + (np.roll(turbulence, -1, axis=0) - np.roll(turbulence, 1, axis=0)) / 2.0
    distance = np.abs(np.sin(phase)) / np.maximum(np.hypot(slope_u, slope_v), 1e-3)
    return np.exp(-((distance / width) ** 2))


def _cells(rng: np.random.Generator, per_side: int) -> np.ndarray:
    """(TILE, TILE) distance in texels from each texel to the nearest border of the Voronoi
    cells of one random point in each square of a ``per_side`` x ``per_side`` grid (second
    nearest minus nearest distance), periodic over the tile. With a point per square, a
    texel's two nearest points lie among the nine squares around its own."""
    size = TILE / per_side
    jitter = rng.uniform(0.0, 1.0, (2, per_side, per_side))
    square_v, square_u = (_V // size).astype(int), (_U // size).astype(int)
    squared = []
    for dv in (-1, 0, 1):
        for du in (-1, 0, 1):
            near_v, near_u = square_v + dv, square_u + du
            point_v = (near_v + jitter[0, near_v % per_side, near_u % per_side]) * size
            point_u = (near_u + jitter[1, near_v % per_side, near_u % per_side]) * size
            squared.append((_V + 0.5 - point_v) ** 2 + (_U + 0.5 - point_u) ** 2)
    nearest = np.sqrt(np.partition(np.stack(squared), 1, axis=0)[:2])
    return nearest[1] - nearest[0]


def _grid(offset: int, cell: int) -> tuple[np.ndarray, np.ndarray]:
    """(TILE,) cell index and grout flag of every row (or column) of a grid of ``cell``-texel
    cells whose one-texel grout lines lie at ``offset``, ``offset + cell``, ... An offset in
    [1, cell - 2] keeps the grout off the tile's first and last texel, so the tile's wrap lies
    inside a cell rather than on a grout line."""
    position = (np.arange(TILE) - offset) % TILE
    return position // cell, position % cell == 0


# ---------------------------------------------------------------------------------------
# Object patterns (stretched over a face: need not tile)


def _wood(rng: np.random.Generator, variant: int) -> np.ndarray:
    lines = int(rng.integers(5, 10))
    # Slow along u, so the grain lines wave gently and run along u.
    warp = _noise(rng, 4.0, 9.0)
    phase = 2.0 * math.pi * lines * _V / TILE + 1.2 * warp + rng.uniform(0.0, 2.0 * math.pi)
    # Lines fade in and out along their length, as growth rings cut at a slant do.
    line = np.maximum(np.cos(phase), 0.0) ** 3 * (0.75 + 0.25 * np.tanh(_noise(rng, 6.0, 6.0)))
    streaks = _noise1(rng, 0.6)[:, None] * (1.0 + 0.3 * _noise1(rng, 8.0)[None, :])
    return 1.0 - 0.25 * line + 0.025 * streaks


def _fabric(rng: np.random.Generator, variant: int) -> np.ndarray:
    # Even variants a plain weave (a checker of single texels), odd ones a 2/2 twill (diagonals).
    weave = (_U + _V) % 2 if variant % 2 == 0 else ((_U + _V) // 2) % 2
    return 1.0 + 0.05 * (2.0 * weave - 1.0) + 0.035 * _noise(rng, 4.0, 4.0) + 0.01 * _noise(rng, 0.0, 0.0)


def _leather(rng: np.random.Generator, variant: int) -> np.ndarray:
    border = _cells(rng, int(rng.integers(7, 10)))
    # Rounded pebbles with soft creases between: the cells' borders, blurred.
    pebbles = _blur(0.7) @ np.clip(border / 2.5, 0.0, 1.0) @ _blur(0.7).T
    edge = np.minimum(np.minimum(_U, TILE - 1 - _U), np.minimum(_V, TILE - 1 - _V))
    worn = np.exp(-edge / 3.0)  # handled edges go darker
    return 1.0 + 0.16 * (pebbles - 0.5) + 0.02 * _noise(rng, 5.0, 5.0) - 0.05 * worn


def _metal(rng: np.random.Generator, variant: int) -> np.ndarray:
    # Brushing leaves streaks along u: one value per row, varying slowly along it.
    streaks = _noise1(rng, 0.5)[:, None] * (1.0 + 0.25 * _noise1(rng, 10.0)[None, :])
    centre, width, slant = rng.uniform(0.0, TILE), rng.uniform(5.0, 9.0), rng.uniform(-0.15, 0.15)
    offset = (_V - centre - slant * _U + TILE / 2) % TILE - TILE / 2
    highlight = np.exp(-0.5 * (offset / width) ** 2)
    return 1.0 + 0.04 * streaks + 0.1 * highlight


def _ceramic(rng: np.random.Generator, variant: int) -> np.ndarray:
    angle = rng.uniform(0.15, 0.35) * math.pi + (math.pi / 2) * (variant % 2)
    along = (_U * math.cos(angle) + _V * math.sin(angle)) / (TILE * (abs(math.cos(angle)) + abs(math.sin(angle))))
    gradient = 2.0 * (along - along.mean())  # about -1 .. 1 from corner to corner
    out = 1.0 + 0.04 * gradient + 0.004 * _noise(rng, 1.0, 1.0)
    count = int(rng.integers(3, 7))
    out[rng.integers(0, TILE, count), rng.integers(0, TILE, count)] *= rng.choice([0.93, 1.06], count)
    return out


def _stone(rng: np.random.Generator, variant: int) -> np.ndarray:
    veins = _marble(rng, rng.uniform(0.6, 1.0))
    return 1.05 - 0.22 * veins + 0.025 * _noise(rng, 4.0, 4.0) + 0.008 * _noise(rng, 0.0, 0.0)


def _paper(rng: np.random.Generator, variant: int) -> np.ndarray:
    count = int(rng.integers(10, 18))
    start = rng.uniform(0.0, TILE, (2, count))
    angle = rng.uniform(0.0, math.pi, count)
    length = rng.uniform(4.0, 10.0, count)
    direction = np.stack([np.sin(angle), np.cos(angle)])  # (v, u) of each fibre
    dv, du = _V[..., None] - start[0], _U[..., None] - start[1]
    t = np.clip(dv * direction[0] + du * direction[1], 0.0, length)
    distance = np.hypot(dv - t * direction[0], du - t * direction[1])
    fibres = np.exp(-((distance / 0.6) ** 2)).max(axis=-1)
    return 1.0 + 0.015 * _noise(rng, 4.0, 4.0) + 0.006 * _noise(rng, 0.0, 0.0) - 0.035 * fibres


# ---------------------------------------------------------------------------------------
# Surface patterns (repeat every SURFACE_PERIOD metres: tile seamlessly)


def _floorboards(rng: np.random.Generator, variant: int) -> np.ndarray:
    boards = 6
    # Seams at 0, 5, 11, 16, 21, 27 shifted by 1..3: the tile's last row and first row lie in
    # one board, so its wrap is no seam the eye would catch repeating.
    seam_rows = int(rng.integers(1, 4)) + np.round(np.arange(boards) * TILE / boards).astype(int)
    board = (np.searchsorted(seam_rows, np.arange(TILE), side="right") - 1) % boards
    seam = np.isin(np.arange(TILE), seam_rows)
    tones = 1.0 + rng.uniform(-0.1, 0.1, boards)
    # One end joint per board, staggered by about a third of a tile from board to board, off
    # the tile's first and last column.
    stride = TILE // 3 + int(rng.integers(-1, 2))
    joints = 1 + (int(rng.integers(TILE)) + stride * np.arange(boards) + rng.integers(-2, 3, boards)) % (TILE - 2)
    grain = 0.03 * _noise(rng, 0.6, 6.0) + 0.012 * _noise(rng, 0.0, 2.0)
    out = tones[board][:, None] + grain
    out[np.arange(TILE) == joints[board][:, None]] = 0.72
    out[seam, :] = 0.7
    return out


def _tile(rng: np.random.Generator, variant: int) -> np.ndarray:
    cell = TILE // 4
    row, grout_row = _grid(int(rng.integers(1, cell - 1)), cell)
    col, grout_col = _grid(int(rng.integers(1, cell - 1)), cell)
    tones = 1.0 + rng.uniform(-0.04, 0.04, (4, 4))
    out = tones[row[:, None], col[None, :]] + 0.006 * _noise(rng, 1.5, 1.5)
    out[grout_row[:, None] | grout_col[None, :]] = rng.uniform(0.75, 0.85)
    return out


def _carpet(rng: np.random.Generator, variant: int) -> np.ndarray:
    pile = 0.035 * _noise(rng, 0.0, 0.0) + 0.015 * _noise(rng, 0.8, 0.8)
    return 1.0 + pile + 0.03 * _noise(rng, 5.0, 5.0)


def _stone_slabs(rng: np.random.Generator, variant: int) -> np.ndarray:
    cell = TILE // 2
    row, grout_row = _grid(int(rng.integers(1, cell - 1)), cell)
    col, grout_col = _grid(int(rng.integers(1, cell - 1)), cell)
    slab = (2 * row[:, None] + col[None, :]).astype(int)
    # Each slab is cut from its own block: its own veins and tone. The veins are periodic, so
    # the slab across the tile's wrap still continues into itself.
    veins = np.stack([_marble(rng, rng.uniform(0.5, 0.8)) for _ in range(4)])
    tones = 1.0 + rng.uniform(-0.03, 0.03, 4)
    out = tones[slab] - 0.2 * np.take_along_axis(veins, slab[None], axis=0)[0] + 0.015 * _noise(rng, 3.0, 3.0)
    out[grout_row[:, None] | grout_col[None, :]] = rng.uniform(0.72, 0.82)
    return out


def _paint(rng: np.random.Generator, variant: int) -> np.ndarray:
    # A roller leaves long faint bands along one stroke direction (axis 0) and a fine stipple.
    return 1.0 + 0.009 * _noise(rng, 6.0, 1.2) + 0.005 * _noise(rng, 0.5, 0.5)


def _wallpaper(rng: np.random.Generator, variant: int) -> np.ndarray:
    ground = 1.0 + 0.008 * _noise(rng, 2.0, 2.0)
    contrast = rng.uniform(0.06, 0.08)
    if variant % 2 == 0:  # stripes of two tones
        period = 8 if variant % 4 == 0 else 16
        width = int(rng.integers(period // 4, 3 * period // 4 + 1))
        # No stripe edge between the last column and the first: the wrap lies inside a stripe.
        offsets = [o for o in range(1, period) if (o + width) % period != 0]
        offset = offsets[rng.integers(len(offsets))]
        stripe = ((_U - offset) % period) < width
        return ground + contrast * np.where(stripe, 1.0, -1.0)
    # Odd variants: a half-drop grid of small motifs, centred in 8-texel cells so that the
    # rows and columns at a cell's edge (the tile's wrap among them) stay plain ground.
    cell = TILE // 4
    drop = (cell // 2) * ((_U // cell) % 2)
    dv, du = (_V + drop) % cell - (cell - 1) / 2, _U % cell - (cell - 1) / 2
    if variant % 4 == 1:
        distance, radius = np.hypot(dv, du), rng.uniform(1.6, 2.2)  # dots
    else:
        distance, radius = np.abs(dv) + np.abs(du), rng.uniform(2.4, 2.9)  # diamonds
    motif = np.clip(radius - distance + 0.5, 0.0, 1.0)  # antialiased edge
    return ground - 2.0 * contrast * motif * rng.choice([1.0, -0.8])


_GENERATORS: dict[str, _Maker] = {
    "wood": _wood, "fabric": _fabric, "leather": _leather, "metal": _metal, "ceramic": _ceramic,
    "stone": _stone, "paper": _paper,
    "floorboards": _floorboards, "tile": _tile, "carpet": _carpet, "stone_slabs": _stone_slabs,
    "paint": _paint, "wallpaper": _wallpaper,
}
assert set(_GENERATORS) == OBJECT_PATTERNS | SURFACE_PATTERNS


# ---------------------------------------------------------------------------------------
# The interface


@lru_cache(maxsize=256)  # 13 names x 4 variants in use; bounded against callers' stray variants
def pattern(name: str, variant: int) -> np.ndarray:
    """(TILE, TILE) float32 brightness factors of the pattern ``name`` (in ``OBJECT_PATTERNS``
    or ``SURFACE_PATTERNS``), ``variant`` in [0, PATTERN_VARIANTS) (taken modulo
    PATTERN_VARIANTS). A texel's colour is the surface's colour times its factor.

    Deterministic (seeded from ``zlib.crc32`` of the name, and the variant), cached, and
    read-only: callers share the one array. Raises ValueError for an unknown name."""
    make = _GENERATORS.get(name)
    if make is None:
        raise ValueError(f"unknown pattern {name!r}; known: {', '.join(sorted(_GENERATORS))}")
    variant %= PATTERN_VARIANTS
    rng = np.random.default_rng([zlib.crc32(name.encode()), variant])
    raw = make(rng, variant)
    # A mean of 1 keeps the surface's average colour its scene colour, however dark its grout.
    factors = np.clip(raw / raw.mean(), *_FACTOR_RANGE)
    out = (np.round(factors * _QUANTUM) / _QUANTUM).astype(np.float32)
    out.flags.writeable = False
    return out


def tile(name: str, variant: int, rgb8: tuple[int, int, int]) -> np.ndarray:
    """(TILE, TILE, 3) uint8: ``rgb8`` times ``pattern(name, variant)``, rounded and clipped
    to 0..255."""
    # Channels first, interleaved at the end: with three channels as numpy's innermost loop the
    # arithmetic runs several times slower.
    texels = pattern(name, variant).reshape(1, TILE * TILE) * np.asarray(rgb8, dtype=np.float32)[:, None]
    np.rint(texels, out=texels)
    # Two ufuncs rather than np.clip, whose own overhead costs more than the arithmetic here.
    np.minimum(texels, _WHITE, out=texels)
    np.maximum(texels, _BLACK, out=texels)
    return texels.astype(np.uint8).T.copy().reshape(TILE, TILE, 3)


def surface_pattern(material: str) -> str | None:
    """The surface pattern of a scene ``Surface`` material: ``"wood"`` -> ``"floorboards"``,
    ``"stone"`` -> ``"stone_slabs"``, ``"tile"``, ``"carpet"``, ``"paint"`` and
    ``"wallpaper"`` -> themselves; anything else (``"plain"``, ...) -> None (drawn flat)."""
    return _SURFACE_OF_MATERIAL.get(material)


def object_pattern(material: str) -> str | None:
    """The object pattern of a part's material: the name itself if in ``OBJECT_PATTERNS``, else
    None (plastic, glass, food, plain, ... are drawn flat)."""
    return material if material in OBJECT_PATTERNS else None

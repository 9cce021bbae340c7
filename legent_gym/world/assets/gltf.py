"""Import glTF 2.0 files (``.gltf`` / ``.glb``) as :class:`AssetModel` assets.

Geometry is read with trimesh; everything else (frame conversion, colours, annotations)
happens here so that an imported asset looks like a built-in one to the scene builder.
The file is checked before anything is converted (the bounds on what it may hold, its
container, the files it refers to, its images) by :mod:`legent_gym.world.assets.gltf_file`.

Frames. glTF is right-handed, +y up, and "the front of a glTF asset faces +z" (glTF 2.0
spec, section 3.4), so the asset's own right-hand side is -x. Our asset frame is z up with
the front facing +y (see :mod:`legent_gym.world.assets.model`), so the asset's right is +x.
The map that sends glTF up to our up and glTF front to our front is

    (x, y, z)_gltf -> (-x, z, y)_ours        [[-1, 0, 0], [0, 0, 1], [0, 1, 0]]

a rotation (determinant +1: a +90 degree turn about x followed by a half turn about z), so
nothing is mirrored and triangle winding (outward normals) is preserved. The naive
(x, -z, y) is also a rotation but turns the model's front toward -y. ``up_axis="z"``
declares a file already authored in our convention (z up, front +y): no rotation.

After the rotation the model is recentred (footprint centred on x = y = 0, lowest point at
z = 0) and, if ``size`` is given, scaled uniformly to fit inside it.

Each (node instance, primitive) becomes one :class:`Part` with ``collision="hull"``: parts
are not merged even when they share a colour, because one convex hull over several pieces
(a table's legs and top) would fill the space between them. The builder merges the visual
parts of a link into one mesh anyway, so the part count does not cost draw calls.

Kept: meshes at every node instance, base colour factors, base colour textures with their
UVs (long sides capped at ``MAX_TEXTURE_SIDE``), vertex colours (averaged: MuJoCo has no
per-vertex colour), BLEND alpha. Dropped: animations (skinned meshes come in their bind
pose), cameras, lights, texture transforms, texture alpha, metallic/roughness, normal and
emissive maps.
"""

from __future__ import annotations

import dataclasses
import math
import re
import warnings
from collections import OrderedDict
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, get_args

import numpy as np

from legent_gym.world.assets import registry
from legent_gym.world.assets.gltf_file import (
    MAX_GLTF_BYTES,
    MAX_GLTF_ITEMS,
    MAX_IMAGES,
    MAX_VERTICES,
    AssetImportError,
    AssetImportWarning,
    read_document,
)
from legent_gym.world.assets.model import AssetModel, Link, Part, Placement, Receptacle

__all__ = [
    "GLTF_TO_ASSET",
    "AssetImportError",
    "AssetImportWarning",
    "MAX_GLTF_BYTES",
    "MAX_GLTF_ITEMS",
    "MAX_IMAGES",
    "MAX_VERTICES",
    "clear_cache",
    "load_gltf",
    "load_imported_asset",
    "scene_asset_model",
    "turned_model",
    "register_gltf",
]

#: glTF (y up, front +z) -> asset frame (z up, front +y); see the module docstring.
GLTF_TO_ASSET = np.array([[-1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]])
assert np.linalg.det(GLTF_TO_ASSET) > 0  # a rotation: the import must never mirror a model

#: Above this many triangles an import warns that the asset will render slowly.
TRIANGLE_WARN_LIMIT = 20_000
#: Longer texture sides are downscaled: MuJoCo keeps every texture in each model's memory.
MAX_TEXTURE_SIDE = 1024
#: Default mass: this density times the bounding-box volume, clipped to ``MASS_RANGE``.
DEFAULT_DENSITY = 200.0  # kg/m^3: a bounding box is mostly air around the real material
MASS_RANGE = (0.05, 50.0)
#: Default ``pickupable``: the largest dimension is below this (metres).
PICKUPABLE_MAX_DIM = 0.5
#: glTF's default material is white (spec, "Default Material"); used when a primitive has no material.
DEFAULT_RGBA = (1.0, 1.0, 1.0, 1.0)
#: Material hints recognised in glTF material names (Part.material).
MATERIAL_HINTS = ("wood", "fabric", "metal", "plastic", "ceramic", "glass", "leather", "stone")
#: Meshes with less surface (m^2) are left out: MuJoCo compiles none under 1e-15 m^2, and a
#: scene may scale an object down by 1e-3 per axis.
MIN_MESH_AREA = 1e-8
#: Parts whose convex hull holds less (m^3) collide through a box: MuJoCo refuses hulls
#: under 1e-15 m^3 ("mesh volume is too small").
MIN_HULL_VOLUME = 1e-9
_MODE_NAMES = {0: "points", 1: "lines", 2: "line loops", 3: "line strips",
               4: "triangles", 5: "triangle strips", 6: "triangle fans"}
_TRIANGLE_MODES = {4, 5}  # trimesh reads these; it skips fans
_CACHE_SIZE = 32




# ---------------------------------------------------------------------------------------
# Public API


def load_gltf(
    path: str | Path,
    *,
    size: Sequence[float] | None = None,
    up_axis: str = "y",
    category: str | None = None,
    names: Sequence[str] | None = None,
    pickupable: bool | None = None,
    mass: float | None = None,
    receptacles: Iterable[Receptacle | Mapping[str, Any]] | None = None,
    placement: str | None = None,
    rooms: Sequence[str] | None = None,
    max_hull_vertices: int = 64,
) -> AssetModel:
    """Import a glTF/GLB file as a one-link :class:`AssetModel` in the asset frame.

    ``size`` is the (x, y, z) box, in metres and in the asset frame, that the model is
    uniformly scaled to fit (the smallest ratio wins, so proportions are kept); ``None``
    keeps the file's metres. ``up_axis`` is ``"y"`` (glTF standard) or ``"z"`` (already in
    our frame). Annotations left as ``None`` get defaults derived from the geometry (see
    :func:`_annotations`). ``max_hull_vertices`` is the cap the builder should give MuJoCo's
    convex hulls (``maxhullvert``); it is validated and part of the cache key, but the
    model has no field to carry it yet.

    Results are cached by (resolved path, file mtime and size, arguments): importing the
    same unchanged file with the same arguments returns the same object, which callers must
    treat as immutable. Raises :class:`AssetImportError` for any bad file or argument.
    """
    path = Path(path)
    opts = _Options.build(path, size=size, up_axis=up_axis, category=category, names=names,
                          pickupable=pickupable, mass=mass, receptacles=receptacles,
                          placement=placement, rooms=rooms, max_hull_vertices=max_hull_vertices)
    key = (*_file_identity(path), opts)
    model = _CACHE.get(key)
    if model is None:
        model = _import(path, opts)
        _CACHE[key] = model
        while len(_CACHE) > _CACHE_SIZE:
            _CACHE.popitem(last=False)
    else:
        _CACHE.move_to_end(key)
    return model


def register_gltf(asset_id: str, path: str | Path, *, replace: bool = False, **kwargs: Any) -> None:
    """Register ``asset_id`` in the asset registry as the model imported from ``path``.

    The file is imported now, so a bad file or argument raises :class:`AssetImportError`
    here rather than when a scene is built. Every variant is the same geometry (an imported
    file has no parameters to randomise), so the factory ignores its generator.
    ``replace=True`` overrides an id that is already registered (as in
    :func:`registry.register`); other keyword arguments go to :func:`load_gltf`.
    """
    model = load_gltf(Path(path).resolve(), **kwargs)
    # A shallow copy under the registered id: registry.make() renames models whose id
    # differs, and the cached model may be shared by several ids.
    named = dataclasses.replace(model, asset_id=asset_id)
    registry.register(asset_id, lambda rng: named, replace=replace)


def load_imported_asset(asset, base_dir: str | Path) -> AssetModel:
    """The model of a scene's :class:`~legent_gym.world.scene.ImportedAsset` entry.

    ``asset.source`` is resolved against ``base_dir`` (the scene file's folder) unless it
    is absolute; a relative source that leads out of ``base_dir`` (through ``..`` or a
    symbolic link) raises :class:`AssetImportError`. The model is named ``asset.id``; the
    import itself is cached as in :func:`load_gltf`. This is what the scene builder calls
    for imported assets.
    """
    path = Path(asset.source)
    if not path.is_absolute():
        base = Path(base_dir).resolve()
        path = base / path
        try:
            inside = path.resolve().is_relative_to(base)
        except (OSError, RuntimeError) as err:  # RuntimeError: a symbolic link loop
            raise AssetImportError(f"{path}: cannot resolve the path: {err}") from err
        if not inside:
            raise AssetImportError(f"{path}: leads out of the scene's folder {base} (to "
                                   f"{path.resolve()}); a scene refers only to files in its own folder")
    given = getattr(asset, "receptacles", None)
    model = load_gltf(path, size=asset.size, up_axis=asset.up_axis, category=asset.category,
                      names=list(asset.names) or None, pickupable=asset.pickupable,
                      mass=asset.mass, placement=getattr(asset, "placement", None),
                      receptacles=None if given is None else [])
    model = turned_model(model, getattr(asset, "yaw", 0))
    if given is not None:
        model = dataclasses.replace(model, receptacles=[
            Receptacle(r.name or f"surface_{i}", tuple(r.center), tuple(r.half_size), r.height,
                       clearance=r.clearance) for i, r in enumerate(given)])
    return model if model.asset_id == asset.id else dataclasses.replace(model, asset_id=asset.id)


def turned_model(model: AssetModel, yaw: float) -> AssetModel:
    """``model`` turned by ``yaw`` degrees about z, its footprint centred again; its
    receptacles turn with it (on a quarter turn; on another turn they are dropped)."""
    if yaw % 360 == 0:
        return model
    t = math.radians(yaw)
    c, s = math.cos(t), math.sin(t)
    rot = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    matrix = np.eye(4)
    matrix[:3, :3] = rot
    links = [dataclasses.replace(link, parts=[p.transformed(matrix) for p in link.parts]) for link in model.links]
    turned = dataclasses.replace(model, links=links, receptacles=[])
    lo, hi = turned.bounds()
    shift = np.eye(4)
    shift[:2, 3] = -(lo[:2] + hi[:2]) / 2
    links = [dataclasses.replace(link, parts=[p.transformed(shift) for p in link.parts]) for link in turned.links]
    receptacles = []
    if yaw % 90 == 0:
        quarter = yaw % 180 == 90
        for r in model.receptacles:
            x, y = rot[:2, :2] @ np.asarray(r.center, dtype=np.float64) + shift[:2, 3]
            half = (r.half_size[1], r.half_size[0]) if quarter else (r.half_size[0], r.half_size[1])
            receptacles.append(dataclasses.replace(r, center=(float(x), float(y)), half_size=half))
    return dataclasses.replace(turned, links=links, receptacles=receptacles)


def scene_asset_model(scene: Any, asset_id: str, variant: int = 0) -> AssetModel:
    """The model of an asset id as a scene uses it: its ``assets`` entry (the import) if it
    declares one, else the registry's."""
    for entry in scene.assets:
        if entry.id == asset_id:  # paths relative to the scene file's folder (a built scene: the cwd)
            return load_imported_asset(entry, scene.base_dir or Path.cwd())
    return registry.make(asset_id, variant)


def clear_cache() -> None:
    """Forget every cached import (the next :func:`load_gltf` re-reads its file)."""
    _CACHE.clear()


_CACHE: OrderedDict[tuple, AssetModel] = OrderedDict()


# ---------------------------------------------------------------------------------------
# Arguments


@dataclass(frozen=True)
class _Options:
    """The import arguments, validated and made hashable (they are part of the cache key)."""

    size: tuple[float, float, float] | None
    up_axis: str
    category: str
    names: tuple[str, ...]
    pickupable: bool | None
    mass: float | None
    receptacles: tuple[tuple, ...] | None  # Receptacle fields, in declaration order
    placement: Placement | None
    rooms: tuple[str, ...]
    max_hull_vertices: int

    @classmethod
    def build(cls, path: Path, *, size, up_axis, category, names, pickupable, mass, receptacles,
              placement, rooms, max_hull_vertices) -> _Options:
        """Validate the arguments of :func:`load_gltf`; errors name the file."""
        if up_axis not in ("y", "z"):
            raise AssetImportError(f"{path}: up_axis must be 'y' or 'z', not {up_axis!r}")
        if category is None:
            category = _category_from_stem(path)
        elif not isinstance(category, str) or not category.strip():
            raise AssetImportError(f"{path}: category must be a non-empty string, not {category!r}")
        if mass is not None and not (_is_number(mass) and math.isfinite(mass) and mass > 0):
            raise AssetImportError(f"{path}: mass must be a positive number, not {mass!r}")
        if pickupable is not None and not isinstance(pickupable, bool | np.bool_):
            raise AssetImportError(f"{path}: pickupable must be True, False or None, not {pickupable!r}")
        if placement is not None and placement not in get_args(Placement):
            raise AssetImportError(f"{path}: placement must be one of {get_args(Placement)}, "
                                   f"not {placement!r}")
        if (isinstance(max_hull_vertices, bool) or not isinstance(max_hull_vertices, int | np.integer)
                or max_hull_vertices < 4):
            # MuJoCo's maxhullvert must exceed 3 (a hull needs a tetrahedron).
            raise AssetImportError(f"{path}: max_hull_vertices must be an integer >= 4, "
                                   f"not {max_hull_vertices!r}")
        return cls(
            size=_validate_size(path, size),
            up_axis=up_axis,
            category=category.strip(),
            names=_string_tuple(path, "names", names),
            pickupable=None if pickupable is None else bool(pickupable),
            mass=None if mass is None else float(mass),
            receptacles=None if receptacles is None else _receptacle_tuples(path, receptacles),
            placement=placement,
            rooms=_string_tuple(path, "rooms", rooms),
            max_hull_vertices=int(max_hull_vertices),
        )


def _is_number(value: Any) -> bool:
    return isinstance(value, int | float | np.integer | np.floating) and not isinstance(value, bool)


def _validate_size(path: Path, size) -> tuple[float, float, float] | None:
    """``size`` as three positive finite floats, or None."""
    if size is None:
        return None
    try:
        values = tuple(float(s) for s in size)
    except (TypeError, ValueError) as err:
        raise AssetImportError(f"{path}: size must be three numbers (x, y, z), not {size!r}") from err
    if len(values) != 3 or not all(math.isfinite(v) and v > 0 for v in values):
        raise AssetImportError(f"{path}: size must be three positive finite numbers (x, y, z), "
                               f"not {size!r}")
    x, y, z = values
    return x, y, z


def _string_tuple(path: Path, what: str, values) -> tuple[str, ...]:
    """A list-of-strings argument as a tuple (None -> empty)."""
    if values is None:
        return ()
    if isinstance(values, str) or not all(isinstance(v, str) and v for v in values):
        raise AssetImportError(f"{path}: {what} must be a list of non-empty strings, not {values!r}")
    return tuple(values)


def _receptacle_tuples(path: Path, receptacles) -> tuple[tuple, ...]:
    """Receptacles (objects or keyword mappings) as hashable field tuples."""
    out = []
    for rec in receptacles:
        try:
            if isinstance(rec, Mapping):
                rec = Receptacle(**rec)
            if not isinstance(rec, Receptacle):
                raise TypeError(f"expected a Receptacle or a mapping, got {type(rec).__name__}")
            out.append((str(rec.name), tuple(float(c) for c in rec.center),
                        tuple(float(h) for h in rec.half_size), float(rec.height), str(rec.link),
                        float(rec.clearance)))
        except (TypeError, ValueError) as err:
            raise AssetImportError(f"{path}: bad receptacle {rec!r}: {err}") from err
    return tuple(out)


def _category_from_stem(path: Path) -> str:
    """The default category: the file name without extension, lower-case, ``_``-separated."""
    category = re.sub(r"[^0-9a-z]+", "_", path.stem.lower()).strip("_")
    return category or "object"


def _file_identity(path: Path) -> tuple[str, int, int]:
    """(resolved path, mtime in ns, size in bytes): what makes a cached import stale."""
    try:
        stat = path.stat()
        resolved = path.resolve()
    except OSError as err:
        raise AssetImportError(f"{path}: cannot read the file: {err.strerror or err}") from err
    if not path.is_file():
        raise AssetImportError(f"{path}: not a file")
    return str(resolved), stat.st_mtime_ns, stat.st_size


# ---------------------------------------------------------------------------------------
# The import


def _import(path: Path, opts: _Options) -> AssetModel:
    """Read, convert and annotate one file (the uncached work of :func:`load_gltf`)."""
    document = read_document(path)
    scene = _load_scene(path)
    parts = _scene_parts(path, scene, document)
    rotation = GLTF_TO_ASSET if opts.up_axis == "y" else np.eye(3)
    parts = [p.transformed(_affine(rotation)) for p in parts]
    parts = _normalise(path, parts, opts.size)
    parts = _assign_collision(path, parts)
    _warn_if_heavy(path, parts)
    return _annotations(path, parts, opts)


def _load_scene(path: Path):
    """The file as a trimesh Scene; any loader failure becomes an AssetImportError."""
    # trimesh takes seconds to import: only when a glTF file is read
    import trimesh

    try:
        # process=False keeps vertices exactly as stored: merging them would weld UV seams.
        return trimesh.load(str(path), force="scene", process=False,
                            resolver=trimesh.resolvers.FilePathResolver(str(path)))
    except Exception as err:  # trimesh raises many types for bad data
        raise AssetImportError(f"{path}: cannot load the glTF data: "
                               f"{type(err).__name__}: {err}") from err


def _scene_parts(path: Path, scene, document: dict) -> list[Part]:
    """One Part per (node instance, triangle primitive), in the file's world frame."""
    # trimesh takes seconds to import: only when a glTF file is read
    import trimesh

    parts: list[Part] = []
    images: dict[int, np.ndarray | None] = {}  # one array per image, shared by its users
    vertices = 0
    try:
        nodes = list(scene.graph.nodes_geometry)
    except Exception as err:  # trimesh resolves the node graph lazily, and raises many types
        raise AssetImportError(f"{path}: the node graph cannot be used: {type(err).__name__}: {err}") from err
    for node in nodes:
        try:
            matrix, geom_name = scene.graph[node]
        except Exception as err:  # e.g. a matrix that is not a rigid transform
            raise AssetImportError(f"{path}: the transform of node {node!r} cannot be used: "
                                   f"{type(err).__name__}: {err}") from err
        mesh = scene.geometry.get(geom_name)
        if not isinstance(mesh, trimesh.Trimesh) or len(mesh.faces) == 0:
            continue  # points and lines have no surface to show or collide with
        vertices += len(mesh.vertices)  # every instance of a mesh is a copy of its vertices
        if vertices > MAX_VERTICES:
            raise AssetImportError(f"{path}: more than {MAX_VERTICES} vertices over its node "
                                   "instances, more than an asset may have (MAX_VERTICES)")
        part = _mesh_part(path, mesh, geom_name, images)
        matrix = np.asarray(matrix, dtype=np.float64)
        if not np.all(np.isfinite(matrix)):
            raise AssetImportError(f"{path}: node {node!r} has a non-finite transform")
        parts.append(part.transformed(matrix))
    if not parts:
        raise AssetImportError(f"{path}: no triangle geometry ({_describe_primitives(document)})")
    return parts


def _describe_primitives(document: dict) -> str:
    """What the file holds instead of triangles, for the no-geometry error."""
    counts: dict[str, int] = {}
    meshes = document.get("meshes")
    for mesh in meshes if isinstance(meshes, list) else []:
        prims = mesh.get("primitives") if isinstance(mesh, dict) else None
        for prim in prims if isinstance(prims, list) else []:
            mode = prim.get("mode", 4) if isinstance(prim, dict) else None
            if not isinstance(mode, int) or isinstance(mode, bool):
                name = f"mode {str(mode)[:20]}"
            elif mode in _TRIANGLE_MODES:
                name = "empty triangles"
            else:
                name = _MODE_NAMES.get(mode, f"mode {mode}")
            counts[name] = counts.get(name, 0) + 1
    if not counts:
        return "the file has no meshes"
    found = ", ".join(f"{n} primitive(s) of {kind}" for kind, n in sorted(counts.items()))
    return f"found {found}; only triangle primitives can be imported"


def _mesh_part(path: Path, mesh, name: str, images: dict[int, np.ndarray | None]) -> Part:
    """A Part (untransformed) from one trimesh primitive, with its colour or texture."""
    vertices = np.asarray(mesh.vertices, dtype=np.float64)
    faces = np.asarray(mesh.faces, dtype=np.int64)
    if vertices.ndim != 2 or vertices.shape[1] != 3 or faces.ndim != 2 or faces.shape[1] != 3:
        raise AssetImportError(f"{path}: mesh {name!r} has vertex positions or triangles of the wrong shape "
                               f"(positions {vertices.shape}, triangles {faces.shape}; a POSITION accessor "
                               "that is not VEC3?)")
    if not np.all(np.isfinite(vertices)):
        raise AssetImportError(f"{path}: mesh {name!r} has non-finite vertex coordinates (NaN or inf)")
    if faces.size and (faces.min() < 0 or faces.max() >= len(vertices)):
        raise AssetImportError(f"{path}: mesh {name!r} has face indices out of range")
    rgba, uv, texture, material = _appearance(path, mesh, name, images)
    if 0 < len(vertices) < 4:
        # MuJoCo compiles no mesh of fewer than four vertices ("at least 4 vertices
        # required"), not even a visual one: add the centroid, used by no triangle, so the
        # mesh compiles and looks, bounds and triangle count stay the same.
        vertices = np.concatenate([vertices, vertices.mean(axis=0, keepdims=True)])
        if uv is not None:
            uv = np.concatenate([uv, uv.mean(axis=0, keepdims=True)])
    return Part(vertices, faces, rgba, "hull", uv=uv, texture=texture, material=material)


def _appearance(path: Path, mesh, name: str, images: dict[int, np.ndarray | None]):
    """(rgba, uv, texture, material hint) of a primitive.

    glTF multiplies base colour factor, base colour texture and COLOR_0. A texture is kept
    with its UVs; MuJoCo has no per-vertex colour, so vertex colours are averaged into the
    rgba (weighted by triangle area, so dense regions do not dominate).
    """
    # trimesh takes seconds to import: only when a glTF file is read
    from trimesh.visual.color import ColorVisuals
    from trimesh.visual.texture import TextureVisuals

    visual = mesh.visual
    rgba = np.array(DEFAULT_RGBA)
    uv = texture = None
    hint = "plain"
    colours, per_vertex = None, True  # (N, 4) per-vertex or (M, 4) per-face colours
    if isinstance(visual, TextureVisuals):
        material = visual.material
        if material is not None:
            pbr = material if hasattr(material, "baseColorFactor") else material.to_pbr()
            rgba = _factor_rgba(pbr)
            hint = _material_hint(getattr(pbr, "name", None))
            image = getattr(pbr, "baseColorTexture", None)
            texture = None if image is None else _texture_array(path, image, name, images)
            if texture is not None:
                uv = _valid_uv(visual.uv, len(mesh.vertices))
                if uv is None:  # a texture without UVs cannot be mapped: use its mean colour
                    rgba[:3] *= texture.reshape(-1, 3).mean(axis=0) / 255.0
                    texture = None
        colours = visual.vertex_attributes.get("color") if visual.vertex_attributes else None
    elif isinstance(visual, ColorVisuals) and visual.kind == "vertex":
        colours = visual.vertex_colors
    elif isinstance(visual, ColorVisuals) and visual.kind == "face":
        colours, per_vertex = visual.face_colors, False
    expected_rows = len(mesh.vertices) if per_vertex else len(mesh.faces)
    if colours is not None and len(colours) == expected_rows:
        rgba[:3] *= _mean_colour(mesh, np.asarray(colours), per_vertex)
    # glTF: "the alpha value is ignored" for OPAQUE (the default) and MASK is a cut-out.
    return tuple(float(c) for c in np.clip(rgba, 0.0, 1.0)), uv, texture, hint


def _factor_rgba(pbr) -> np.ndarray:
    """The base colour factor as floats in [0, 1]; alpha only counts for BLEND."""
    factor = getattr(pbr, "baseColorFactor", None)
    if factor is None:
        return np.array(DEFAULT_RGBA)
    values = np.asarray(factor).reshape(-1)[:4]
    scale = 255.0 if np.issubdtype(values.dtype, np.integer) else 1.0  # trimesh uses uint8
    rgba = np.ones(4)
    rgba[:len(values)] = values / scale
    if getattr(pbr, "alphaMode", None) != "BLEND":
        rgba[3] = 1.0
    return rgba


def _material_hint(name: str | None) -> str:
    """A Part.material style hint guessed from the glTF material name ("plain" if none)."""
    lowered = name.lower() if isinstance(name, str) else ""  # a corrupt file may give any type
    return next((hint for hint in MATERIAL_HINTS if hint in lowered), "plain")


def _texture_array(path: Path, image, name: str,
                   images: dict[int, np.ndarray | None]) -> np.ndarray | None:
    """A PIL image as (H, W, 3) uint8 (alpha dropped, long sides capped), decoded once.

    None (with a warning) if the image does not decode: the part keeps its base colour.
    """
    if id(image) in images:
        return images[id(image)]
    # start-up time: only for a textured glTF
    from PIL import Image

    try:
        rgb = image.convert("RGB")  # palette, grey and RGBA images all become RGB
        if max(rgb.size) > MAX_TEXTURE_SIDE:
            scale = MAX_TEXTURE_SIDE / max(rgb.size)
            rgb = rgb.resize((max(1, round(rgb.width * scale)), max(1, round(rgb.height * scale))),
                             Image.Resampling.LANCZOS)
        array = np.ascontiguousarray(np.asarray(rgb, dtype=np.uint8))
    except Exception as err:  # PIL raises OSError, ValueError, SyntaxError... on bad data
        warnings.warn(f"{path}: the texture of mesh {name!r} cannot be decoded "
                      f"({type(err).__name__}: {err}); it keeps only its base colour",
                      AssetImportWarning, stacklevel=2)
        array = None
    images[id(image)] = array
    return array


def _valid_uv(uv, n_vertices: int) -> np.ndarray | None:
    """The primitive's texture coordinates, or None if missing or unusable.

    glTF puts the UV origin at the image's top-left (v grows downward); Part.uv, like
    OpenGL and OBJ, has v pointing up, i.e. v_part = 1 - v_gltf. trimesh's glTF loader
    already applies exactly that flip, so its UVs are used unchanged; flipping again here
    would turn every texture upside down. (MuJoCo, given texture data top row first as
    Part.texture is, samples v = 0 at the top row, like glTF: a MuJoCo mesh made from a
    Part needs texcoord v = 1 - Part.uv v, or the image rows flipped.)
    """
    if uv is None:
        return None
    uv = np.asarray(uv, dtype=np.float64)
    if uv.ndim != 2 or uv.shape != (n_vertices, 2) or not np.all(np.isfinite(uv)):
        return None
    return uv.copy()


def _mean_colour(mesh, colours: np.ndarray, per_vertex: bool) -> np.ndarray:
    """Area-weighted mean RGB (in [0, 1]) of per-vertex or per-face colours."""
    faces = np.asarray(mesh.faces)
    rgb = colours[:, :3].astype(np.float64)
    if np.issubdtype(colours.dtype, np.integer):  # normalised integers (uint8 or uint16)
        rgb = rgb / float(np.iinfo(colours.dtype).max)
    per_face = rgb[faces].mean(axis=1) if per_vertex else rgb
    weights = _face_areas(np.asarray(mesh.vertices, dtype=np.float64), faces)
    if weights.sum() <= 0:
        weights = np.ones(len(faces))
    return (per_face * weights[:, None]).sum(axis=0) / weights.sum()


def _face_areas(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    tri = vertices[faces]
    return 0.5 * np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1)


def _affine(rotation: np.ndarray, translation=(0.0, 0.0, 0.0), scale: float = 1.0) -> np.ndarray:
    """The 4x4 transform x -> scale * (rotation @ x + translation)."""
    matrix = np.eye(4)
    matrix[:3, :3] = scale * rotation
    matrix[:3, 3] = scale * np.asarray(translation, dtype=np.float64)
    return matrix


def _bounds(parts: list[Part]) -> np.ndarray:
    allv = np.concatenate([p.vertices for p in parts])
    return np.stack([allv.min(axis=0), allv.max(axis=0)])


def _normalise(path: Path, parts: list[Part], size) -> list[Part]:
    """Recentre (footprint centred at x = y = 0, min z = 0) and scale to fit ``size``."""
    bounds = _bounds(parts)
    if not np.all(np.isfinite(bounds)):
        raise AssetImportError(f"{path}: non-finite vertex coordinates after the node transforms")
    extent = bounds[1] - bounds[0]
    if extent.max() <= 1e-9:
        raise AssetImportError(f"{path}: zero-size bounds (all vertices are at one point)")
    if sum(_face_areas(p.vertices, p.faces).sum() for p in parts) <= 0:
        raise AssetImportError(f"{path}: every triangle has zero area")
    scale = 1.0
    if size is not None:
        # Only axes with extent constrain the scale: a flat model fits any thickness.
        usable = extent > 1e-9 * extent.max()
        scale = float(np.min(np.asarray(size)[usable] / extent[usable]))
    # MuJoCo compiles no mesh of (almost) no area ("mesh surface area is too small").
    areas = [float(_face_areas(p.vertices, p.faces).sum()) * scale**2 for p in parts]
    if max(areas) < MIN_MESH_AREA:
        raise AssetImportError(f"{path}: the model is too small to build: its largest mesh has "
                               f"{max(areas):.3g} m^2 of surface, under the {MIN_MESH_AREA:g} m^2 MuJoCo can "
                               "compile (are its units metres? give it a size)")
    small = sum(a < MIN_MESH_AREA for a in areas)
    if small:
        warnings.warn(f"{path}: {small} mesh(es) with (almost) no surface area are left out",
                      AssetImportWarning, stacklevel=4)
        parts = [p for p, a in zip(parts, areas) if a >= MIN_MESH_AREA]
        bounds = _bounds(parts)
    centre = bounds.mean(axis=0)
    offset = (-centre[0], -centre[1], -bounds[0][2])
    matrix = _affine(np.eye(3), offset, scale)
    return [p.transformed(matrix) for p in parts]


def _assign_collision(path: Path, parts: list[Part]) -> list[Part]:
    """``collision="hull"`` for solid parts, ``"box"`` for flat ones.

    MuJoCo refuses to build a convex hull from coplanar vertices ("mesh has coplanar
    vertices, cannot compute convex hull"), from fewer than four or from points enclosing
    no volume, so a flat part (a single quad or triangle, a decal) keeps its visual mesh
    and collides through its bounding box, which the builder grows to a thin slab (see
    :func:`legent_gym.world.meshing.link_geometry`). A warning says so.
    """
    out = [dataclasses.replace(p, collision="box" if _is_flat(p.vertices) else "hull") for p in parts]
    flat = sum(p.collision == "box" for p in out)
    out = [dataclasses.replace(p, collision="box") if p.collision == "hull" and _hull_volume(p.vertices)
           < MIN_HULL_VOLUME else p for p in out]
    thin = sum(p.collision == "box" for p in out) - flat
    if flat or thin:
        if flat == len(out):
            which = "the model is flat (all its vertices are coplanar)"
        elif thin == len(out):
            which = f"the model encloses almost no volume (under {MIN_HULL_VOLUME:g} m^3)"
        else:
            which = f"{flat + thin} of its {len(out)} meshes are flat or enclose almost no volume"
        warnings.warn(f"{path}: {which}, so MuJoCo cannot make a convex hull of it; it collides "
                      "through a thin box from its bounds", AssetImportWarning, stacklevel=4)
    return out


def _hull_volume(vertices: np.ndarray) -> float:
    """The volume of the points' convex hull (0 where qhull finds none)."""
    # start-up time: only when a glTF's hull is measured
    from scipy.spatial import ConvexHull, QhullError

    try:
        return float(ConvexHull(vertices).volume)
    except (QhullError, ValueError):
        return 0.0


def _is_flat(vertices: np.ndarray) -> bool:
    """True if the points span less than three dimensions (relative tolerance 1e-6)."""
    if len(vertices) < 4:
        return True
    centred = vertices - vertices.mean(axis=0)
    extent = float(np.abs(centred).max())
    if not extent > 0:
        return True
    centred = centred / extent  # the test is scale-free; unscaled, huge coordinates overflow
    try:
        singular = np.linalg.svd(centred.T @ centred, compute_uv=False)  # 3x3: cheap for any N
    except np.linalg.LinAlgError:
        return True
    return bool(np.sqrt(singular[-1]) <= 1e-6 * np.sqrt(singular[0]))


def _warn_if_heavy(path: Path, parts: list[Part]) -> None:
    """Warn when the triangle count will make rendering slow (no simplification is done)."""
    count = sum(len(p.faces) for p in parts)
    if count > TRIANGLE_WARN_LIMIT:
        warnings.warn(f"{path}: {count} triangles (more than {TRIANGLE_WARN_LIMIT}); this asset "
                      "will render slowly, consider a decimated version", AssetImportWarning,
                      stacklevel=4)


# ---------------------------------------------------------------------------------------
# Annotations


def _annotations(path: Path, parts: list[Part], opts: _Options) -> AssetModel:
    """Wrap the parts in a one-link model, filling unset annotations from the geometry.

    Defaults: ``pickupable`` if the largest dimension is under 0.5 m; ``mass`` is
    200 kg/m^3 times the bounding-box volume, clipped to [0.05, 50] kg; ``placement`` is
    "surface" for pickupable things and "wall" otherwise; receptacles: see
    :func:`_top_receptacle` (non-pickupable assets only).
    """
    size = _bounds(parts)[1] - _bounds(parts)[0]
    pickupable = bool(size.max() < PICKUPABLE_MAX_DIM) if opts.pickupable is None else opts.pickupable
    mass = opts.mass
    if mass is None:
        mass = float(np.clip(DEFAULT_DENSITY * np.prod(size), *MASS_RANGE))
    placement: Placement = opts.placement or ("surface" if pickupable else "wall")
    if opts.receptacles is not None:
        receptacles = [Receptacle(*fields) for fields in opts.receptacles]
    else:
        top = None if pickupable else _top_receptacle(parts)
        receptacles = [] if top is None else [top]
    return AssetModel(
        asset_id=_category_from_stem(path),
        category=opts.category,
        links=[Link("base", parts)],
        names=list(opts.names),  # empty -> AssetModel's default, the category in words
        receptacles=receptacles,
        pickupable=pickupable,
        mass=mass,
        rooms=list(opts.rooms),
        placement=placement,
    )


#: Receptacle rule constants: faces within ~18 degrees of horizontal, 1 cm height bins.
_UP_COS = 0.95
_HEIGHT_BIN = 0.01
_MIN_TOP_FRACTION = 0.4  # of the footprint (bounding rectangle) area
_MIN_TOP_AREA = 0.04  # m^2: a 20 x 20 cm surface
_TOP_MARGIN = 0.02  # m kept free along each edge so placed things do not overhang


def _top_receptacle(parts: list[Part]) -> Receptacle | None:
    """A receptacle on the highest large flat surface, or None.

    Upward-facing triangles (normal within ~18 degrees of +z) are binned by height in
    1 cm steps; the highest bin whose area is at least 40% of the footprint and 0.04 m^2
    is the top (so a vase modelled on a table does not hide the table top). The receptacle
    is that surface's bounding rectangle shrunk by 2 cm per side.
    """
    verts = np.concatenate([p.vertices for p in parts])
    offsets = np.cumsum([0] + [len(p.vertices) for p in parts[:-1]])
    faces = np.concatenate([p.faces + o for p, o in zip(parts, offsets)])
    tri = verts[faces]
    normal = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    length = np.linalg.norm(normal, axis=1)
    z_range = np.ptp(tri[:, :, 2], axis=1)
    up = (length > 0) & (normal[:, 2] > _UP_COS * length) & (z_range < _HEIGHT_BIN)
    if not up.any():
        return None
    area = 0.5 * length[up]
    level = np.round(tri[up, :, 2].mean(axis=1) / _HEIGHT_BIN).astype(np.int64)
    footprint = np.ptp(verts[:, 0]) * np.ptp(verts[:, 1])
    for bin_level in np.unique(level)[::-1]:
        in_bin = level == bin_level
        if area[in_bin].sum() < max(_MIN_TOP_AREA, _MIN_TOP_FRACTION * footprint):
            continue
        pts = tri[up][in_bin].reshape(-1, 3)
        lo, hi = pts[:, :2].min(axis=0), pts[:, :2].max(axis=0)
        half = np.maximum((hi - lo) / 2.0 - _TOP_MARGIN, 0.01)
        centre = (lo + hi) / 2.0
        return Receptacle("top", (float(centre[0]), float(centre[1])),
                          (float(half[0]), float(half[1])), float(pts[:, 2].max()))
    return None

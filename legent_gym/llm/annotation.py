"""Annotate an imported glTF/GLB asset: geometric fields computed, semantic fields from a VLM.

``legent-gym asset annotate model.glb [--llm-base-url URL --model M] [--out asset.json]``
(:func:`annotate_asset`):

* **geometry** (:class:`Geometry`, never asked): the stable up axis (glTF's ``y`` unless
  the model does not stand on its base that way and does with ``z``), the size from the
  bounds (metres, our frame: x right, y front, z up), and the placeable surfaces: rays cast
  straight down on a 5 cm grid over the footprint, each grid point keeping the first
  surface it meets when that faces up; hits grouped by height in 1 cm bins; a group of at
  least 0.04 m^2 above 2 cm becomes a surface (its bounding rectangle, 2 cm in from each
  side);
* **semantics** (:class:`Semantics`, objathor's fields): a VLM is shown four renders of the
  asset (cameras at 0, 90, 180 and 270 degrees around it, view 0 facing the glTF front) and
  answers with name, category, description, pickable, receptacle, on floor / wall /
  object, materials, mass in kg and the view that shows the front; the asset is turned so
  that this front faces our +y (``yaw``), and the surfaces are cast on the turned model.

Annotations are cached by the file's SHA-256 (``cache_dir``/``<sha256>.json``): an
annotation with semantics is reused as it is. Without an endpoint only the geometry is
written and ``missing`` lists the semantic fields.

:func:`register_annotation` registers an annotated asset in the asset registry under its
category, with its names, pickable, mass, placement (``on_object``: surface; ``on_wall``:
wall; else a floor piece against a wall) and receptacles (the surfaces, if the VLM says it
is a receptacle): the generator (a plan's ``asset``) and the tasks then use it like a
built-in asset. The model is the one that the scene ``assets`` entry of
:func:`imported_asset` builds; the registry keeps that entry and the plan solver writes it
into the scenes that use the asset, so a saved scene builds it in any process with nothing
registered.
"""

from __future__ import annotations

import base64
import hashlib
import io
import json
import math
import os
from pathlib import Path
from typing import Any, Literal

import numpy as np
from PIL import Image
from pydantic import BaseModel, ConfigDict, Field, ValidationError, field_validator

from legent_gym.errors import UserError
from legent_gym.llm.client import ChatClient, LLMError, describe_error
from legent_gym.llm.prompts import ANNOTATION_PROMPT
from legent_gym.utils.atomic import atomic_write_text
from legent_gym.world.assets import registry
from legent_gym.world.assets.gltf import load_gltf, load_imported_asset, turned_model
from legent_gym.world.builder import build_world
from legent_gym.world.preview import preview_scene
from legent_gym.world.render import FreeCamera, Renderer
from legent_gym.world.scene import ImportedAsset, ImportedSurface

ANNOTATION_VERSION = 1
#: Spacing of the downward rays that find placeable surfaces (metres).
SURFACE_GRID = 0.05
#: Hits are grouped by height in bins of this size (metres).
SURFACE_BIN = 0.01
#: A surface has at least this area (m^2) and lies above this height (metres).
MIN_SURFACE_AREA = 0.04
MIN_SURFACE_HEIGHT = 0.02
#: Kept free along each side of a surface (metres).
SURFACE_MARGIN = 0.02
#: The renders' yaws around the asset (degrees); view 0 faces the asset's glTF front.
VIEW_YAWS = (0, 90, 180, 270)
#: The semantic fields the VLM fills.
SEMANTIC_FIELDS = ("name", "category", "description", "pickable", "receptacle", "on_floor", "on_wall",
                   "on_object", "materials", "mass", "front_view")


class Surface(BaseModel):
    """A placeable rectangle: centre (x, y), half extents, height of the surface (metres)."""

    center: tuple[float, float]
    half_size: tuple[float, float]
    height: float


class Geometry(BaseModel):
    up_axis: Literal["y", "z"]
    stable: bool
    size: tuple[float, float, float]
    surfaces: list[Surface]


class Semantics(BaseModel):
    """What the VLM says of the asset (objathor's fields; ``pickable`` is asked)."""

    model_config = ConfigDict(extra="ignore")

    name: str = Field(min_length=1, max_length=80)
    category: str = Field(min_length=1, max_length=60)
    description: str = Field(min_length=1, max_length=1000)
    pickable: bool
    receptacle: bool
    on_floor: bool
    on_wall: bool
    on_object: bool
    materials: list[str] = Field(max_length=12)
    mass: float = Field(gt=0, le=5000)
    front_view: int = Field(ge=0, le=3)

    @field_validator("category")
    @classmethod
    def _snake(cls, value: str) -> str:
        out = "_".join(value.strip().lower().replace("-", " ").split())
        if not out.replace("_", "").isalnum():
            raise ValueError(f"a category is words, got {value!r}")
        return out


class AssetAnnotation(BaseModel):
    version: int = ANNOTATION_VERSION
    source: str
    sha256: str
    geometry: Geometry
    semantics: Semantics | None = None
    yaw: float = 0.0  # degrees turned about z so that the front faces +y
    missing: list[str] = Field(default_factory=list)


# -- geometry ------------------------------------------------------------------------------


def file_sha256(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def _triangles(model: Any) -> np.ndarray:
    tris = [p.vertices[p.faces] + np.asarray(link.pos) for link in model.links for p in link.parts]
    return np.concatenate(tris) if tris else np.zeros((0, 3, 3))


def stands(model: Any) -> bool:
    """The centre of the bounds is over the hull of the points within 1 cm of the bottom
    (approximated by their bounding rectangle, 10% in from each side)."""
    pts = np.concatenate([p.vertices for link in model.links for p in link.parts])
    low = pts[pts[:, 2] <= pts[:, 2].min() + 0.01][:, :2]
    lo, hi = low.min(axis=0), low.max(axis=0)
    span = hi - lo
    if min(span) < 1e-3:
        return False
    centre = (pts.min(axis=0)[:2] + pts.max(axis=0)[:2]) / 2
    return bool(np.all(centre >= lo + 0.1 * span) and np.all(centre <= hi - 0.1 * span))


def placeable_surfaces(model: Any) -> list[Surface]:
    """The model's placeable surfaces by rays cast down on a 5 cm grid (module docstring)."""
    tri = _triangles(model)
    if not len(tri):
        return []
    lo, hi = tri.reshape(-1, 3).min(axis=0), tri.reshape(-1, 3).max(axis=0)
    xs = np.arange(lo[0] + SURFACE_GRID / 2, hi[0], SURFACE_GRID)
    ys = np.arange(lo[1] + SURFACE_GRID / 2, hi[1], SURFACE_GRID)
    if not len(xs) or not len(ys):
        return []
    gx, gy = np.meshgrid(xs, ys, indexing="ij")
    points = np.stack([gx.ravel(), gy.ravel()], axis=1)
    a, b, c = tri[:, 0], tri[:, 1], tri[:, 2]
    normal = np.cross(b - a, c - a)
    length = np.linalg.norm(normal, axis=1)
    keep = length > 1e-12
    a, b, c, normal, length = a[keep], b[keep], c[keep], normal[keep], length[keep]
    with np.errstate(divide="ignore", invalid="ignore"):
        return _surfaces(points, lo, a, b, c, normal, length)


def _surfaces(points: np.ndarray, lo: np.ndarray, a: np.ndarray, b: np.ndarray, c: np.ndarray,
              normal: np.ndarray, length: np.ndarray) -> list[Surface]:
    top = np.full(len(points), -np.inf)
    up = np.zeros(len(points), dtype=bool)
    for start in range(0, len(points), 256):  # points x triangles, in chunks
        p = points[start:start + 256, None, :]
        v0, v1, v2 = (b - a)[None, :, :2], (c - a)[None, :, :2], p - a[None, :, :2]
        d00, d01, d11 = (v0 * v0).sum(-1), (v0 * v1).sum(-1), (v1 * v1).sum(-1)
        d20, d21 = (v2 * v0).sum(-1), (v2 * v1).sum(-1)
        den = d00 * d11 - d01 * d01
        v = (d11 * d20 - d01 * d21) / den
        w = (d00 * d21 - d01 * d20) / den
        u = 1 - v - w
        inside = (np.abs(den) > 1e-14) & (u >= -1e-9) & (v >= -1e-9) & (w >= -1e-9)
        z = np.where(inside, a[None, :, 2] + v * (b - a)[None, :, 2] + w * (c - a)[None, :, 2], -np.inf)
        first = z.argmax(axis=1)
        top[start:start + 256] = z[np.arange(len(first)), first]
        up[start:start + 256] = normal[first, 2] > 0.95 * length[first]
    hit = np.isfinite(top) & up & (top > lo[2] + MIN_SURFACE_HEIGHT)
    out = []
    cell = SURFACE_GRID ** 2
    levels = np.round(top[hit] / SURFACE_BIN).astype(np.int64)
    for level in np.unique(levels)[::-1]:
        pts = points[hit][levels == level]
        if len(pts) * cell < MIN_SURFACE_AREA:
            continue
        p_lo, p_hi = pts.min(axis=0) - SURFACE_GRID / 2, pts.max(axis=0) + SURFACE_GRID / 2
        half = np.maximum((p_hi - p_lo) / 2 - SURFACE_MARGIN, 0.01)
        centre = (p_lo + p_hi) / 2
        out.append(Surface(center=(_r(centre[0]), _r(centre[1])), half_size=(_r(half[0]), _r(half[1])),
                           height=_r(top[hit][levels == level].max())))
    return out


def _r(value: float) -> float:
    return round(float(value), 4) + 0.0  # + 0.0: no -0.0


def import_model(path: Path, up_axis: str = "y", semantics: Semantics | None = None, yaw: float = 0.0) -> Any:
    """The asset as imported with these annotations and turned by ``yaw``."""
    kwargs: dict[str, Any] = {}
    if semantics is not None:
        placement = "surface" if semantics.on_object else "wall"
        kwargs = {"category": semantics.category, "names": [semantics.name.lower()],
                  "pickupable": semantics.pickable, "mass": semantics.mass, "placement": placement}
    return turned_model(load_gltf(path, up_axis=up_axis, receptacles=[], **kwargs), yaw)


def geometry_of(path: Path, yaw: float = 0.0) -> Geometry:
    up_axis, stable = "y", True
    model = import_model(path, "y")
    if not stands(model):
        other = import_model(path, "z")
        up_axis, stable = ("z", True) if stands(other) else ("y", False)
    model = import_model(path, up_axis, yaw=yaw)
    lo, hi = model.bounds()
    size = tuple(_r(v) for v in hi - lo)
    return Geometry(up_axis=up_axis, stable=stable, size=size, surfaces=placeable_surfaces(model))  # type: ignore[arg-type]


# -- views and the VLM -----------------------------------------------------------------------


def render_views(path: Path, up_axis: str, size: int = 256) -> list[np.ndarray]:
    """Four renders of the asset on a bare floor, from cameras at :data:`VIEW_YAWS` around it
    (view 0 in front of it)."""
    imported = ImportedAsset(id="annotated", source=str(path.resolve()), up_axis=up_axis)  # type: ignore[arg-type]
    world = build_world(preview_scene("annotated", imported=imported, base_dir=path.parent, kind="static"))
    lo, hi = world.assets[0].bounds()
    centre = world.object_position(0) + (lo + hi) / 2
    distance = max(float(np.linalg.norm(hi - lo)) / 2 / math.tan(math.radians(22.5)) * 1.15, 0.3)
    renderer = Renderer(world, size, size, "pretty")
    try:
        # MuJoCo's azimuth 270 looks along -y: from in front of the asset (its front faces +y).
        return [renderer.rgb(FreeCamera(tuple(centre), distance, azimuth=(270.0 + yaw) % 360, elevation=-20.0))
                for yaw in VIEW_YAWS]
    finally:
        renderer.close()


def png_data_url(image: np.ndarray) -> str:
    buffer = io.BytesIO()
    Image.fromarray(image).save(buffer, format="PNG")
    return "data:image/png;base64," + base64.b64encode(buffer.getvalue()).decode()


def ask_semantics(client: Any, views: list[np.ndarray], geometry: Geometry) -> Semantics:
    """The VLM's :class:`Semantics` of the asset shown in ``views``."""
    text = ANNOTATION_PROMPT.format(x=geometry.size[0], y=geometry.size[1], z=geometry.size[2])
    content: list[dict[str, Any]] = [{"type": "text", "text": text}]
    for index, image in enumerate(views):
        content.append({"type": "text", "text": f"View {index}:"})
        content.append({"type": "image_url", "image_url": {"url": png_data_url(image)}})
    semantics, _ = client.complete_model([{"role": "user", "content": content}], Semantics, max_tokens=1024)
    return semantics


# -- the whole ---------------------------------------------------------------------------------


def annotate_asset(path: str | Path, client: Any = None, cache_dir: str | Path | None = None) -> AssetAnnotation:
    """The annotation of the glTF/GLB file at ``path`` (see the module docstring); a cached
    one with semantics when ``cache_dir`` holds it."""
    path = Path(path)
    sha = file_sha256(path)
    cached = None if cache_dir is None else Path(cache_dir) / f"{sha}.json"
    if cached is not None and cached.exists():
        try:
            known = AssetAnnotation.model_validate_json(cached.read_text(encoding="utf-8"))
        except ValueError:
            known = None
        if known is not None and known.semantics is not None and known.version == ANNOTATION_VERSION:
            return known.model_copy(update={"source": str(path)})
    geometry = geometry_of(path)
    semantics, yaw = None, 0.0
    if client is not None:
        semantics = ask_semantics(client, render_views(path, geometry.up_axis), geometry)
        yaw = float((-90 * semantics.front_view) % 360)
        if yaw:
            geometry = geometry_of(path, yaw)
    annotation = AssetAnnotation(source=str(path), sha256=sha, geometry=geometry, semantics=semantics, yaw=yaw,
                                 missing=[] if semantics is not None else list(SEMANTIC_FIELDS))
    if cached is not None:
        cached.parent.mkdir(parents=True, exist_ok=True)
        atomic_write_text(cached, annotation.model_dump_json(indent=1) + "\n")
    return annotation


def register_annotation(annotation: AssetAnnotation | str | Path, asset_id: str | None = None,
                        *, replace: bool = False) -> str:
    """Register an annotated asset (an annotation, or its JSON file, whose ``source`` is
    resolved against the file's folder) under ``asset_id`` (default: its category); returns
    the id. Without semantics the asset keeps the importer's defaults (category from the
    file name). The model is the one a scene's ``assets`` entry from
    :func:`imported_asset` builds, and the registry keeps that entry: a generator that
    places the asset writes it into the scene, so the scene rebuilds it in any process."""
    base = Path.cwd()
    if not isinstance(annotation, AssetAnnotation):
        file = Path(annotation)
        annotation = AssetAnnotation.model_validate_json(file.read_text(encoding="utf-8"))
        base = file.parent
    source = Path(annotation.source)
    path = (source if source.is_absolute() else base / source).resolve()
    entry = imported_asset(annotation, path, asset_id)
    model = load_imported_asset(entry, path.parent)
    registry.register(entry.id, lambda rng: model, replace=replace, imported=entry)
    return entry.id


def imported_asset(annotation: AssetAnnotation, path: Path, asset_id: str | None = None) -> Any:
    """The scene ``assets`` entry (:class:`~legent_gym.world.scene.ImportedAsset`, with the
    absolute ``path`` as its source) that builds an annotated asset: up axis, turn, size
    (the file's own, before the turn), category, names, pickable, mass, placement
    (``on_object``: surface; else wall) and the surfaces as receptacles (those of a
    receptacle; without semantics, of a thing that is not pickable)."""
    semantics = annotation.semantics
    up = annotation.geometry.up_axis
    kwargs: dict[str, Any] = {}
    if semantics is not None:
        kwargs = {"category": semantics.category, "names": [semantics.name.lower()],
                  "pickupable": semantics.pickable, "mass": semantics.mass,
                  "placement": "surface" if semantics.on_object else "wall"}
    plain = load_gltf(path, up_axis=up, receptacles=[], **kwargs)
    lo, hi = plain.bounds()
    receptacle = semantics.receptacle if semantics is not None else not plain.pickupable
    surfaces = [ImportedSurface(name=f"surface_{i}", center=s.center, half_size=s.half_size, height=s.height)
                for i, s in enumerate(annotation.geometry.surfaces)] if receptacle else []
    return ImportedAsset(id=asset_id or plain.category, source=str(path), size=(float(hi[0] - lo[0]), float(hi[1] - lo[1]), float(hi[2] - lo[2])),
                         up_axis=up, category=plain.category, names=list(kwargs.get("names", [])),
                         pickupable=plain.pickupable, mass=plain.mass, yaw=int(round(annotation.yaw)) % 360,
                         placement=plain.placement, receptacles=surfaces)


def write_annotation(annotation: AssetAnnotation, out: str | Path) -> None:
    atomic_write_text(Path(out), json.dumps(annotation.model_dump(mode="json"), indent=1) + "\n")


def default_cache_dir() -> Path:
    """``$XDG_CACHE_HOME/legent-gym/annotations`` (``~/.cache`` without it)."""
    return Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "legent-gym" / "annotations"


def annotate_command(args: Any) -> int:
    """``legent-gym asset annotate`` (``args`` from the CLI); problems a user can cause raise
    :class:`~legent_gym.errors.UserError` with one line."""
    path = Path(args.asset)
    if not path.is_file():
        raise UserError(f"{path}: no such file")
    if path.suffix.lower() not in (".glb", ".gltf"):
        raise UserError(f"{path}: not a .glb or .gltf file")
    out = Path(args.out) if args.out else path.with_name(path.stem + ".asset.json")
    client = None
    if args.model:
        try:
            client = ChatClient(args.llm_base_url, model=args.model, timeout=args.timeout, max_retries=args.retries,
                                backoff=1.0, max_backoff=10.0)
        except ValueError as err:
            raise UserError(str(err)) from None
    elif args.llm_base_url:
        raise UserError("--llm-base-url needs --model (the VLM's name)")
    try:
        annotation = annotate_asset(path, client, args.cache_dir or default_cache_dir())
    except LLMError as err:
        raise UserError(str(err)) from None
    # The source as seen from the annotation's folder, so that the pair can move together.
    source = os.path.relpath(path.resolve(), out.resolve().parent)
    write_annotation(annotation.model_copy(update={"source": source}), out)
    g = annotation.geometry
    print(f"geometry: up {g.up_axis}{'' if g.stable else ' (does not stand stably)'}, size "
          f"{g.size[0]:.2f} x {g.size[1]:.2f} x {g.size[2]:.2f} m, {len(g.surfaces)} placeable surface(s)")
    if annotation.semantics is None:
        print(f"missing: {', '.join(annotation.missing)} (no VLM: give --llm-base-url and --model)")
    else:
        s = annotation.semantics
        print(f"semantics: {s.name} ({s.category}), front in view {s.front_view} (turned {annotation.yaw:g} deg)")
    print(f"wrote {out}")
    return 0


def register_annotation_files(paths: list[str] | None) -> list[str]:
    """``--asset FILE.asset.json`` of the CLI: register each annotated asset; a file that is
    not an annotation raises :class:`~legent_gym.errors.UserError` naming it."""
    ids = []
    for path in paths or []:
        try:
            ids.append(register_annotation(path, replace=True))
        except OSError as err:
            raise UserError(f"{path}: {err.strerror or err}") from None
        except ValidationError as err:
            raise UserError(f"{path}: not an asset annotation: {describe_error(err)}") from None
    return ids

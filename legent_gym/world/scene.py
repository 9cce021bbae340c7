"""The scene format: a house written down as versioned JSON.

A scene is plain data. The builder (:mod:`legent_gym.world.builder`) turns it into a MuJoCo
model; generators (:mod:`legent_gym.world.generation`) write it; people can write it by
hand. Frame: MuJoCo's, z up, right-handed, metres; angles in the file are degrees.

Conventions (see ``docs/scene-format.md`` for the full reference and an example):

* A room is a floor polygon (counter-clockwise, metres) with a type and a name.
* A wall is a segment ``start -> end`` with a height and thickness. Doors and windows sit
  in a wall at ``offset`` metres from its start (the centre of the opening); the openings
  in the wall are derived from them, never stored twice.
* An object instance places an asset (built-in id or an id declared under ``assets``)
  with its frame origin, the centre of its footprint on the floor (or on the surface it
  rests on), at ``position``; ``rotation`` is XYZ Euler degrees.
* Spawns give a floor position and a heading (yaw, degrees, 0 = looking along +x).

Loading validates twice: the schema (types, ranges, finite numbers) and the cross
references (unique ids, known assets, doors on existing walls, ...). Every problem is
reported as ``field.path: message`` in one :class:`SceneError`.
"""

from __future__ import annotations

import json
import math
import os
import re
import shutil
import stat
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Annotated, Any, Final, Literal
from urllib.parse import unquote

from pydantic import BaseModel, ConfigDict, Field, PrivateAttr, ValidationError, field_validator

from legent_gym.utils.atomic import atomic_write_text
from legent_gym.world.assets import registry
from legent_gym.world.geometry import polygon_signed_area
from legent_gym.world.styles import STYLES

SCENE_FORMAT: Final = "legent_gym.scene"
SCENE_VERSION: Final = 1

#: Object kinds: ``static`` never moves (furniture); ``interactable`` is a free body under
#: gravity that the agent can pick up; ``covering`` lies flat on the floor and never moves
#: (a rug): drawn, walked over, and colliding with nothing, so it blocks no floor.
ObjectKind = Literal["static", "interactable", "covering"]


class SceneError(ValueError):
    """A scene that cannot be used: each entry of :attr:`problems` is ``(path, message)``."""

    def __init__(self, problems: list[tuple[str, str]], source: str | None = None):
        self.problems = problems
        self.source = source
        where = f" in {source}" if source else ""
        lines = [f"  {path or '<scene>'}: {msg}" for path, msg in problems]
        super().__init__(f"invalid scene{where} ({len(problems)} problem(s)):\n" + "\n".join(lines))

    def summary(self, limit: int = 3) -> str:
        """One line: the file, then the first ``limit`` problems (and how many more)."""
        shown = "; ".join(f"{path}: {msg}" if path else msg for path, msg in self.problems[:limit])
        more = len(self.problems) - limit
        if more > 0:
            shown += f"; and {more} more problem(s)"
        return f"{self.source}: invalid scene: {shown}" if self.source else f"invalid scene: {shown}"


#: The largest coordinate or length a scene may hold, metres: a house fits in 10 km, and
#: bounded numbers keep lengths, areas and MuJoCo's meshes finite (1e308 is finite, its
#: square is not).
MAX_METRES: Final = 1e4
#: The largest angle (degrees) or joint position a scene may hold.
MAX_ANGLE: Final = 1e6
#: Object scale factors and imported-asset sizes below this are too small for MuJoCo to
#: compile (it refuses meshes whose surface area is below 1e-15).
MIN_SCALE: Final = 1e-3
MAX_SCALE: Final = 1e3
#: Largest integer id or seed (ids become MuJoCo names and int32 lookups).
MAX_ID: Final = 2**31 - 1

#: The largest scene file (or JSON text) accepted, bytes: a generated house is tens of KB.
MAX_SCENE_BYTES: Final = 32 * 1024 * 1024
#: The most entries each list of a scene may hold; a longer list is refused by name before
#: anything is built. Lights: MuJoCo draws at most 100 (``mjMAXLIGHT``).
MAX_ROOMS: Final = 1_000
MAX_POLYGON_POINTS: Final = 10_000
MAX_WALLS: Final = 10_000
MAX_OPENINGS: Final = 10_000  # doors, and windows
MAX_OBJECTS: Final = 10_000
MAX_IMPORTED_ASSETS: Final = 1_000
MAX_LIGHTS: Final = 100
MAX_JOINTS: Final = 1_000  # joint positions of one object
MAX_NAMES: Final = 100  # names of one imported asset
MAX_RECEPTACLES: Final = 100  # placeable surfaces of one imported asset
#: Imported-asset files end in one of these.
ASSET_SUFFIXES: Final = (".gltf", ".glb")

Finite = Annotated[float, Field(ge=-MAX_ANGLE, le=MAX_ANGLE, allow_inf_nan=False)]
Coord = Annotated[float, Field(ge=-MAX_METRES, le=MAX_METRES, allow_inf_nan=False)]
Positive = Annotated[float, Field(gt=0, le=MAX_METRES, allow_inf_nan=False)]
NonNegative = Annotated[float, Field(ge=0, le=MAX_METRES, allow_inf_nan=False)]
Scale = Annotated[float, Field(ge=MIN_SCALE, le=MAX_SCALE, allow_inf_nan=False)]
Unit = Annotated[float, Field(ge=0, le=1, allow_inf_nan=False)]
Vec2 = tuple[Coord, Coord]
Vec3 = tuple[Coord, Coord, Coord]
Angles = tuple[Finite, Finite, Finite]
Id = Annotated[int, Field(ge=0, le=MAX_ID)]
RGBA = tuple[Unit, Unit, Unit, Unit]
RGB = tuple[Unit, Unit, Unit]
Identifier = Annotated[str, Field(min_length=1, max_length=128, pattern=r"^[A-Za-z0-9_.:\-]+$")]


class _Model(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=False, validate_assignment=True)


class Surface(_Model):
    """How a floor or wall looks: a material name from the style presets and a colour."""

    material: str = "plain"
    rgba: RGBA = (0.8, 0.8, 0.8, 1.0)


class Room(_Model):
    id: Identifier
    type: str = Field(min_length=1, description="bedroom, living_room, kitchen, ...")
    name: str = Field(min_length=1, description="What people call it: 'bedroom'.")
    polygon: list[Vec2] = Field(min_length=3, max_length=MAX_POLYGON_POINTS,
                                description="Floor outline, metres, CCW.")
    floor: Surface = Surface(material="wood", rgba=(0.62, 0.48, 0.33, 1.0))
    wall: Surface = Surface(material="paint", rgba=(0.9, 0.88, 0.84, 1.0))

    @field_validator("polygon")
    @classmethod
    def _polygon_has_area(cls, polygon: list[tuple[float, float]]) -> list[tuple[float, float]]:
        area = polygon_signed_area(polygon)
        if abs(area) < 1e-6:
            raise ValueError("polygon has no area")
        return polygon


class Wall(_Model):
    id: Identifier
    start: Vec2
    end: Vec2
    height: Positive = 3.0
    thickness: Positive = 0.1
    #: Room ids on either side; "exterior" for the outside.
    rooms: list[str] = Field(default_factory=list, max_length=2)

    @property
    def length(self) -> float:
        return math.dist(self.start, self.end)


class Door(_Model):
    """A door opening in a wall, with a hinged leaf unless ``leaf`` is false (an archway)."""

    id: Identifier
    wall: Identifier
    offset: Coord = Field(description="Centre of the opening, metres from the wall's start.")
    width: Positive = 0.9
    height: Positive = 2.1
    leaf: bool = True
    #: Which end of the opening the hinge is at: toward the wall's "start" or "end".
    hinge: Literal["start", "end"] = "start"
    #: Side the leaf swings to: "left" or "right" of the wall's direction start -> end.
    swing: Literal["left", "right"] = "left"
    #: 0 closed, 1 open (90 degrees).
    openness: Unit = 1.0
    connects: list[str] = Field(default_factory=list, max_length=2)


class Window(_Model):
    id: Identifier
    wall: Identifier
    offset: Coord
    width: Positive = 1.0
    height: Positive = 1.0
    sill: NonNegative = 0.9


class ImportedSurface(_Model):
    """A placeable rectangle of an imported asset, in the asset's frame after ``yaw``:
    centre (x, y), half extents and the height of the surface, metres; ``clearance``: the
    free height above it."""

    name: Identifier | None = None
    center: Vec2
    half_size: tuple[Positive, Positive]
    height: NonNegative
    clearance: Positive = 1.0


class ImportedAsset(_Model):
    """A user glTF/GLB file used by this scene, with its annotations (what ``legent-gym
    asset annotate`` finds: the up axis, the turn that makes the front face +y, the
    placement, the placeable surfaces, category, names, pickable, mass). Fields left out
    keep the importer's defaults."""

    id: Identifier
    source: str = Field(min_length=1, max_length=4096,
                        description="Path to .glb/.gltf, relative to the scene file.")
    size: tuple[Scale, Scale, Scale] | None = Field(default=None,
                                                    description="Target bounding size (x, y, z) before the "
                                                                "turn by yaw, metres.")
    up_axis: Literal["y", "z"] = "y"
    category: str | None = None
    names: list[str] = Field(default_factory=list, max_length=MAX_NAMES)
    pickupable: bool | None = None
    mass: Positive | None = None
    yaw: int = Field(default=0, description="Quarter turn about z after the import, degrees (0, 90, 180, 270): "
                                            "an annotation's turn that makes the front face +y.")
    placement: Literal["wall", "corner", "middle", "surface", "hanging", "floor"] | None = Field(
        default=None, description="Where generators put it: against a wall, in a corner, in the middle, on a "
                                  "surface, hanging on a wall, flat on the floor (a covering).")
    receptacles: list[ImportedSurface] | None = Field(
        default=None, max_length=MAX_RECEPTACLES,
        description="Placeable surfaces (none: not a receptacle); absent: the importer finds its top.")

    @field_validator("yaw")
    @classmethod
    def _quarter_turn(cls, yaw: int) -> int:
        if yaw not in (0, 90, 180, 270):
            raise ValueError(f"yaw must be 0, 90, 180 or 270 (degrees), got {yaw}")
        return yaw

    @field_validator("source")
    @classmethod
    def _source_is_a_gltf_path(cls, source: str) -> str:
        problem = source_problem(source, relative_only=False)
        if problem:
            raise ValueError(problem)
        return source

    @field_validator("size")
    @classmethod
    def _size_positive(cls, size):
        if size is not None and min(size) <= 0:
            raise ValueError("every size component must be > 0")
        return size


class ObjectInstance(_Model):
    id: Id
    asset: Identifier
    variant: Annotated[int, Field(ge=0, le=2**63 - 1)] = Field(default=0, description="Seed of the asset's look.")
    position: Vec3
    rotation: Angles = (0.0, 0.0, 0.0)
    scale: tuple[Scale, Scale, Scale] = (1.0, 1.0, 1.0)
    kind: ObjectKind = "static"
    #: Id of the object whose receptacle surface this one rests on (None: the floor).
    on: Id | None = None
    room: str | None = None
    #: Positions of articulated parts by joint name (radians for hinges, metres for slides).
    joints: dict[str, Finite] = Field(default_factory=dict, max_length=MAX_JOINTS)


class Spawn(_Model):
    position: Vec2
    yaw: Finite = 0.0


class Light(_Model):
    position: Vec3
    direction: Vec3 = (0.0, 0.0, -1.0)
    diffuse: RGB = (0.6, 0.6, 0.6)
    directional: bool = False
    cast_shadow: bool = True

    @field_validator("direction")
    @classmethod
    def _direction_nonzero(cls, direction):
        if math.hypot(*direction) < 1e-9:
            raise ValueError("a light's direction must not be the zero vector")
        return direction


class Style(_Model):
    """Rendering style: a preset name from :mod:`legent_gym.world.styles`."""

    preset: str = "realistic"
    ambient: RGB = (0.35, 0.35, 0.35)


class Scene(_Model):
    format: Literal["legent_gym.scene"] = SCENE_FORMAT
    version: Literal[1] = SCENE_VERSION
    name: str = "house"
    seed: Annotated[int, Field(ge=-(2**63), le=2**64 - 1)] | None = None
    style: Style = Style()
    rooms: list[Room] = Field(min_length=1, max_length=MAX_ROOMS)
    walls: list[Wall] = Field(default_factory=list, max_length=MAX_WALLS)
    doors: list[Door] = Field(default_factory=list, max_length=MAX_OPENINGS)
    windows: list[Window] = Field(default_factory=list, max_length=MAX_OPENINGS)
    assets: list[ImportedAsset] = Field(default_factory=list, max_length=MAX_IMPORTED_ASSETS)
    objects: list[ObjectInstance] = Field(default_factory=list, max_length=MAX_OBJECTS)
    agent: Spawn
    user: Spawn | None = None
    lights: list[Light] = Field(default_factory=list, max_length=MAX_LIGHTS)
    # Where relative imported-asset paths resolve from: not part of the format, so a
    # private attribute (never serialised), read and set through ``base_dir``.
    _base_dir: Path | None = PrivateAttr(default=None)

    @property
    def base_dir(self) -> Path | None:
        """Directory that relative imported-asset paths resolve against (the scene file's
        folder when loaded from a file; ``None``: the working directory). Not serialised."""
        return self._base_dir

    @base_dir.setter
    def base_dir(self, directory: Path | None) -> None:
        self._base_dir = None if directory is None else Path(directory)

    # -- lookups ------------------------------------------------------------------------
    def object(self, object_id: int) -> ObjectInstance:
        for obj in self.objects:
            if obj.id == object_id:
                return obj
        raise KeyError(f"no object with id {object_id}")

    def wall(self, wall_id: str) -> Wall:
        for wall in self.walls:
            if wall.id == wall_id:
                return wall
        raise KeyError(f"no wall with id {wall_id!r}")

    def room(self, room_id: str) -> Room:
        for room in self.rooms:
            if room.id == room_id:
                return room
        raise KeyError(f"no room with id {room_id!r}")

    def bounds(self) -> tuple[tuple[float, float], tuple[float, float]]:
        """((xmin, ymin), (xmax, ymax)) over all room polygons."""
        xs = [p[0] for r in self.rooms for p in r.polygon]
        ys = [p[1] for r in self.rooms for p in r.polygon]
        return (min(xs), min(ys)), (max(xs), max(ys))

    # -- serialisation ------------------------------------------------------------------
    def to_dict(self) -> dict[str, Any]:
        return self.model_dump(mode="json")

    def to_json(self, indent: int | None = 1) -> str:
        return json.dumps(self.to_dict(), indent=indent, ensure_ascii=False) + "\n"


# ---------------------------------------------------------------------------------------
# Loading, validation, saving

AssetLookup = Callable[[str], bool]


def _format_loc(loc: tuple) -> str:
    path = ""
    for part in loc:
        if isinstance(part, int):
            path += f"[{part}]"
        else:
            path += ("." if path else "") + str(part)
    return path


def _pydantic_problems(err: ValidationError) -> list[tuple[str, str]]:
    problems = []
    for e in err.errors(include_url=False):
        # Drop pydantic's internal union/constraint tags ("tuple[...]", "function-after").
        loc = tuple(p for p in e["loc"] if not (isinstance(p, str) and ("[" in p or "-" in p)))
        msg = e["msg"].removeprefix("Value error, ")
        if e.get("type") in ("finite_number",):
            msg = "must be a finite number (NaN and infinity are not allowed)"
        problems.append((_format_loc(loc), msg))
    return problems


def check_references(scene: Scene, asset_known: AssetLookup | None = None) -> list[tuple[str, str]]:
    """Cross-reference checks the schema cannot express. Returns ``(path, message)`` pairs."""
    problems: list[tuple[str, str]] = []

    def unique(kind: str, ids: list) -> None:
        seen: dict = {}
        for i, ident in enumerate(ids):
            if ident in seen:
                problems.append((f"{kind}[{i}].id", f"duplicate id {ident!r} (also {kind}[{seen[ident]}])"))
            else:
                seen[ident] = i

    unique("rooms", [r.id for r in scene.rooms])
    unique("walls", [w.id for w in scene.walls])
    unique("doors", [d.id for d in scene.doors])
    unique("windows", [w.id for w in scene.windows])
    unique("assets", [a.id for a in scene.assets])
    unique("objects", [o.id for o in scene.objects])

    room_ids = {r.id for r in scene.rooms}
    walls = {w.id: w for w in scene.walls}
    for i, wall in enumerate(scene.walls):
        if wall.length < 1e-6:
            problems.append((f"walls[{i}]", "start and end are the same point"))
        for j, rid in enumerate(wall.rooms):
            if rid != "exterior" and rid not in room_ids:
                problems.append((f"walls[{i}].rooms[{j}]", f"unknown room {rid!r}"))

    openings: tuple[tuple[str, Sequence[Door | Window]], ...] = (("doors", scene.doors), ("windows", scene.windows))
    for kind, items in openings:
        for i, item in enumerate(items):
            host = walls.get(item.wall)
            if host is None:
                problems.append((f"{kind}[{i}].wall", f"unknown wall {item.wall!r}"))
                continue
            half = item.width / 2
            if item.offset - half < -1e-9 or item.offset + half > host.length + 1e-9:
                problems.append(
                    (f"{kind}[{i}].offset", f"opening [{item.offset - half:.3f}, {item.offset + half:.3f}] "
                     f"does not fit in wall {host.id!r} of length {host.length:.3f}")
                )
            top = item.height + (item.sill if isinstance(item, Window) else 0.0)
            if top > host.height + 1e-9:
                problems.append((f"{kind}[{i}].height", f"opening is taller than wall {host.id!r}"))
    for i, door in enumerate(scene.doors):
        for j, rid in enumerate(door.connects):
            if rid != "exterior" and rid not in room_ids:
                problems.append((f"doors[{i}].connects[{j}]", f"unknown room {rid!r}"))

    if scene.style.preset not in STYLES:
        problems.append(("style.preset", f"unknown style preset {scene.style.preset!r}; known: {', '.join(STYLES)}"))
    imported = {a.id for a in scene.assets}
    object_ids = {o.id for o in scene.objects}
    for i, obj in enumerate(scene.objects):
        if obj.asset not in imported and asset_known is not None and not asset_known(obj.asset):
            problems.append((f"objects[{i}].asset", f"unknown asset id {obj.asset!r}"))
        if obj.on is not None:
            if obj.on not in object_ids:
                problems.append((f"objects[{i}].on", f"no object with id {obj.on}"))
            elif obj.on == obj.id:
                problems.append((f"objects[{i}].on", "an object cannot rest on itself"))
        if obj.room is not None and obj.room not in room_ids:
            problems.append((f"objects[{i}].room", f"unknown room {obj.room!r}"))
    return problems


def _default_asset_lookup() -> AssetLookup:
    return registry.has


def validate_scene(data: Any, *, asset_known: AssetLookup | None | Literal["registry"] = "registry",
                   source: str | None = None) -> Scene:
    """Validate a dict (or a :class:`Scene`) and return the scene, or raise :class:`SceneError`.

    ``asset_known`` decides which asset ids exist: by default the built-in registry; pass a
    callable of your own, or ``None`` to skip the asset check.
    """
    if isinstance(data, Scene):
        data = data.to_dict()
    if not isinstance(data, dict):
        raise SceneError([("", f"expected a JSON object at the top level, got {type(data).__name__}")], source)
    try:
        scene = Scene.model_validate(data)
    except ValidationError as err:
        raise SceneError(_pydantic_problems(err), source) from None
    lookup = _default_asset_lookup() if asset_known == "registry" else asset_known
    problems = check_references(scene, lookup)
    if problems:
        raise SceneError(problems, source)
    return scene


def loads_scene(text: str, *, source: str | None = None, base_dir: str | os.PathLike | None = None,
                **kwargs) -> Scene:
    """Parse and validate scene JSON text, as :func:`load_scene` does a file's.

    Imported-asset sources must be relative paths that stay inside ``base_dir`` (symbolic
    links are followed when ``base_dir`` is given); see :func:`check_asset_sources`.
    """
    if len(text) > MAX_SCENE_BYTES:
        raise SceneError([("", f"the text is {len(text)} characters long, more than the {MAX_SCENE_BYTES} "
                               "a scene may have (MAX_SCENE_BYTES)")], source)
    try:
        data = json.loads(text, parse_constant=_reject_constant)
    except json.JSONDecodeError as err:
        raise SceneError([("", f"not valid JSON: {err.msg} at line {err.lineno} column {err.colno}")], source) from None
    except RecursionError:
        raise SceneError([("", "not a scene: the JSON is nested too deeply")], source) from None
    except ValueError as err:
        raise SceneError([("", str(err))], source) from None
    scene = validate_scene(data, source=source, **kwargs)
    problems = check_asset_sources(scene, base_dir)
    if problems:
        raise SceneError(problems, source)
    return scene


def _reject_constant(name: str):
    raise ValueError(f"not valid JSON: {name} is not a number JSON allows")


def load_scene(path: str | os.PathLike, **kwargs) -> Scene:
    """Read and validate a scene file. Imported asset paths stay relative to the file.

    The file must be a regular file of at most :data:`MAX_SCENE_BYTES` bytes of UTF-8 (a
    byte order mark is allowed); its imported assets must lie in its own folder.
    """
    path = Path(path)
    try:
        info = os.stat(path)  # before opening: opening a FIFO would wait for a writer
        if not stat.S_ISREG(info.st_mode):
            raise SceneError([("", "not a regular file (a directory, device or pipe)")], str(path))
        if info.st_size > MAX_SCENE_BYTES:
            raise SceneError([("", f"the file is {info.st_size} bytes, more than the {MAX_SCENE_BYTES} "
                                   "a scene may have (MAX_SCENE_BYTES)")], str(path))
        with open(path, "rb") as file:
            data = file.read(MAX_SCENE_BYTES + 1)
    except OSError as err:
        raise SceneError([("", f"cannot read file: {err.strerror or err}")], str(path)) from None
    if len(data) > MAX_SCENE_BYTES:  # grew since the stat
        raise SceneError([("", f"the file is more than the {MAX_SCENE_BYTES} bytes a scene may have "
                               "(MAX_SCENE_BYTES)")], str(path))
    try:
        text = data.decode("utf-8-sig")  # a byte order mark is allowed
    except UnicodeDecodeError:
        raise SceneError([("", "file is not UTF-8 text")], str(path)) from None
    base_dir = path.parent.resolve()
    scene = loads_scene(text, source=str(path), base_dir=base_dir, **kwargs)
    # Remember where the file was, so relative asset sources resolve (not serialised).
    scene.base_dir = base_dir
    return scene


_URL_SCHEME = re.compile(r"^[A-Za-z][A-Za-z0-9+.\-]*:")


def source_problem(source: str, *, relative_only: bool = True) -> str | None:
    """What is wrong with an imported-asset ``source`` path, or None.

    Refused always: URLs (anything starting ``scheme:``, e.g. ``http:``, ``file:``,
    ``data:``), control characters, names not ending in ``.gltf`` / ``.glb``. With
    ``relative_only`` (a scene read from a file or text) also absolute paths, ``~`` and
    ``..`` that climbs out of the scene's folder.
    """
    if any(ord(c) < 32 or ord(c) == 127 for c in source):
        return f"{source!r} contains a control character"
    scheme = _URL_SCHEME.match(source)
    if scheme:
        return f"{source[:80]!r} is a URL ({scheme.group(0)}); only files in the scene's folder are read"
    if not source.lower().endswith(ASSET_SUFFIXES):
        return f"{source[:80]!r} must name a .gltf or .glb file"
    if relative_only:
        if source.startswith(("/", "\\", "~")):
            return f"{source[:80]!r} is an absolute path; a scene refers only to files in its own folder"
        depth = 0
        for part in source.replace("\\", "/").split("/"):
            depth += -1 if part == ".." else 0 if part in ("", ".") else 1
            if depth < 0:
                return f"{source[:80]!r} leaves the scene's folder (..); a scene refers only to files in its own folder"
    return None


def check_asset_sources(scene: Scene, base_dir: str | os.PathLike | None = None) -> list[tuple[str, str]]:
    """``(path, message)`` for each imported asset whose source a scene file may not use.

    Every source must pass :func:`source_problem` with ``relative_only``; with a
    ``base_dir`` the source resolved against it (symbolic links followed) must also stay
    inside it and, where it exists, be a regular file (not a device, pipe or directory).
    """
    problems: list[tuple[str, str]] = []
    base = None if base_dir is None else Path(base_dir).resolve()
    for i, asset in enumerate(scene.assets):
        problem = source_problem(asset.source)
        if problem is None and base is not None:
            try:
                target = (base / asset.source).resolve()
                if not target.is_relative_to(base):
                    problem = f"{asset.source!r} leads out of the scene's folder (to {target})"
                elif target.exists() and not target.is_file():
                    problem = f"{asset.source!r} is not a regular file (a directory, device or pipe)"
            except (OSError, RuntimeError) as err:  # RuntimeError: a symbolic link loop
                problem = f"{asset.source!r} cannot be resolved: {err}"
        if problem:
            problems.append((f"assets[{i}].source", problem))
    return problems


def save_scene(scene: Scene, path: str | os.PathLike) -> None:
    """Write a scene file. An imported asset whose source is an absolute path (a generator
    that used an annotated asset writes those) is written relative to the file's folder;
    a file outside that folder is first copied into ``<scene file stem>_assets/`` beside
    it (a .gltf with the buffers and images it names), so the scene file and its folder
    are all a later process needs."""
    atomic_write_text(path, portable_scene(scene, Path(path).resolve().parent, Path(path).stem).to_json())


def portable_scene(scene: Scene, folder: Path, stem: str) -> Scene:
    """``scene`` with each absolute imported-asset source made relative to ``folder``
    (copying files from outside it into ``folder/<stem>_assets/``); unchanged when no
    source is absolute."""
    if not any(Path(a.source).is_absolute() for a in scene.assets):
        return scene
    assets = []
    for asset in scene.assets:
        source = Path(asset.source)
        if source.is_absolute():
            target = source.resolve()
            if not target.is_relative_to(folder):
                target = _copy_asset_file(target, folder / f"{stem}_assets" / asset.id)
            asset = asset.model_copy(update={"source": target.relative_to(folder).as_posix()})
        assets.append(asset)
    out = scene.model_copy(update={"assets": assets})
    out.base_dir = scene.base_dir
    return out


def _copy_asset_file(source: Path, folder: Path) -> Path:
    """Copy a .glb, or a .gltf with the relative buffer and image files it names, into
    ``folder``; the copy's path."""
    folder.mkdir(parents=True, exist_ok=True)
    target = folder / source.name
    shutil.copyfile(source, target)
    if source.suffix.lower() == ".gltf":
        try:
            doc = json.loads(source.read_text(encoding="utf-8"))
        except (OSError, ValueError):
            return target  # the importer names what is wrong with it
        for entry in [*doc.get("buffers", []), *doc.get("images", [])]:
            uri = entry.get("uri") if isinstance(entry, dict) else None
            if not isinstance(uri, str) or _URL_SCHEME.match(uri) or uri.startswith(("/", "\\")):
                continue
            part = (source.parent / unquote(uri)).resolve()
            if part.is_file() and part.is_relative_to(source.parent.resolve()):
                dest = folder / part.relative_to(source.parent.resolve())
                dest.parent.mkdir(parents=True, exist_ok=True)
                shutil.copyfile(part, dest)
    return target


def scene_base_dir(scene: Scene) -> Path:
    return scene.base_dir or Path.cwd()


def scene_json_schema() -> dict[str, Any]:
    """The JSON Schema of the format (for editors and other languages)."""
    return Scene.model_json_schema()

"""``generate_house``: a seeded, validated house from a spec and conditions.

One attempt: choose the room mix, grow a floor plan, add doors and windows, furnish, put
small objects on reachable surfaces, place the agent and the user, and check the result
with :func:`~legent_gym.world.generation.validate.check_house`. A failed attempt is
retried with the next generator derived from the seed (bounded in count and time); an
invalid house is never returned. Everything random comes from
``np.random.default_rng(seed)``, so the same arguments give the same JSON.
"""

from __future__ import annotations

import time
from collections import Counter
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from legent_gym.world.generation.conditions import (
    Catalog,
    GenerationError,
    HouseSpec,
    make_spec,
    normalise_name,
)
from legent_gym.world.generation.dressing import dress_house
from legent_gym.world.generation.floorplan import (
    FloorPlan,
    PlanFailed,
    build_floorplan,
    place_doors,
    place_windows,
    plan_grid,
    r4,
)
from legent_gym.world.generation.furnish import (
    Furnisher,
    Placed,
    PlacementFailed,
    allowed_room_types,
    furnish_house,
)
from legent_gym.world.generation.presets import PRESETS, preset
from legent_gym.world.generation.roomtypes import ROOM_TYPES, parse_rooms
from legent_gym.world.generation.small_objects import (
    SmallPlaced,
    place_small_objects,
    receptacle_corners,
)
from legent_gym.world.generation.surfaces_and_lights import (
    ceiling_light,
    light_point,
    room_surfaces,
)
from legent_gym.world.generation.validate import check_house
from legent_gym.world.geometry import door_passable, local_footprint
from legent_gym.world.navigation import (
    DEFAULT_AGENT_RADIUS,
    DEFAULT_RESOLUTION,
    NavGrid,
    clearance_at_least,
)
from legent_gym.world.scene import ObjectInstance, ObjectKind, Room, Scene, Spawn

#: The version of the houses a seed gives: it changes whenever the same seed and conditions
#: give another house (docs/generation.md lists what changed); anything that stores houses
#: made from seeds keys them by it. 2: 50 pickupable kinds (33 more: kitchenware, decor,
#: office and bathroom things) on the surfaces that plausibly hold them. 3: 105 asset types
#: (34 more pieces of furniture, appliances and fixtures) furnishing rooms by type, and
#: appliances on kitchen counters. 4: pictures hung on walls (``WALL_DECOR``), and doors and
#: drawers that open on kitchen counters, desks, sideboards and tv stands. 5: set dressing
#: (``dressing``: rows of books on shelves, rugs and mats, wall cabinets and hoods, curtains,
#: cushions), 32 variants per asset type (``registry.GENERATED_VARIANTS``), and small
#: objects at a density of 2 per surface.
GENERATOR_VERSION = 5
#: Extra clearance (beyond the agent radius) preferred around spawn points, metres.
SPAWN_CLEARANCE = 0.15
#: How far the agent reaches from where it stands (the validity check's reach).
REACH = 1.0


@dataclass
class Conditions:
    """A spec's conditions resolved against the asset catalog (checked once, up front)."""

    need: dict[str, int] = field(default_factory=dict)  #: furniture category -> at least
    caps: dict[str, int] = field(default_factory=dict)  #: furniture category -> at most
    labels: dict[str, str] = field(default_factory=dict)  #: furniture category -> condition text
    small_counts: dict[str, int] = field(default_factory=dict)  #: exact counts
    small_least: dict[str, int] = field(default_factory=dict)  #: at least (from ``require``)
    require_on: list[tuple[str, list[str], str]] = field(default_factory=list)
    #: Furniture that must exist as any one of several categories, with its label.
    need_any: list[tuple[list[str], str]] = field(default_factory=list)


def _has_surface(catalog: Catalog, category: str) -> bool:
    return any(r.link == "base" for a in catalog.by_category[category] for r in catalog.models[a].receptacles)


def resolve_conditions(spec: HouseSpec, catalog: Catalog) -> Conditions:
    """Map names to categories and check what can be checked without a house."""
    c = Conditions()
    names, pairs = spec.split_require()
    for name in names:
        cat = catalog.resolve_one(name, "furniture")
        if catalog.is_small(cat):
            c.small_least[cat] = c.small_least.get(cat, 0) + 1
        else:
            c.need[cat] = c.need.get(cat, 0) + 1
            c.labels[cat] = f"required {normalise_name(name)!r}"
    for name, n in spec.object_counts.items():
        cat = catalog.resolve_one(name)
        if catalog.is_small(cat):
            c.small_counts[cat] = n
            continue
        if c.need.get(cat, 0) > n:
            raise GenerationError(f"conditions disagree: 'require' asks for {c.need[cat]} {cat!r} but "
                                  f"object_counts allows {n}")
        c.need[cat], c.caps[cat] = n, n
        c.labels[cat] = f"{n} {cat!r} (object_counts)"
    for obj_name, rec_name in list(spec.require_on) + pairs:
        label = f"'{obj_name} on {rec_name}'"
        obj = catalog.resolve_one(obj_name)
        recs = [r for r in catalog.resolve(rec_name, "receptacle") if catalog.is_furniture(r)]
        if not catalog.is_small(obj):
            raise GenerationError(f"cannot place {label}: {obj!r} is not a small object that can rest on a surface")
        with_surface = [r for r in recs if _has_surface(catalog, r)]
        if not with_surface:
            raise GenerationError(f"cannot place {label}: {rec_name!r} has no surface to put things on")
        c.require_on.append((obj, with_surface, label))
        c.need_any.append((with_surface, label))
    for cat, n in c.small_least.items():
        if cat in c.small_counts and c.small_counts[cat] < n:
            raise GenerationError(f"conditions disagree: 'require' asks for {cat!r} but object_counts allows {c.small_counts[cat]}")
    on_counts = Counter(obj for obj, _, _ in c.require_on)
    for cat, n in on_counts.items():
        if cat in c.small_counts and c.small_counts[cat] < n:
            raise GenerationError(f"conditions disagree: require_on puts {n} {cat!r} on surfaces but object_counts "
                                  f"allows {c.small_counts[cat]}")
    if spec.max_per_surface == 0 and (c.require_on or any(c.small_counts.values()) or c.small_least):
        raise GenerationError("cannot place small objects with max_per_surface=0")
    _check_room_types(spec, catalog, c)
    _check_capacity(spec, catalog, c)
    return c


def _check_room_types(spec: HouseSpec, catalog: Catalog, c: Conditions) -> None:
    """With a fixed room list, every needed piece must be allowed in one of its rooms."""
    if spec.rooms is not None:
        options = [spec.rooms]
    elif spec.room_options is not None:
        options = spec.room_options
    else:
        return
    wanted = [([cat], c.labels[cat]) for cat in sorted(c.need) if c.need[cat] > 0] + c.need_any
    for cats, label in wanted:
        types = set().union(*(allowed_room_types(catalog, cat) for cat in cats))
        if spec.rooms is not None and len(spec.rooms) < (spec.n_rooms or 0):
            continue  # extra random rooms will be chosen to fit
        if not any(types & set(rooms) for rooms in options):
            where = " or ".join(sorted(ROOM_TYPES[t].name if t in ROOM_TYPES else t for t in types))
            have = ", ".join(ROOM_TYPES[t].name for t in options[0])
            raise GenerationError(f"cannot place {label}: a {' or '.join(cats)} goes in a {where}, "
                                  f"and the house has only: {have}")


def _check_capacity(spec: HouseSpec, catalog: Catalog, c: Conditions) -> None:
    """Fail at once when needed furniture cannot fit in the largest house possible."""
    if spec.rooms is not None:
        cells = sum(ROOM_TYPES[t].cells[1] for t in spec.rooms) + 2
    else:
        cells = 6 * max(len(spec.rooms or []), spec.n_rooms or 6, 6) + 2
    biggest = cells * spec.cell_size[1] ** 2
    if spec.area is not None:
        biggest = min(biggest, spec.area[1])
    for cat in sorted(c.need):
        lr = local_footprint(catalog.describe(cat))
        need_area = c.need[cat] * (lr[2] - lr[0]) * (lr[3] - lr[1])
        if need_area > 0.5 * biggest:
            raise GenerationError(f"cannot place {c.labels[cat]}: {c.need[cat]} of them cover "
                                  f"{need_area:.0f} m^2, more than half of the largest floor this house "
                                  f"can have ({biggest:.0f} m^2)")


# ---------------------------------------------------------------------------------------
# Room mix


_EXTRAS = ("hallway", "office", "dining_room", "bedroom", "bathroom", "bedroom")


def default_mix(n: int, rng: np.random.Generator) -> list[str]:
    """A plausible house of ``n`` rooms: bedroom, living room, kitchen, bathroom, then extras."""
    base = ["bedroom", "living_room", "kitchen", "bathroom"]
    if n <= 4:
        return base[:n]
    extras = [_EXTRAS[k] for k in rng.permutation(len(_EXTRAS)).tolist()]
    return base + extras[: n - 4] + ["bedroom"] * max(0, n - 4 - len(extras))


def choose_rooms(spec: HouseSpec, c: Conditions, catalog: Catalog, rng: np.random.Generator) -> list[str]:
    """Room types of this attempt; rooms the conditions need are swapped in when the user
    did not fix the list."""
    if spec.rooms is not None:
        rooms = list(spec.rooms)
        if spec.n_rooms is not None and len(rooms) < spec.n_rooms:
            rooms += [t for t in default_mix(spec.n_rooms + 4, rng)[4:]][: spec.n_rooms - len(rooms)]
        fixed = len(spec.rooms)
    elif spec.room_options:
        rooms = list(spec.room_options[int(rng.integers(len(spec.room_options)))])
        fixed = 0
    else:
        n = spec.n_rooms or int(rng.integers(1, 7))
        rooms = default_mix(n, rng)
        fixed = 0
    wanted = [[cat] for cat in sorted(c.need) if c.need[cat] > 0] + [cats for cats, _ in c.need_any]
    for cats in wanted:
        types = set().union(*(allowed_room_types(catalog, cat) for cat in cats))
        if types & set(rooms):
            continue
        choice = sorted(types)[int(rng.integers(len(types)))]
        needed_elsewhere = {t for cs in wanted for cat in cs for t in allowed_room_types(catalog, cat)}
        swappable = [k for k in range(fixed, len(rooms)) if rooms[k] not in needed_elsewhere
                     or rooms.count(rooms[k]) > 1]
        if swappable and (spec.n_rooms is not None or spec.room_options):
            rooms[swappable[-1]] = choice
        elif spec.n_rooms is None or len(rooms) < spec.n_rooms:
            rooms.append(choice)
    return rooms


# ---------------------------------------------------------------------------------------
# One attempt


class AttemptFailed(Exception):
    def __init__(self, message: str, label: str | None = None):
        super().__init__(message)
        self.label = label


def _floor_plan(spec: HouseSpec, types: list[str], rng: np.random.Generator) -> FloorPlan:
    last = None
    for _ in range(30 if spec.area is not None else 3):
        try:
            grid = plan_grid(types, rng, cell_range=spec.cell_size, area=spec.area)
            fp = build_floorplan(grid, types, wall_height=spec.wall_height)
            # Doors are open while the house is built and checked; ``door_openness`` is
            # applied to the finished house (see generate_house).
            place_doors(fp, rng, openness=1.0)
            if spec.windows:
                place_windows(fp, rng)
            return fp
        except PlanFailed as err:
            last = err
    if spec.area is not None:
        raise AttemptFailed(f"cannot meet area={tuple(spec.area)} m^2 with rooms {types}: {last}", "area")
    raise AttemptFailed(f"no floor plan for rooms {types}: {last}")


def _needs_for_house(c: Conditions, fp: FloorPlan, catalog: Catalog) -> dict[str, int]:
    """``need`` plus one receptacle for each require_on pair that none of its categories
    covers yet (the first category allowed in this house's rooms)."""
    need = dict(c.need)
    types = set(fp.types)
    for cats, _label in c.need_any:
        if any(need.get(cat, 0) > 0 for cat in cats):
            continue
        for cat in cats:
            if allowed_room_types(catalog, cat) & types:
                need[cat] = max(need.get(cat, 0), 1)
                break
    return need


def _furnish(c: Conditions, fp: FloorPlan, catalog: Catalog, rng: np.random.Generator) -> Furnisher:
    try:
        return furnish_house(fp, catalog, rng, need=_needs_for_house(c, fp, catalog), caps=c.caps)
    except PlacementFailed as err:
        if err.category is None:
            raise AttemptFailed(str(err)) from None
        label = c.labels.get(err.category) or next(
            (lab for cats, lab in c.need_any if err.category in cats), err.category)
        raise AttemptFailed(f"cannot place {label}: {err}", label) from None


def _scene_rooms(fp: FloorPlan, rng: np.random.Generator) -> list[Room]:
    rooms = []
    for i, (rid, rtype, poly) in enumerate(zip(fp.room_ids, fp.types, fp.polygons)):
        floor, wall = room_surfaces(rtype, rng)
        same = [k for k, t in enumerate(fp.types) if t == rtype]
        name = ROOM_TYPES[rtype].name + ("" if len(same) == 1 else f" {same.index(i) + 1}")
        rooms.append(Room(id=rid, type=rtype, name=name, polygon=poly, floor=floor, wall=wall))
    return rooms


def _furniture(fp: FloorPlan, pieces: list[Placed]) -> tuple[list[ObjectInstance], dict[int, int]]:
    """Furniture ordered by room (then placement), ids 0..N-1; and each piece's id."""
    order = sorted(range(len(pieces)), key=lambda k: (pieces[k].room, k))
    new_id = {k: i for i, k in enumerate(order)}
    return [_piece_object(fp, pieces[k], new_id[k], new_id) for k in order], new_id


def _piece_object(fp: FloorPlan, p: Placed, ident: int, new_id: dict[int, int]) -> ObjectInstance:
    """The scene object of a placed piece, ``new_id`` giving the ids of the pieces before it."""
    kind: ObjectKind = "interactable" if p.model.pickupable else ("covering" if p.model.placement == "floor" else "static")
    return ObjectInstance(
        id=ident, asset=p.asset, variant=p.variant, position=(r4(p.x), r4(p.y), r4(p.z)),
        rotation=(0.0, 0.0, r4(p.yaw_deg)), scale=p.scale, kind=kind,
        on=None if p.support is None else new_id[p.support], room=fp.room_ids[p.room])


def _objects(fp: FloorPlan, pieces: list[Placed], furniture: tuple[list[ObjectInstance], dict[int, int]],
             small: list[SmallPlaced]) -> list[ObjectInstance]:
    """The furniture (:func:`_furniture`'s, the same instances), the pieces added after it
    (the set dressing: :mod:`legent_gym.world.generation.dressing`), then the small objects."""
    out, new_id = list(furniture[0]), dict(furniture[1])
    for k in range(len(pieces)):
        if k not in new_id:
            new_id[k] = len(out)
            out.append(_piece_object(fp, pieces[k], new_id[k], new_id))
    for s in small:
        out.append(ObjectInstance(
            id=len(out), asset=s.asset, variant=s.variant, position=(r4(s.x), r4(s.y), r4(s.z)),
            rotation=(0.0, 0.0, r4(s.yaw)), kind="interactable", on=new_id[s.support],
            room=fp.room_ids[pieces[s.support].room]))
    return out


def _main_component(nav: NavGrid, fp: FloorPlan, spaces) -> int:
    """The walkable component that links the doors (where people walk in and out); the
    largest one if no door mouth is walkable."""
    votes: Counter[int] = Counter()
    for space in spaces:
        for m in space.mouths:
            win = nav.raster.window(*m)
            if win is not None:
                here = nav.labels[win[0]]
                votes.update(here[here > 0].tolist())
    if votes:
        return max(sorted(votes), key=lambda k: votes[k])
    counts = np.bincount(nav.labels.ravel())
    counts[0] = 0
    return int(np.argmax(counts)) if counts.sum() else 0


def _far_cells(nav: NavGrid, cells: np.ndarray, xy: tuple[float, float], distance: float) -> np.ndarray:
    pts = (cells[:, ::-1] + 0.5) * nav.resolution + np.asarray(nav.origin)
    return cells[np.hypot(pts[:, 0] - xy[0], pts[:, 1] - xy[1]) >= distance + 1e-3]


class SpawnSampler:
    """Draws agent and user spawns on walkable floor of one component, preferably with some
    room around them (:data:`SPAWN_CLEARANCE`), at least a distance apart. The candidate
    cells are found once, so a kept house draws new spawns for each episode cheaply."""

    def __init__(self, nav: NavGrid, component: int):
        self.nav = nav
        self.ok = nav.labels == component
        comfy = self.ok & clearance_at_least(nav.free, nav.agent_radius + SPAWN_CLEARANCE + nav.resolution / 2,
                                             nav.resolution)
        self.cells = np.argwhere(comfy if comfy.any() else self.ok)
        self._all_cells: np.ndarray | None = None

    def draw(self, rng: np.random.Generator, *, user: bool, min_distance: float) -> tuple[Spawn, Spawn | None]:
        """An agent spawn and, with ``user``, a user spawn at least ``min_distance`` from it;
        raises :class:`AttemptFailed` when there is no room for them."""
        nav, cells = self.nav, self.cells
        if len(cells) == 0:
            raise AttemptFailed("no walkable floor for the agent")
        a = cells[int(rng.integers(len(cells)))]
        ax, ay = nav.to_world(a)
        agent = Spawn(position=(r4(ax), r4(ay)), yaw=round(float(rng.uniform(0.0, 360.0)), 1))
        if not user:
            return agent, None
        far = _far_cells(nav, cells, (ax, ay), min_distance)
        if len(far) == 0:
            if self._all_cells is None:
                self._all_cells = np.argwhere(self.ok)
            far = _far_cells(nav, self._all_cells, (ax, ay), min_distance)
        if len(far) == 0:
            raise AttemptFailed(f"cannot place the user at least {min_distance} m from the agent "
                                "(min_user_distance)", "min_user_distance")
        u = far[int(rng.integers(len(far)))]
        ux, uy = nav.to_world(u)
        return agent, Spawn(position=(r4(ux), r4(uy)), yaw=round(float(rng.uniform(0.0, 360.0)), 1))


def place_spawns(nav: NavGrid, component: int, rng: np.random.Generator, *, user: bool,
                 min_distance: float) -> tuple[Spawn, Spawn | None]:
    """Agent and user on walkable floor of one component (see :class:`SpawnSampler`)."""
    return SpawnSampler(nav, component).draw(rng, user=user, min_distance=min_distance)


def scene_rooms(fp: FloorPlan, rng: np.random.Generator) -> list[Room]:
    """The scene's rooms of a floor plan (names, floor and wall surfaces)."""
    return _scene_rooms(fp, rng)


def scene_objects(fp: FloorPlan, pieces: list[Placed],
                  small: list[SmallPlaced]) -> tuple[list[ObjectInstance], list[ObjectInstance], dict[int, int]]:
    """The furniture as scene objects, all objects (furniture, then small objects), and
    each piece's object id."""
    furniture = _furniture(fp, pieces)
    return furniture[0], _objects(fp, pieces, furniture, small), furniture[1]


def main_component(nav: NavGrid, fp: FloorPlan, spaces) -> int:
    """The walkable component that links the doors."""
    return _main_component(nav, fp, spaces)


def attempt_house(seed: int, spec: HouseSpec, c: Conditions, catalog: Catalog,
                  rng: np.random.Generator) -> Scene:
    """One try at a house; raises :class:`AttemptFailed` (or returns a scene to check)."""
    return _attempt(seed, spec, c, catalog, rng)[0]


def _attempt(seed: int, spec: HouseSpec, c: Conditions, catalog: Catalog,
             rng: np.random.Generator) -> tuple[Scene, NavGrid]:
    """:func:`attempt_house`, and the navigation grid of the house without its small
    objects (default agent radius and resolution), with which it was checked."""
    types = choose_rooms(spec, c, catalog, rng)
    fp = _floor_plan(spec, types, rng)
    furn = _furnish(c, fp, catalog, rng)
    rooms = _scene_rooms(fp, rng)
    lights = [ceiling_light(light_point(p), spec.wall_height) for p in fp.polygons]
    base: dict[str, Any] = dict(name=spec.name or f"house-{seed}", seed=seed, rooms=rooms, walls=fp.walls, doors=fp.doors,
                windows=fp.windows, lights=lights)
    furniture = _furniture(fp, furn.pieces)
    bare = Scene(**base, objects=furniture[0], agent=Spawn(position=(0.0, 0.0)))
    nav = NavGrid.from_scene(bare, agent_radius=DEFAULT_AGENT_RADIUS, resolution=DEFAULT_RESOLUTION)
    component = _main_component(nav, fp, furn.spaces)

    def reachable(piece: Placed, rec) -> bool:
        return nav.can_reach(receptacle_corners(piece, rec), REACH, component)

    dress_house(furn, rng, lambda corners: nav.can_reach(corners, REACH, component))
    counts = dict(c.small_counts)
    for cat, n in c.small_least.items():
        counts.setdefault(cat, 0)
        counts[cat] = max(counts[cat], n)
    try:
        small = place_small_objects(furn.pieces, catalog, rng, require_on=c.require_on, counts=counts,
                                    density=spec.density, max_per_surface=spec.max_per_surface,
                                    reachable=reachable)
    except PlacementFailed as err:
        raise AttemptFailed(str(err), "small objects") from None
    agent, user = place_spawns(nav, component, rng, user=spec.user, min_distance=spec.min_user_distance)
    scene = Scene(**base, objects=_objects(fp, furn.pieces, furniture, small), agent=agent, user=user)
    problems = check_house(scene, nav, reach=REACH)
    if problems:
        raise AttemptFailed("the house fails its checks: " + "; ".join(problems[:3]))
    return scene, nav


# ---------------------------------------------------------------------------------------


def resolve_spec(spec: Any) -> HouseSpec | None:
    """A :class:`HouseSpec` from a preset name, a room description, a list of room types,
    a dict, or a spec (None: no base)."""
    if spec is None or isinstance(spec, HouseSpec):
        return spec
    if isinstance(spec, dict):
        return make_spec(None, spec)
    if isinstance(spec, str):
        named = preset(spec)
        if named is not None:
            return named
        try:
            return make_spec(None, {"rooms": parse_rooms(spec)})
        except ValueError as err:
            raise GenerationError(f"{err}; or a preset: {', '.join(PRESETS)}") from None
    if isinstance(spec, list | tuple):
        return make_spec(None, {"rooms": list(spec)})
    raise TypeError(f"spec must be a preset name, a room description, a list of room types, a dict "
                    f"or a HouseSpec, not {type(spec).__name__}")


def generate_house(seed: int, spec: Any = None, **conditions: Any) -> Scene:
    """A furnished, validated house: the same arguments always give the same scene.

    ``spec``: a preset name ("OneRoom", "TwoRoom", "FourRoom", "Apartment"), a room
    description ("2 bed 1 bath", "bedroom + living room"), a list of room types, a dict or
    a :class:`HouseSpec`. ``conditions``: any :class:`HouseSpec` field as a keyword
    (``rooms``, ``n_rooms``, ``area``, ``require``, ``require_on``, ``object_counts``,
    ``density``, ``max_per_surface``, ``min_user_distance``, ...); ``None`` values are
    ignored, unknown keywords raise ``TypeError``.

    Raises :class:`GenerationError` naming the condition that cannot be met (at once when
    it is plainly impossible, else after ``max_attempts`` tries or ``time_limit`` seconds).
    """
    return _generate(seed, spec, conditions)[0]


def generate_house_with_grid(seed: int, spec: Any = None, **conditions: Any) -> tuple[Scene, NavGrid]:
    """:func:`generate_house`'s scene and its navigation grid, ``NavGrid.from_scene(scene)``
    (the default agent radius and resolution), for less than that costs: the generator has
    rasterised the house to check it, so only the small objects' footprints are added."""
    scene, nav = _generate(seed, spec, conditions)
    if not all(door_passable(d) for d in scene.doors):
        # The house was checked with its doors open (``door_openness`` closes them after).
        return scene, NavGrid.from_scene(scene)
    return scene, nav.for_scene(scene)


def _generate(seed: int, spec: Any, conditions: dict[str, Any]) -> tuple[Scene, NavGrid]:
    """The generated scene (doors set to ``door_openness``) and the grid of its bare house,
    with the doors open."""
    seed = int(seed)
    hs = make_spec(resolve_spec(spec), conditions)
    catalog = Catalog.from_registry()
    c = resolve_conditions(hs, catalog)
    master = np.random.default_rng(seed)
    started = time.perf_counter()
    failures: list[AttemptFailed] = []
    for _ in range(hs.max_attempts):
        rng = master.spawn(1)[0]
        try:
            scene, nav = _attempt(seed, hs, c, catalog, rng)
            return _with_door_openness(scene, hs.door_openness), nav
        except AttemptFailed as err:
            failures.append(err)
        if time.perf_counter() - started > hs.time_limit:
            break
    raise GenerationError(_summary(failures, time.perf_counter() - started))


def _with_door_openness(scene: Scene, openness: float) -> Scene:
    """Set the leaves of the (validated, open) doors to ``openness``."""
    if openness != 1.0:
        for door in scene.doors:
            if door.leaf:
                door.openness = openness
    return scene


def _summary(failures: list[AttemptFailed], elapsed: float) -> str:
    labelled = [f for f in failures if f.label]
    pool = labelled or failures
    common = Counter(str(f) for f in pool).most_common(1)[0][0]
    prefix = "" if labelled else "could not generate a valid house: "
    return f"{prefix}{common} ({len(failures)} attempt(s), {elapsed:.1f} s)"

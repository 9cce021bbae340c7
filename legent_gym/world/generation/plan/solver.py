"""The plan's solver: :func:`solve_plan` (a floor plan with the rooms' sizes, doors,
windows, then a depth-first search per room over candidate poses, scored by the relations;
see :mod:`legent_gym.world.generation.plan`), and the relations measured on a result
(:func:`relation_scores`)."""

from __future__ import annotations

import difflib
import time
from dataclasses import dataclass
from typing import Any

import numpy as np

from legent_gym.world.assets import registry
from legent_gym.world.generation.conditions import Catalog, GenerationError, normalise_name
from legent_gym.world.generation.floorplan import (
    FloorPlan,
    PlanFailed,
    add_door,
    build_floorplan,
    place_doors,
    place_windows,
    plan_grid,
)
from legent_gym.world.generation.furnish import SUPPORTS, WALL_GAP, Furnisher, RoomSpace
from legent_gym.world.generation.house import (
    REACH,
    AttemptFailed,
    main_component,
    place_spawns,
    scene_objects,
    scene_rooms,
)
from legent_gym.world.generation.plan.schema import (
    BESIDE_GAP,
    FACING_ANGLE,
    FAR_DISTANCE,
    FRONT_ANGLE,
    MIDDLE_CLEARANCE,
    NEAR_GAP,
    SIDE_ANGLE,
    TARGETED,
    WALL_CONTACT,
    Relation,
    ScenePlan,
    SolvedScene,
    SolveReport,
    load_plan,
)
from legent_gym.world.generation.roomtypes import ROOM_TYPES, ROOM_WORDS, room_type_of
from legent_gym.world.generation.small_objects import (
    SmallObjectPlacer,
    open_receptacle,
    receptacle_corners,
)
from legent_gym.world.generation.surfaces_and_lights import ceiling_light, light_point
from legent_gym.world.generation.validate import check_house
from legent_gym.world.geometry import local_footprint, turned_rect
from legent_gym.world.navigation import DEFAULT_AGENT_RADIUS, DEFAULT_RESOLUTION, NavGrid
from legent_gym.world.scene import Scene, Spawn

CELL_AREA = 2.3 * 2.3  # m^2 per floor-plan cell (the middle of the generator's cell sizes)
CELL_RANGE = (2.0, 2.6)
WALL_HEIGHT = 3.0
DFS_BRANCH = 3  # candidates tried per object before backtracking
DFS_BUDGET = 60  # commits per room before the search turns greedy
SUPPORT_PICKS = 8  # assets tried for a piece that planned small objects stand on
FIT_SHARE = 0.75  # ...until one that this share of their categories' models fit
SMALL_TRIES = 12  # assets tried for a small object or a tv on the piece the plan names
STRICT_BUDGET = 150  # commits per room of the search that meets every relation
ATTEMPTS = 6  # tries at a valid house
STRICT_ATTEMPTS = 3  # of which the first ones give up on a room that misses a relation
BUILT_ATTEMPTS = 3  # valid houses built before the one that lacks the fewest planned things is kept


# ---------------------------------------------------------------------------------------
# Names


def resolve_room_type(word: str) -> tuple[str, bool]:
    """The room type a word names, and whether it was a guess (the nearest word)."""
    exact = room_type_of(word)
    if exact is not None:
        return exact, False
    w = " ".join(word.lower().replace("_", " ").replace("-", " ").split())
    for part in reversed(w.split()):
        t = room_type_of(part)
        if t is not None:
            return t, True
    close = difflib.get_close_matches(w, list(ROOM_WORDS), n=1, cutoff=0.6)
    return (ROOM_WORDS[close[0]] if close else "living_room"), True


def nearest_category(catalog: Catalog, name: str) -> tuple[str | None, bool]:
    """The library category a name refers to and whether it was a guess: the name itself,
    else its words from the last (the head noun: "king size bed" -> bed), else the closest
    spelling of a known name; (None, True) when nothing is close."""
    try:
        return catalog.resolve_one(name), False
    except GenerationError:
        pass
    words = normalise_name(name).split()
    for k in range(len(words) - 1, -1, -1):
        for phrase in (" ".join(words[k:]), words[k]):
            try:
                return catalog.resolve_one(phrase), True
            except GenerationError:
                continue
    close = difflib.get_close_matches(normalise_name(name), sorted(catalog.aliases), n=1, cutoff=0.75)
    if close:
        return catalog.aliases[close[0]][0], True
    return None, True


# ---------------------------------------------------------------------------------------
# Relations: measured on footprints (x0, y0, x1, y1), yaws and the room's inner outline


def front_dirs(yaw_deg: np.ndarray) -> np.ndarray:
    """Unit front directions (N, 2) of yaws in degrees (a model's front is +y)."""
    a = np.radians(np.asarray(yaw_deg, dtype=np.float64))
    return np.column_stack([-np.sin(a), np.cos(a)])


def rect_gap(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Distance between rectangles ``a`` (N, 4) and one rectangle ``b`` (0 where they touch)."""
    gx = np.maximum(np.maximum(b[0] - a[:, 2], a[:, 0] - b[2]), 0.0)
    gy = np.maximum(np.maximum(b[1] - a[:, 3], a[:, 1] - b[3]), 0.0)
    return np.hypot(gx, gy)


def wall_gap(rects: np.ndarray, inner: np.ndarray) -> np.ndarray:
    """Distance from each rectangle (N, 4) to the nearest wall face of a rectilinear room
    outline ``inner`` (the rectangles inside it)."""
    out = np.full(len(rects), np.inf)
    n = len(inner)
    for k in range(n):
        p0, p1 = inner[k], inner[(k + 1) % n]
        seg = np.array([min(p0[0], p1[0]), min(p0[1], p1[1]), max(p0[0], p1[0]), max(p0[1], p1[1])])
        out = np.minimum(out, rect_gap(rects, seg))
    return out


def _angle(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Angle in degrees between rows of u and v (v need not be unit; 0 length: 180)."""
    norm = np.hypot(v[:, 0], v[:, 1])
    cos = (u * v).sum(axis=1) / np.where(norm > 1e-9, norm, 1.0)
    return np.where(norm > 1e-9, np.degrees(np.arccos(np.clip(cos, -1.0, 1.0))), 180.0)


def relation_scores(kind: str, rects: np.ndarray, yaws: np.ndarray, inner: np.ndarray,
                    target: tuple[np.ndarray, float] | None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """For candidate footprints (N, 4) and yaws (N,): (holds, score in [0, 1], measure)
    of one relation. ``target``: the target's footprint and yaw for targeted kinds."""
    centres = np.column_stack([(rects[:, 0] + rects[:, 2]) / 2, (rects[:, 1] + rects[:, 3]) / 2])
    if kind == "against_wall":
        g = wall_gap(rects, inner)
        return g <= WALL_CONTACT, np.clip(1.0 - (g - WALL_CONTACT), 0.0, 1.0), g
    if kind == "middle":
        g = wall_gap(rects, inner)
        return g >= MIDDLE_CLEARANCE, np.clip(g / MIDDLE_CLEARANCE, 0.0, 1.0), g
    assert target is not None
    trect, tyaw = target
    tc = np.array([(trect[0] + trect[2]) / 2, (trect[1] + trect[3]) / 2])
    gap = rect_gap(rects, trect)
    if kind == "near":
        return gap <= NEAR_GAP, np.clip(1.0 - (gap - NEAR_GAP) / 2.0, 0.0, 1.0), gap
    if kind == "far":
        d = np.hypot(centres[:, 0] - tc[0], centres[:, 1] - tc[1])
        return d >= FAR_DISTANCE, np.clip(d / FAR_DISTANCE, 0.0, 1.0), d
    if kind == "facing":
        ang = _angle(front_dirs(yaws), tc[None, :] - centres)
        return ang <= FACING_ANGLE, np.clip(1.0 - (ang - FACING_ANGLE) / 90.0, 0.0, 1.0), ang
    turn = {"in_front_of": 0.0, "left_of": 90.0, "right_of": -90.0}[kind]
    limit = FRONT_ANGLE if kind == "in_front_of" else SIDE_ANGLE
    direction = np.repeat(front_dirs(np.array([tyaw + turn])), len(rects), axis=0)
    ang = _angle(direction, centres - tc[None, :])
    holds = (ang <= limit) & (gap <= BESIDE_GAP)
    score = np.clip(1.0 - (ang - limit) / 90.0, 0.0, 1.0) * np.clip(1.0 - (gap - BESIDE_GAP) / 2.0, 0.0, 1.0)
    return holds, score, ang


def _credit(scored: tuple[np.ndarray, np.ndarray, np.ndarray]) -> np.ndarray:
    """A candidate's points for one relation: 1 where it holds, else less than half, more
    as it gets closer (so meeting a relation outweighs any nearness and preference)."""
    holds, score, _ = scored
    return np.where(holds, 1.0, 0.45 * score)


def _measure_text(kind: str, value: float) -> str:
    if kind in ("facing", "in_front_of", "left_of", "right_of"):
        return f"{value:.0f} deg"
    return f"{value:.2f} m"


# ---------------------------------------------------------------------------------------
# Candidate poses around a target (footprints: ``turned[q]`` is a piece's footprint about
# its origin at quarter turn q)


def _beside(t: np.ndarray, turned: np.ndarray, gaps: np.ndarray) -> np.ndarray:
    """Poses (N, 4) beside each side of rectangle ``t``, ``gaps`` away from it, centred on
    the side or flush with either end of it, at every quarter turn."""
    out = []
    for q in range(4):
        lx0, ly0, lx1, ly1 = turned[q]
        along_y = [t[1] - ly0, t[3] - ly1, (t[1] + t[3] - ly0 - ly1) / 2]
        along_x = [t[0] - lx0, t[2] - lx1, (t[0] + t[2] - lx0 - lx1) / 2]
        for g in gaps:
            out += [(t[2] + g - lx0, y, q) for y in along_y] + [(t[0] - g - lx1, y, q) for y in along_y]
            out += [(x, t[3] + g - ly0, q) for x in along_x] + [(x, t[1] - g - ly1, q) for x in along_x]
    a = np.asarray(out, dtype=np.float64)
    return np.column_stack([a, np.zeros(len(a))])


def _ahead(t: np.ndarray, tq: int, turned: np.ndarray, bbox: np.ndarray) -> np.ndarray:
    """Poses (N, 4) centred on the front ray of rectangle ``t`` (quarter turn ``tq``),
    every 0.3 m to the far side of ``bbox``, at every quarter turn."""
    d = front_dirs(np.array([tq * 90.0]))[0]
    c = np.array([(t[0] + t[2]) / 2, (t[1] + t[3]) / 2])
    reach = float(np.hypot(bbox[2] - bbox[0], bbox[3] - bbox[1]))
    steps = np.arange(0.6, reach, 0.3)
    pts = c[None, :] + steps[:, None] * d[None, :]
    out = []
    for q in range(4):
        lx0, ly0, lx1, ly1 = turned[q]
        out.append(np.column_stack([pts[:, 0] - (lx0 + lx1) / 2, pts[:, 1] - (ly0 + ly1) / 2,
                                    np.full(len(pts), q), np.zeros(len(pts))]))
    return np.concatenate(out)


def _to_wall(poses: np.ndarray, turned: np.ndarray, space: RoomSpace) -> np.ndarray:
    """``poses`` (N, 4) moved straight back against each wall face they look onto within a
    metre (the same gap to the wall as the furnisher's wall poses)."""
    q = poses[:, 2].astype(np.int64) % 4
    rects = np.column_stack([poses[:, 0], poses[:, 1], poses[:, 0], poses[:, 1]]) + turned[q]
    out = []
    for p0, e, n, length, _, _ in space.edges():
        p1 = p0 + e * length
        if abs(n[0]) > 0.5:  # a wall along y: x = p0[0]
            lo, hi = min(p0[1], p1[1]), max(p0[1], p1[1])
            over = (rects[:, 3] > lo) & (rects[:, 1] < hi)
            d = rects[:, 0] - p0[0] if n[0] > 0 else p0[0] - rects[:, 2]
            shift = np.column_stack([-np.sign(n[0]) * (d - WALL_GAP), np.zeros(len(d))])
        else:  # a wall along x: y = p0[1]
            lo, hi = min(p0[0], p1[0]), max(p0[0], p1[0])
            over = (rects[:, 2] > lo) & (rects[:, 0] < hi)
            d = rects[:, 1] - p0[1] if n[1] > 0 else p0[1] - rects[:, 3]
            shift = np.column_stack([np.zeros(len(d)), -np.sign(n[1]) * (d - WALL_GAP)])
        pick = over & (d > WALL_GAP + 1e-6) & (d < 1.0)
        moved = poses[pick].copy()
        moved[:, :2] += shift[pick]
        out.append(moved)
    return np.concatenate(out) if out else np.zeros((0, 4))


# ---------------------------------------------------------------------------------------
# The solver


@dataclass
class _Item:
    """One instance of a planned object."""

    room: int
    key: str  # "room/object"
    name: str
    index: int
    category: str
    on: str | None
    relations: list[Relation]
    piece: int | None = None  # index in the furnisher's pieces
    small: int | None = None  # index in the small placer's list


def _needs(item: _Item) -> set[str]:
    return {r.target for r in item.relations if r.target} | ({item.on} if item.on else set())


def _order(items: list[_Item]) -> list[_Item]:
    """Targets before the objects that refer to them (stable; cycles keep plan order)."""
    out: list[_Item] = []
    placed: set[str] = set()
    pending = list(items)
    while pending:
        names = {i.name for i in pending}
        ready = [i for i in pending if not (_needs(i) & names - {i.name}) or _needs(i) <= placed]
        if not ready:
            ready = [pending[0]]
        for i in ready:
            out.append(i)
            pending.remove(i)
        placed |= {i.name for i in ready if i.name not in {p.name for p in pending}}
    return out


def _floor_order(items: list[_Item]) -> list[_Item]:
    """The order in which the search places a room's floor pieces: a piece that others
    refer to, then at once the pieces whose targets are all placed (most relations
    first), and the pieces that refer to nothing last (they fit along any free wall)."""
    out: list[_Item] = []
    pending = list(items)
    names = {i.name for i in items}
    targets = {r.target for i in items for r in i.relations if r.target}
    while pending:
        placed = {i.name for i in out}
        waiting = {i.name for i in pending}
        ready = [i for i in pending if _needs(i) & names and (_needs(i) & names) - {i.name} <= placed - waiting]
        if ready:
            pick = max(ready, key=lambda i: len(i.relations))
        else:
            gates = [i for i in pending if i.name in targets]
            free = [i for i in gates if not ((_needs(i) & names) - {i.name}) - placed]
            pick = (free or gates or pending)[0]
        out.append(pick)
        pending.remove(pick)
    return out


class _Solver:
    def __init__(self, plan: ScenePlan, seed: int, catalog: Catalog, report: SolveReport):
        self.plan, self.seed, self.catalog, self.report = plan, seed, catalog, report
        self._sizes: dict[str, np.ndarray] = {}
        self.types: list[str] = []
        for room in plan.rooms:
            rtype, guessed = resolve_room_type(room.type)
            if guessed:
                report.warnings.append(f"room {room.name!r}: type {room.type!r} is not known; built as a "
                                       f"{ROOM_TYPES[rtype].name}")
            self.types.append(rtype)
        self.items: list[list[_Item]] = []
        dropped: set[str] = set()
        for r, room in enumerate(plan.rooms):
            items = []
            for obj in room.objects:
                wanted = obj.asset or obj.name
                cat, guessed = nearest_category(catalog, wanted)
                key = f"{room.name}/{obj.name}"
                if cat is None:
                    report.warnings.append(f"dropped {key}: {wanted!r} is no asset category and none is close "
                                           f"(known: {', '.join(catalog.categories)})")
                    dropped.add(key)
                    continue
                if guessed:
                    report.mapped[wanted] = cat
                items += [_Item(r, key, obj.name, k, cat, obj.on, list(obj.relations)) for k in range(obj.count)]
            self.items.append(items)
        for items in self.items:  # relations to dropped objects cannot be met
            for item in items:
                room_name = plan.rooms[item.room].name
                if item.on and f"{room_name}/{item.on}" in dropped:
                    report.warnings.append(f"{item.key}: stands on {item.on!r}, which was dropped; placed on "
                                           "any surface")
                    item.on = None
                keep = [rel for rel in item.relations if f"{room_name}/{rel.target}" not in dropped]
                for rel in item.relations:
                    if rel not in keep:
                        report.unmet.append(f"{item.key} {rel.kind} {rel.target}: the target was dropped")
                item.relations = keep

    # -- floor plan ------------------------------------------------------------------
    def floor_plan(self, rng: np.random.Generator) -> tuple[FloorPlan, list[str], Furnisher]:
        targets = []
        for room, rtype in zip(self.plan.rooms, self.types):
            lo, hi = ROOM_TYPES[rtype].cells
            if room.size is None:
                targets.append(int(rng.integers(lo, hi + 1)))
            else:
                targets.append(int(min(8, max(1, round(room.size / CELL_AREA)))))
        index = {r.name: k for k, r in enumerate(self.plan.rooms)}
        wanted = [(index[a], index[b]) for a, b in self.plan.doors]
        best: tuple[FloorPlan, list[str], Furnisher] | None = None
        for _ in range(8):
            try:
                grid = plan_grid(self.types, rng, cell_range=CELL_RANGE, targets=targets)
                fp = build_floorplan(grid, self.types, wall_height=WALL_HEIGHT)
                place_doors(fp, rng, openness=1.0)
            except PlanFailed:
                continue
            missing: list[str] = []
            ids = fp.room_ids
            for a, b in wanted:
                linked = any(set(d.connects) == {ids[a], ids[b]} for d in fp.doors)
                if linked:
                    continue
                if (min(a, b), max(a, b)) not in fp.adjacency():
                    missing.append(f"door between {self.plan.rooms[a].name!r} and {self.plan.rooms[b].name!r}: "
                                   "the rooms are not adjacent in the floor plan")
                elif not add_door(fp, (a, b), rng):
                    missing.append(f"door between {self.plan.rooms[a].name!r} and {self.plan.rooms[b].name!r}: "
                                   "no room for a door on their shared wall")
            place_windows(fp, rng)
            f = Furnisher(fp, self.catalog, rng)
            if not all(f.room_ok(space) for space in f.spaces):  # a door's mouth is cut off
                continue
            if best is None or len(missing) < len(best[1]):
                best = (fp, missing, f)
            if not missing:
                break
        if best is None:
            raise _AttemptFailed(f"no floor plan for rooms {self.types} with every room walkable between its doors")
        return best

    # -- furniture -------------------------------------------------------------------
    def candidates(self, f: Furnisher, space: RoomSpace, item: _Item, model: Any,
                   rng: np.random.Generator) -> np.ndarray:
        """Candidate poses (N, 4: x, y, quarter turns, preference): the furnisher's wall,
        corner and free-floor poses; a grid over the room for ``middle``; around each placed
        target, poses beside each of its sides (several gaps, centred or flush with either
        end of the side, every turn) and along its front ray; for ``against_wall``, each of
        these also pushed against the nearest wall face behind it."""
        poses = [f.anchor_poses(space, model)]
        if any(r.kind == "middle" for r in item.relations):  # a grid over the room, every 0.3 m
            bb = space.bbox
            gx, gy = np.meshgrid(np.arange(bb[0] + 0.3, bb[2], 0.3), np.arange(bb[1] + 0.3, bb[3], 0.3))
            n = gx.size
            poses.append(np.column_stack([np.tile(gx.ravel(), 4), np.tile(gy.ravel(), 4),
                                          np.repeat(np.arange(4), n), np.zeros(4 * n)]))
        targets = self.targets_of(f, item)
        if targets:
            local = local_footprint(model)
            turned = np.array([turned_rect(local, q) for q in range(4)])  # (4, 4) per quarter turn
            gaps = np.array([space.margin + 0.03, space.margin + 0.3, 0.75])
            out = []
            for target in targets:
                t = f.pieces[target].rect
                out.append(_beside(t, turned, gaps))
                out.append(_ahead(t, f.pieces[target].q, turned, space.bbox))
            near = np.concatenate(out)
            poses.append(near)
            if any(r.kind == "against_wall" for r in item.relations):
                poses.append(_to_wall(near, turned, space))
        return np.concatenate(poses) if poses else np.zeros((0, 4))

    def targets_of(self, f: Furnisher, item: _Item) -> list[int]:
        names = {r.target for r in item.relations if r.target}
        return [i.piece for i in self.items[item.room] if i.name in names and i.piece is not None
                and f.pieces[i.piece].on_floor]

    def scores(self, f: Furnisher, space: RoomSpace, item: _Item, rects: np.ndarray,
               qs: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Per candidate: the soft score (the credit of each relation) and whether every
        relation that can be measured now (its target placed) holds."""
        total = np.zeros(len(rects))
        met = np.ones(len(rects), dtype=bool)
        yaws = qs * 90.0
        for rel in item.relations:
            if rel.kind in TARGETED:
                targets = [i for i in self.items[item.room] if i.name == rel.target and i.piece is not None
                           and i is not item]
                if not targets:
                    continue
                best = np.zeros(len(rects))
                holds = np.zeros(len(rects), dtype=bool)
                for t in targets:
                    p = f.pieces[t.piece]  # type: ignore[index]
                    scored = relation_scores(rel.kind, rects, yaws, space.inner, (p.rect, p.yaw_deg))
                    best = np.maximum(best, _credit(scored))
                    holds |= scored[0]
                total += best
                met &= holds
            else:
                scored = relation_scores(rel.kind, rects, yaws, space.inner, None)
                total += _credit(scored)
                met &= scored[0]
        return total, met

    def pick(self, f: Furnisher, item: _Item) -> tuple[str, int, Any]:
        """An asset for a floor piece: for a piece that planned small objects stand on,
        the first of a few picks on whose open surfaces most models of each of their
        categories fit (else the pick where the most fit)."""
        pick = f.pick(item.category)
        cats = {i.category for i in self.items[item.room] if i.on == item.name and self.catalog.is_small(i.category)}
        if not cats:
            return pick
        best, best_share = pick, -1.0
        for k in range(SUPPORT_PICKS):
            if k:
                pick = f.pick(item.category)
            share = min(self.fits(pick[2], c) for c in cats)
            if share >= FIT_SHARE:
                return pick
            if share > best_share:
                best, best_share = pick, share
        return best

    def fits(self, model: Any, category: str) -> float:
        """The share of a sample of a small category's models (its assets' variants) that
        fit an open receptacle of ``model``: footprint, with room to turn a little, and
        clearance."""
        if category not in self._sizes:
            ids = self.catalog.by_category[category]
            self._sizes[category] = np.array([registry.make(a, v).size for a in ids for v in (0, 250, 500, 750)])
        sizes = self._sizes[category]
        fit = np.zeros(len(sizes), dtype=bool)
        for rec in model.receptacles:
            if not open_receptacle(model, rec):
                continue
            room = 2 * np.asarray(rec.half_size) - 0.06
            fit |= (sizes[:, 0] <= room[0]) & (sizes[:, 1] <= room[1]) & (sizes[:, 2] <= rec.clearance)
        return float(fit.mean())

    def furnish_room(self, f: Furnisher, space: RoomSpace, rng: np.random.Generator, strict_only: bool = False) -> bool:
        """Place the room's floor furniture: first a depth-first search in which every
        piece meets each of its relations whose target is already placed (targets come
        first), with forward checking (a placement that leaves a later piece no pose meeting
        its relations is not taken) and backjumping to the target of a piece that cannot
        meet its relations; if that search runs out of its budget, a search that only keeps
        the hard constraints, best soft score first (what it misses is reported)."""
        floor = _floor_order([i for i in self.items[space.index] if self.is_floor(i.category)])
        picks = [self.pick(f, i) for i in floor]
        noise = [rng.random(4096) for _ in floor]  # the same tie-breaking for each look at a level
        level: dict[str, list[int]] = {}
        for k, i in enumerate(floor):
            level.setdefault(i.name, []).append(k)
        # Levels whose pieces a piece's relations refer to, and the later pieces that refer to it.
        refs = [sorted({j for r in i.relations if r.target for j in level.get(r.target, []) if j < k})
                for k, i in enumerate(floor)]
        # The later pieces with relations to pieces all placed once k is (forward checking).
        checked = [[j for j in range(k + 1, len(floor)) if refs[j] and refs[j][-1] <= k] for k in range(len(floor))]
        cache: dict[tuple, list] = {}
        found: dict[tuple, tuple] = {}

        def state(k: int) -> tuple:
            return k, tuple((j, f.pieces[j].x, f.pieces[j].y, f.pieces[j].q) for j in space.pieces)

        def candidates(k: int) -> tuple:
            """Per state: candidate poses, footprints, front zones, soft score and whether
            the relations hold (before the hard checks)."""
            key = state(k)
            if key not in found:
                item, (asset, variant, model) = floor[k], picks[k]
                poses = self.candidates(f, space, item, model, rng)
                qs = poses[:, 2].astype(np.int64)
                rects, fronts = f.footprints(item.category, asset, variant, model, poses[:, 0], poses[:, 1], qs)
                score, met = self.scores(f, space, item, rects[:, 0], qs % 4)
                score = score + 0.05 * poses[:, 3] / 10.0 + 0.01 * noise[k][np.arange(len(poses)) % len(noise[k])]
                found[key] = (poses, rects, fronts, score, met, np.array([model.size[2]]))
            return found[key]

        def can_meet(k: int) -> bool:
            """Whether piece k has a valid pose meeting its relations, as things stand."""
            key = state(k)
            if key in cache:
                return any(o[5] for o in cache[key])
            poses, rects, fronts, _, met, tall = candidates(k)
            idx = np.nonzero(met)[0]
            return bool(len(idx)) and bool(f.valid(space, rects[idx], fronts[idx], tall).any())

        def options(k: int) -> list[tuple[float, float, int, np.ndarray, np.ndarray, bool]]:
            """Valid poses of piece k, best soft score first."""
            key = state(k)
            if key in cache:
                return cache[key]
            poses, rects, fronts, score, met, tall = candidates(k)
            idx = np.nonzero(f.valid(space, rects, fronts, tall))[0]
            order = idx[np.argsort(-score[idx], kind="stable")]
            out = [(float(poses[c, 0]), float(poses[c, 1]), int(poses[c, 2]) % 4, rects[c, 0], fronts[c, 0],
                    bool(met[c])) for c in order]
            cache[key] = out
            return out

        def place(k: int, pose) -> bool:
            item, (asset, variant, model) = floor[k], picks[k]
            x, y, q, rect, front, _ = pose
            item.piece = f.add_piece(space, item.category, asset, variant, model, x, y, q, rect, front)
            if f.room_ok(space):
                return True
            unplace(k)
            return False

        def unplace(k: int) -> None:
            f.remove_last(space)
            floor[k].piece = None

        def forward_ok(k: int) -> bool:
            """Each later piece whose targets are all placed once k is still has a pose
            meeting its relations."""
            return all(can_meet(j) for j in checked[k])

        budget = [STRICT_BUDGET]

        def strict(k: int) -> int:
            """len(floor) when levels k.. are placed with their relations met; else the
            level (< k) to go back to."""
            if k == len(floor):
                return k
            back = k - 1
            tried = 0
            for pose in options(k):
                if not pose[5]:
                    break  # the rest miss a relation too (met ones rank first)
                if tried >= DFS_BRANCH or budget[0] <= 0:
                    break
                budget[0] -= 1
                if not place(k, pose):
                    continue
                if not forward_ok(k):
                    unplace(k)
                    continue
                tried += 1
                jump = strict(k + 1)
                if jump == len(floor):
                    return jump
                unplace(k)
                if jump < k:
                    return jump
            return back

        if strict(0) == len(floor):
            return True
        for k in range(len(floor) - 1, -1, -1):  # take back a partial placement
            if floor[k].piece is not None:
                unplace(k)
        if strict_only:
            return False
        loose = [DFS_BUDGET]

        def dfs(k: int) -> bool:
            if k == len(floor):
                return True
            tried = 0
            for pose in options(k):
                if tried >= DFS_BRANCH or loose[0] <= 0:
                    break
                loose[0] -= 1
                if not place(k, pose):
                    continue
                tried += 1
                if dfs(k + 1):
                    return True
                unplace(k)
            return False

        if dfs(0):
            return False
        # Greedy, dropping what fits nowhere (reported).
        for k, item in enumerate(floor):
            for pose in options(k)[:6]:
                if place(k, pose):
                    break
            else:
                self.report.unmet.append(f"{item.key}: no room for a {item.category} in room "
                                         f"{self.plan.rooms[item.room].name!r} (copy {item.index + 1})")
        return False

    def is_floor(self, category: str) -> bool:
        return self.catalog.is_furniture(category) and self.catalog.describe(category).placement != "surface"

    def surface_furniture(self, f: Furnisher) -> None:
        for items in self.items:
            for item in items:
                if self.catalog.is_small(item.category) or self.is_floor(item.category):
                    continue
                supports = self.support_pieces(f, item) or [
                    i.piece for i in items if i.piece is not None and
                    f.pieces[i.piece].category in SUPPORTS.get(item.category, ())]
                for s in supports:
                    if not any(p.support == s for p in f.pieces) and f.put_on_support(s, item.category, tries=SMALL_TRIES):
                        item.piece = len(f.pieces) - 1
                        break
                else:
                    self.report.unmet.append(f"{item.key}: no free support for a {item.category}"
                                             + (f" on {item.on!r}" if item.on else ""))

    def support_pieces(self, f: Furnisher, item: _Item) -> list[int]:
        if not item.on:
            return []
        return [i.piece for i in self.items[item.room] if i.name == item.on and i.piece is not None]

    def small_objects(self, f: Furnisher, placer: SmallObjectPlacer) -> None:
        for items in self.items:
            for item in items:
                if not self.catalog.is_small(item.category):
                    continue
                room_pieces = {i.piece for i in items if i.piece is not None}
                wanted = set(self.support_pieces(f, item))
                pools = ([[s for s in placer.surfaces if s.piece in wanted]] if wanted else []) + \
                        [[s for s in placer.surfaces if s.piece in room_pieces]]
                done = False
                for pool in pools:
                    for s in pool:
                        if placer.put(s, item.category, tries=SMALL_TRIES):
                            item.small = len(placer.placed) - 1
                            done = True
                            break
                    if done:
                        break
                if not done:
                    self.report.unmet.append(f"{item.key}: no free reachable surface for a {item.category} in room "
                                             f"{self.plan.rooms[item.room].name!r}")
                elif wanted and placer.placed[item.small].support not in wanted:  # type: ignore[index]
                    self.report.unmet.append(f"{item.key} on {item.on}: no room on it; put on another surface "
                                             "of the room")

    # -- one attempt ------------------------------------------------------------------
    def attempt(self, rng: np.random.Generator, strict: bool = False) -> tuple[Scene, list[str]]:
        """One house. ``strict``: give up (:class:`_AttemptFailed`) as soon as a room's
        furniture cannot meet every relation, rather than place it missing some."""
        for items in self.items:
            for item in items:
                item.piece = item.small = None
        fp, missing, f = self.floor_plan(rng)
        for space in f.spaces:
            if not self.furnish_room(f, space, rng, strict_only=strict) and strict:
                raise _AttemptFailed(f"room {self.plan.rooms[space.index].name!r}: no layout meeting every relation "
                                     "found in the search budget")
        self.surface_furniture(f)
        rooms = scene_rooms(fp, rng)
        lights = [ceiling_light(light_point(p), WALL_HEIGHT) for p in fp.polygons]
        base: dict[str, Any] = dict(name=self.plan.name or f"plan-{self.seed}", seed=self.seed, rooms=rooms,
                                    walls=fp.walls, doors=fp.doors, windows=fp.windows, lights=lights)
        furniture, _, _ = scene_objects(fp, f.pieces, [])
        bare = Scene(**base, objects=furniture, agent=Spawn(position=(0.0, 0.0)))
        nav = NavGrid.from_scene(bare, agent_radius=DEFAULT_AGENT_RADIUS, resolution=DEFAULT_RESOLUTION)
        component = main_component(nav, fp, f.spaces)
        placer = SmallObjectPlacer(f.pieces, self.catalog, rng, max_per_surface=4,
                                   reachable=lambda p, rec: nav.can_reach(receptacle_corners(p, rec), REACH, component))
        self.small_objects(f, placer)
        try:
            agent, user = place_spawns(nav, component, rng, user=True, min_distance=1.5)
        except AttemptFailed as err:
            raise _AttemptFailed(str(err)) from None
        _, objects, ids = scene_objects(fp, f.pieces, placer.placed)
        # An annotated asset goes with its import entry, so that the scene rebuilds it anywhere.
        entries = {a: registry.imported_entry(a) for a in sorted({o.asset for o in objects})}
        scene = Scene(**base, objects=objects, agent=agent, user=user,
                      assets=[e for e in entries.values() if e is not None])
        problems = check_house(scene, nav, reach=REACH)
        if problems:
            raise _AttemptFailed("the house fails its checks: " + "; ".join(problems[:3]))
        n_furniture = len(f.pieces)
        self.report.objects = {}
        for items in self.items:
            for item in items:
                copies = self.report.objects.setdefault(item.key, [])
                if item.piece is not None:
                    copies.append(ids[item.piece])
                elif item.small is not None:
                    copies.append(n_furniture + item.small)
                else:
                    copies.append(None)
        return scene, missing + self.relations_unmet(f)

    def relations_unmet(self, f: Furnisher) -> list[str]:
        out = []
        for items in self.items:
            for item in items:
                if item.piece is None or not f.pieces[item.piece].on_floor:
                    continue
                p = f.pieces[item.piece]
                inner = f.spaces[p.room].inner
                for rel in item.relations:
                    targets = [f.pieces[i.piece] for i in items if i.name == rel.target and i.piece is not None]
                    if rel.kind in TARGETED and not targets:
                        out.append(f"{item.key} #{item.index + 1} {rel.kind} {rel.target}: the target was not placed")
                        continue
                    results = [relation_scores(rel.kind, p.rect[None, :], np.array([p.yaw_deg]), inner,
                                               (t.rect, t.yaw_deg)) for t in targets] or \
                        [relation_scores(rel.kind, p.rect[None, :], np.array([p.yaw_deg]), inner, None)]
                    if not any(bool(r[0][0]) for r in results):
                        best = min(float(r[2][0]) for r in results) if rel.kind != "middle" and rel.kind != "far" \
                            else max(float(r[2][0]) for r in results)
                        what = f"{rel.kind} {rel.target}" if rel.target else rel.kind
                        out.append(f"{item.key} #{item.index + 1} {what}: measured {_measure_text(rel.kind, best)}")
        return out


class _AttemptFailed(Exception):
    pass


def solve_plan(plan: ScenePlan | dict, seed: int = 0, catalog: Catalog | None = None) -> SolvedScene:
    """A validated scene for a plan (see the module docstring): the same plan and seed give
    the same scene. Raises :class:`GenerationError` when no valid house comes out of
    :data:`ATTEMPTS` tries (naming the last problem)."""
    started = time.perf_counter()
    plan = load_plan(plan)
    catalog = catalog or Catalog.from_registry()
    last = ""
    master = np.random.default_rng(int(seed))
    best: tuple[tuple[int, int], SolvedScene] | None = None
    tries = 0
    for k in range(ATTEMPTS):
        report = SolveReport()
        solver = _Solver(plan, int(seed), catalog, report)
        rng = master.spawn(1)[0]
        try:
            scene, unmet = solver.attempt(rng, strict=k < STRICT_ATTEMPTS)
        except _AttemptFailed as err:
            last = str(err)
            continue
        report.unmet += unmet
        tries += 1
        # Houses that lack planned objects or doors are worse than ones that miss relations.
        cost = (sum(" measured " not in u for u in report.unmet), len(report.unmet))
        if best is None or cost < best[0]:
            best = (cost, SolvedScene(scene, report))
        if not report.unmet or tries >= BUILT_ATTEMPTS:
            break
    if best is None:
        raise GenerationError(f"no valid house for the plan in {ATTEMPTS} attempts (last: {last})")
    best[1].report.seconds = time.perf_counter() - started
    return best[1]

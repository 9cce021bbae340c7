"""Which goals an agent can achieve: where it can stand to see an object or act on it.

One definition serves two clients, so they cannot disagree: the task samplers draw only
goals that pass these checks (a goal no agent could achieve is never asked for), and the
experts walk to stands that pass the same checks (so a sampled goal always has a plan).

A *stand* is a walkable point of the **planning grid**: the episode's navigation grid with
obstacles inflated by :data:`PLANNING_MARGIN` more than the body's radius and the user
standing as an obstacle, so that a straight walk between stands of the grid does not graze
anything. What a stand is good for (its *purpose*):

* ``"sight"``: the object is within reach (horizontally, to its footprint) and a ray from
  the eye to its centre meets it first, from the stand and from points around it (arrival is
  never exact): GoTo's success test, once the agent faces it;
* ``"aim"``: a view ray (pitch within the head's range) meets the object within reach:
  ``interact()`` can grab it;
* ``"put"``: holding ``item``, a view ray meets a free spot of the object's surface within
  reach: ``interact()`` puts the item there;
* ``"see"``: a ray meets the object within :data:`FIND_DISTANCE` (WhereIs's ``find``).

Reach checks keep :data:`STAND_SLACK` metres in hand for the same reason.

The samplers also count the actions a goal takes as the experts walk (:func:`walk_leg`,
:func:`stand_leg`, :func:`user_leg`) and draw only goals within :data:`PLAN_BUDGET`.
"""

from __future__ import annotations

import math
from collections import OrderedDict
from collections.abc import Iterator, Sequence
from dataclasses import dataclass

import numpy as np

from legent_gym.tasks.base import MAX_ACTIONS, TaskContext
from legent_gym.world.navigation import NavGrid
from legent_gym.world.rays import cast_rays

__all__ = ["FIND_DISTANCE", "PLANNING_MARGIN", "PLAN_BUDGET", "PURPOSES", "STAND_SLACK", "USER_STOP",
           "Leg", "aim_points", "aims", "centre_in_sight", "merge_corners", "planning_grid", "put_spot", "put_spots",
           "seen_point", "stand_candidates", "stand_leg", "stand_ok", "stands", "user_leg", "user_stand", "walk_leg", "walk_path",
           "yaw_pitch_to"]

#: Extra clearance (metres) kept from obstacles beyond the body's radius: a straight segment
#: between walkable cells may pass half a cell closer to a corner than the cells do, and the
#: body's sweep stops at the first touch.
PLANNING_MARGIN = 0.06
#: Metres of reach a stand keeps in hand: the agent arrives within a few centimetres of it.
STAND_SLACK = 0.08
#: How far from the stand the sight test is repeated (the arrival error it must survive).
SIGHT_JITTER = 0.04
#: ``find(a)`` stops once ``a`` is this close (horizontally) and in sight (LEGENT).
FIND_DISTANCE = 3.0
#: ``goto_user()`` stops this far (horizontally) from the user (ComeHere's success is < 2 m).
USER_STOP = 1.0
#: The experts' walk (LEGENT's): turn first when the heading error is larger than this
#: (degrees), at most MAX_TURN degrees a turn, at most MAX_MOVE metres a move.
ANGLE_TOLERANCE, MAX_TURN, MAX_MOVE = 1.0, 90.0, 2.0
#: Path corners closer than this (metres) to the one before are dropped (LEGENT).
MIN_CORNER_GAP = 0.01
#: The most actions the samplers let a goal's expert plan take: the cap on actions
#: (:data:`legent_gym.tasks.base.MAX_ACTIONS`) less a few for what the estimate of
#: :func:`walk_leg` does not see (a sidestep, an aim that needs a second look).
PLAN_BUDGET = MAX_ACTIONS - 3
PURPOSES = ("sight", "aim", "put", "see")

#: Fractions of an object's half extents (x, y) and of its height (z) where aim points lie.
_AIM_XY = (0.0, -0.5, 0.5, -0.8, 0.8)
_AIM_Z = (0.5, 0.9, 0.2, 0.7, 0.35)
_AIM_FRACTIONS = np.array([(fx, fy, fz) for fz in _AIM_Z for fx in _AIM_XY for fy in _AIM_XY])
# The centre and the top's centre first, then the rest in a fixed shuffled order, so that
# every chunk of rays (see _first_hits) samples the whole object.
_AIM_FRACTIONS = np.vstack([_AIM_FRACTIONS[[0, 25]],
                            np.delete(_AIM_FRACTIONS, [0, 25], axis=0)[np.random.default_rng(0).permutation(123)]])
#: Rays cast at once: a chunk, then the next only if no ray of it served.
_CHUNK = 16
_SURFACE_FRACTIONS = np.array([(fx, fy) for fx in np.linspace(-0.8, 0.8, 5) for fy in np.linspace(-0.8, 0.8, 5)])
_GRIDS: OrderedDict[tuple, tuple[NavGrid, NavGrid | None]] = OrderedDict()
#: The planning grids without the user, per house and margin (None: not made yet, the
#: house seen once).
_BASES: OrderedDict[tuple, tuple[NavGrid, NavGrid | None]] = OrderedDict()
#: Planning grids kept (this episode's two margins, and the last one's), and the distance
#: fields each keeps: a field of a FourRoom house is about a megabyte.
_GRID_CACHE_SIZE, _FIELDS_PER_GRID = 4, 16


def yaw_pitch_to(eye: Sequence[float] | np.ndarray, point: Sequence[float] | np.ndarray) -> tuple[float, float]:
    """The yaw and pitch (degrees; + pitch looks down) that look from ``eye`` at ``point``."""
    dx, dy, dz = point[0] - eye[0], point[1] - eye[1], point[2] - eye[2]
    return math.degrees(math.atan2(dy, dx)), math.degrees(math.atan2(-dz, math.hypot(dx, dy)))


# -- the planning grid -------------------------------------------------------------------------


def planning_grid(ctx: TaskContext, margin: float = PLANNING_MARGIN) -> NavGrid:
    """The episode's grid with obstacles inflated by ``margin`` more and the user (where it
    stands now) as an obstacle. Cached: the same grid for a sampler and for every expert
    call until the user moves."""
    nav = ctx.nav
    user = ctx.user.position if ctx.scene.user is not None else None
    key = (id(nav), margin, None if user is None else (round(float(user[0]), 2), round(float(user[1]), 2)))
    hit = _GRIDS.get(key)
    if hit is not None and hit[1] is not None:
        _GRIDS.move_to_end(key)
        return hit[1]

    def made(obstacles: np.ndarray) -> NavGrid:
        return NavGrid(nav.origin, nav.resolution, nav.floor, nav.walls, obstacles, nav.agent_radius + margin,
                       scene=nav.scene, footprints=nav.footprints)

    if user is None:
        grid = _cached(_BASES, key[:2], nav, lambda: made(nav.obstacles))
    else:
        disc = np.zeros(nav.shape, dtype=bool)
        radius = ctx.user.options.radius
        window = nav.raster.window(user[0] - radius, user[1] - radius, user[0] + radius, user[1] + radius)
        if window is not None:
            sl, cx, cy = window  # cell centres: origin + (index + 0.5) * resolution
            disc[sl] = np.hypot(cx - user[0], cy - user[1]) <= radius
        base = _BASES.get(key[:2])
        if base is None:
            # The house's first place of the user: its grid made at once. Later ones (a kept
            # house) add the user's disc to the grid without the user, made once per house
            # and margin (NavGrid.with_obstacles: the same grid, cheaper).
            grid = made(nav.obstacles | disc)
            _remember(_BASES, key[:2], nav, None)
        else:
            grid = _cached(_BASES, key[:2], nav, lambda: made(nav.obstacles)).with_obstacles(disc)
    grid.cache_size = _FIELDS_PER_GRID
    _remember(_GRIDS, key, nav, grid)
    return grid


def _cached(cache: OrderedDict[tuple, tuple[NavGrid, NavGrid | None]], key: tuple, nav: NavGrid,
            make) -> NavGrid:
    """``cache[key]``'s grid, made with ``make()`` if missing or None."""
    hit = cache.get(key)
    if hit is not None and hit[1] is not None:
        cache.move_to_end(key)
        return hit[1]
    grid = make()
    _remember(cache, key, nav, grid)
    return grid


def _remember(cache: OrderedDict[tuple, tuple[NavGrid, NavGrid | None]], key: tuple, nav: NavGrid,
              grid: NavGrid | None) -> None:
    """Keep ``grid`` as ``cache[key]`` (the least recently used of :data:`_GRID_CACHE_SIZE`
    dropped)."""
    cache[key] = (nav, grid)  # the nav is kept so that its id is not reused while cached
    cache.move_to_end(key)
    if len(cache) > _GRID_CACHE_SIZE:
        cache.popitem(last=False)


def stand_candidates(ctx: TaskContext, object_id: int, reach: float, start: Sequence[float],
                     grid: NavGrid | None = None, stride: int = 1) -> np.ndarray:
    """Points (N, 2) of ``grid`` (default: the planning grid) reachable from ``start`` from
    which the object's footprint is within ``reach`` with no wall between, geodesically
    nearest to ``start`` first. ``stride`` > 1 keeps one cell in ``stride`` along each axis
    (a coarser, cheaper scan)."""
    grid = planning_grid(ctx) if grid is None else grid
    return _near(grid, ctx.footprint(object_id), reach, start, stride)


def _near(grid: NavGrid, corners: np.ndarray, reach: float, start: Sequence[float], stride: int = 1) -> np.ndarray:
    """Walkable points of ``grid`` reachable from ``start`` within ``reach`` of the rectangle
    ``corners`` (no wall between), geodesically nearest to ``start`` first."""
    component = grid.component(start)
    if component == 0:
        return np.zeros((0, 2))
    cells, _ = grid.reach_cells(corners, reach, component)
    if stride > 1 and len(cells):
        cells = cells[(cells[:, 0] % stride == 0) & (cells[:, 1] % stride == 0)]
    if len(cells) == 0:
        return np.zeros((0, 2))
    field = grid.distance_field(start)
    dist = field[cells[:, 0], cells[:, 1]]
    order = np.argsort(dist, kind="stable")
    order = order[np.isfinite(dist[order])]
    cells = cells[order]
    return np.column_stack([grid.origin[0] + (cells[:, 1] + 0.5) * grid.resolution,
                            grid.origin[1] + (cells[:, 0] + 0.5) * grid.resolution])


def user_stand(ctx: TaskContext, start: Sequence[float]) -> tuple[float, float] | None:
    """Where ``goto_user()`` walks: the point within :data:`USER_STOP` of the user (no wall
    between) geodesically nearest to ``start`` (where a shortest path towards the user
    first comes that close), on the planning grid, else on the grid without its extra
    margin; None if the user cannot be approached."""
    user = np.asarray(ctx.user.position, dtype=float)
    corners = np.repeat(user[None, :], 4, axis=0)
    for margin in (PLANNING_MARGIN, 0.0):
        grid = planning_grid(ctx, margin)
        component = grid.component(start)
        if component == 0:
            continue
        # _near's first point, without the sight test of the points after it.
        cells, _ = grid.reach_cells(corners, USER_STOP, component, rank=lambda g=grid: g.distance_field(start))
        if len(cells):
            x, y = grid.to_world(cells[0])
            return float(x), float(y)
    return None


# -- rays ----------------------------------------------------------------------------------------


def eye_at(ctx: TaskContext, xy: Sequence[float]) -> np.ndarray:
    """Where the agent's head camera is when it stands at ``xy``."""
    return np.array([xy[0], xy[1], ctx.agent.options.camera_height], dtype=float)


def _cast_many(ctx: TaskContext, eye: np.ndarray, points: np.ndarray,
               item: int | None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(distance along each unit ray from ``eye`` towards ``points``, scene object id hit or
    -1, the unit rays); distance -1 where nothing is hit. The same rays as ``Body.look``;
    ``item`` (held) is passed through."""
    vec = np.asarray(points, dtype=float) - eye
    vec /= np.maximum(np.linalg.norm(vec, axis=1, keepdims=True), 1e-12)
    dist, hit = cast_rays(ctx.world, eye, vec, item)
    return dist, hit, vec


def aim_points(ctx: TaskContext, object_id: int) -> np.ndarray:
    """Points (N, 3) spread through the object's bounds (where it is now), worth aiming at."""
    world = ctx.world
    lo, hi = world.assets[object_id].bounds()
    body = world.object_body[object_id]
    mid, half = (lo + hi) / 2, (hi - lo) / 2
    local = np.column_stack([mid[0] + _AIM_FRACTIONS[:, 0] * half[0], mid[1] + _AIM_FRACTIONS[:, 1] * half[1],
                             lo[2] + _AIM_FRACTIONS[:, 2] * (hi[2] - lo[2])])
    return world.data.xpos[body] + local @ world.data.xmat[body].reshape(3, 3).T


def put_spot(ctx: TaskContext, host: int, point: np.ndarray, item: int) -> np.ndarray | None:
    """Where ``put`` aimed at ``point`` on ``host`` sets ``item`` down, or None if it finds
    no room. The body's own room check, plus the pieces standing on the host (a tv on a tv
    stand), which that check does not see: an item set down overlapping one is thrown off."""
    spot = ctx.agent.free_spot(host, point, item)
    if isinstance(spot, str):
        return None
    radius = ctx.world.assets[item].footprint_radius()
    for obj in ctx.scene.objects:
        if obj.on == host and obj.kind != "interactable" and obj.id != item \
                and abs(ctx.world.object_position(obj.id)[2] - spot[2]) < 0.15 \
                and ctx.reach_distance(spot[:2], obj.id) < radius + 0.02:
            return None
    return spot


def _put_item(item: int | None) -> int:
    """The item a put sets down (a put without one is a caller's mistake)."""
    if item is None:
        raise ValueError("a put needs the held item (item is None)")
    return item


def put_spots(ctx: TaskContext, host: int, item: int) -> np.ndarray:
    """Points (N, 3) on ``host``'s surfaces where ``put`` aimed at them would set ``item``
    down (the body's own room check)."""
    world = ctx.world
    body = world.object_body[host]
    spots = []
    for rec in world.assets[host].receptacles:
        link_body = body if rec.link == "base" else world.model.body(f"obj_{host}_{rec.link}").id
        rot = world.data.xmat[link_body].reshape(3, 3)
        origin = world.data.xpos[link_body]
        for fx, fy in _SURFACE_FRACTIONS:
            point = origin + rot @ np.array([rec.center[0] + fx * rec.half_size[0],
                                             rec.center[1] + fy * rec.half_size[1], rec.height])
            if put_spot(ctx, host, point, item) is not None:
                spots.append(point)
    return np.array(spots).reshape(-1, 3)


def _first_hits(ctx: TaskContext, eye: np.ndarray, points: np.ndarray, item: int | None, serves) -> list[int]:
    """Indices of ``points`` whose ray from ``eye`` serves (``serves(distance, object hit,
    hit point) -> bool array``), from the first chunk of rays where any does ([] if none).
    Casting chunk by chunk keeps the common case (the first rays serve) cheap."""
    for lo in range(0, len(points), _CHUNK):
        chunk = points[lo:lo + _CHUNK]
        dist, hit, vec = _cast_many(ctx, eye, chunk, item)
        good = np.nonzero(serves(dist, hit, eye + vec * dist[:, None]))[0]
        if len(good):
            return [lo + int(i) for i in good]
    return []


def _in_view(eye: np.ndarray, points: np.ndarray, within: float, pitch_range: tuple[float, float]) -> np.ndarray:
    """The points within ``within`` metres (horizontally) of ``eye`` that the head can tilt to."""
    flat = np.hypot(points[:, 0] - eye[0], points[:, 1] - eye[1])
    pitch = np.degrees(np.arctan2(eye[2] - points[:, 2], flat))
    return points[(flat <= within) & (pitch >= pitch_range[0]) & (pitch <= pitch_range[1])]


def aims(ctx: TaskContext, eye: np.ndarray, object_id: int, reach: float, *, item: int | None = None,
         put: bool = False, pitch_range: tuple[float, float] = (-60.0, 60.0),
         points: np.ndarray | None = None) -> list[tuple[float, float]]:
    """(yaw, pitch) pairs from ``eye`` whose view ray meets the object within ``reach``
    (horizontally; and ``2 * reach`` along the ray, as the body requires), from the first
    chunk of rays where any does. With ``put``, only rays meeting a spot of its surface where
    the held ``item`` fits. ``item`` (held or about to be) is invisible to the rays."""
    if not put:
        # ``interact()`` grabs what it looks at, but then checks reach to the object's
        # centre (``Body.grab`` addressed by id): both must be within reach.
        centre = ctx.object_centre(object_id)
        if math.hypot(centre[0] - eye[0], centre[1] - eye[1]) > reach or np.linalg.norm(centre - eye) > 2 * reach:
            return []
    held = _put_item(item) if put else None  # not None exactly when ``put``
    if points is None:
        points = put_spots(ctx, object_id, held) if held is not None else aim_points(ctx, object_id)
    points = _in_view(eye, points, reach, pitch_range)
    if len(points) == 0:
        return []

    def serves(dist, hit, at):
        ok = (hit == object_id) & (np.hypot(at[:, 0] - eye[0], at[:, 1] - eye[1]) <= reach) & (dist <= 2 * reach)
        if held is not None:
            for i in np.nonzero(ok)[0]:
                ok[i] = put_spot(ctx, object_id, at[i], held) is not None
        return ok

    return [yaw_pitch_to(eye, points[i]) for i in _first_hits(ctx, eye, points, item, serves)]


def centre_in_sight(ctx: TaskContext, eye: np.ndarray, object_id: int, item: int | None = None) -> bool:
    """A ray from ``eye`` to the object's centre meets the object first (GoTo's visibility,
    once the agent faces it)."""
    centre = ctx.object_centre(object_id)
    _, hit, _ = _cast_many(ctx, eye, centre[None, :], item)
    return bool(hit[0] == object_id)


def seen_point(ctx: TaskContext, eye: np.ndarray, object_id: int, within: float = FIND_DISTANCE,
               pitch_range: tuple[float, float] = (-60.0, 60.0), item: int | None = None) -> np.ndarray | None:
    """A point of the object within ``within`` metres (horizontally) of ``eye`` that a view
    ray reaches, the centre first; None if there is none."""
    points = _in_view(eye, np.vstack([ctx.object_centre(object_id)[None, :], aim_points(ctx, object_id)]),
                      within, pitch_range)
    good = _first_hits(ctx, eye, points, item, lambda dist, hit, at: hit == object_id)
    return points[good[0]] if good else None


# -- stands --------------------------------------------------------------------------------------


def stand_reach(ctx: TaskContext, purpose: str) -> float:
    """How far (horizontally) from a stand the object's footprint may be, for a purpose."""
    if purpose not in PURPOSES:
        raise ValueError(f"unknown stand purpose {purpose!r}; known: {', '.join(PURPOSES)}")
    return (FIND_DISTANCE if purpose == "see" else ctx.agent.reach) - STAND_SLACK


def stand_ok(ctx: TaskContext, xy: Sequence[float], object_id: int, purpose: str, item: int | None = None,
             pitch_range: tuple[float, float] = (-60.0, 60.0), points: np.ndarray | None = None) -> bool:
    """Whether standing at ``xy`` serves ``purpose`` for the object (see the module's doc)."""
    reach = stand_reach(ctx, purpose)
    eye = eye_at(ctx, xy)
    if purpose == "sight":
        if ctx.reach_distance(xy, object_id) > reach:
            return False
        return all(centre_in_sight(ctx, eye + (dx, dy, 0.0), object_id, item)
                   for dx, dy in ((0, 0), (SIGHT_JITTER, 0), (-SIGHT_JITTER, 0), (0, SIGHT_JITTER), (0, -SIGHT_JITTER)))
    if purpose == "see":
        return seen_point(ctx, eye, object_id, reach, pitch_range, item) is not None
    return bool(aims(ctx, eye, object_id, reach, item=item, put=purpose == "put", pitch_range=pitch_range,
                     points=points))


def stands(ctx: TaskContext, object_id: int, purpose: str, start: Sequence[float], item: int | None = None,
           pitch_range: tuple[float, float] = (-60.0, 60.0), grid: NavGrid | None = None,
           stride: int = 1) -> Iterator[tuple[float, float]]:
    """Stands for ``purpose``, geodesically nearest to ``start`` first (lazily checked)."""
    points = put_spots(ctx, object_id, _put_item(item)) if purpose == "put" else None
    if points is not None and len(points) == 0:
        return
    for xy in stand_candidates(ctx, object_id, stand_reach(ctx, purpose), start, grid, stride):
        if stand_ok(ctx, xy, object_id, purpose, item, pitch_range, points):
            yield float(xy[0]), float(xy[1])


# -- paths ---------------------------------------------------------------------------------------


def merge_corners(grid: NavGrid, points: list[np.ndarray], longest: float = 1.0) -> list[np.ndarray]:
    """Fewer corners for the same walk: a path hugging a rounded obstacle (a door frame, a
    table's corner, inflated into a disc) bends at several corners close together; two
    corners ``b``, ``c`` are replaced by the point where the lines through the segments on
    either side meet, when that point is within ``longest`` metres and the straight ways to
    and from it stay on ``grid``'s walkable cells. A move costs an action whatever its
    length, so one corner fewer is one action fewer. The ends never move."""
    pts = [np.asarray(p, dtype=float) for p in points]
    i = 1
    while i + 2 < len(pts):
        a, b, c, d = pts[i - 1], pts[i], pts[i + 1], pts[i + 2]
        u, v = b - a, c - d  # a -> b extended forward, d -> c extended backward
        den = u[0] * v[1] - u[1] * v[0]
        if abs(den) > 1e-9:
            w = d - a
            t = (w[0] * v[1] - w[1] * v[0]) / den
            s = (w[0] * u[1] - w[1] * u[0]) / den
            q = a + t * u
            if t >= 1.0 and s >= 1.0 and math.dist(q, b) <= longest and math.dist(q, c) <= longest \
                    and grid.line_of_sight(a, q, through="walkable") and grid.line_of_sight(q, d, through="walkable"):
                pts[i:i + 2] = [q]
                i = max(i - 1, 1)
                continue
        i += 1
    return pts


def walk_path(ctx: TaskContext, start: Sequence[float], goal: Sequence[float],
              grid: NavGrid | None = None) -> list[np.ndarray]:
    """The polyline the experts walk from ``start`` to ``goal`` on ``grid`` (default: the
    planning grid): the smoothed shortest path, from ``start`` itself (when it is off the
    grid, through the nearest walkable cell only if the straight way to the next corner is
    blocked), ending at ``goal`` itself (the last leg heads straight for a goal off the
    grid, such as the user), with :func:`merge_corners`. [] when there is no path."""
    grid = planning_grid(ctx) if grid is None else grid
    path = [np.asarray(p, dtype=float) for p in grid.path(tuple(start), tuple(goal))]
    if not path:
        return []
    here, there = np.asarray(start[:2], dtype=float), np.asarray(goal[:2], dtype=float)
    points = [here]
    if math.dist(path[0], here) >= MIN_CORNER_GAP and not (len(path) > 1 and ctx.nav.line_of_sight(here, path[1], through="walkable")):
        points.append(path[0])
    for p in [*path[1:], there]:
        if math.dist(p, points[-1]) >= MIN_CORNER_GAP:
            points.append(p)
    return merge_corners(grid, points)


# -- how many actions a goal takes -------------------------------------------------------------


@dataclass(frozen=True)
class Leg:
    """A walk as the experts make it: its actions, where it ends and the heading there."""

    actions: int
    end: tuple[float, float]
    yaw: float


def _turns(degrees: float, carried: bool) -> int:
    """Actions a turn costs: one per 90 degrees, the first 90 free when a move carries it."""
    degrees = abs(degrees)
    if degrees <= ANGLE_TOLERANCE:
        return 0
    return math.ceil(max(degrees - MAX_TURN, 0.0) / MAX_TURN) if carried else math.ceil(degrees / MAX_TURN)


def walk_leg(ctx: TaskContext, start: Sequence[float], yaw: float, goal: Sequence[float],
             stop_short: float = 0.0, grid: NavGrid | None = None, look: float | None = None) -> Leg | None:
    """The experts' walk from ``start`` (heading ``yaw``) along the smoothed shortest path
    of ``grid`` (default: the planning grid) to ``goal``, stopping ``stop_short`` before it,
    then turning to heading ``look``: turn to each corner (the move that reaches a corner
    carries the turn), at most :data:`MAX_MOVE` metres a move. None when there is no path."""
    path = walk_path(ctx, start, goal, grid)
    if not path:
        return None
    lengths = [float(np.linalg.norm(b - a)) for a, b in zip(path, path[1:])]
    left = sum(lengths) - stop_short
    actions, carried, end = 0, False, tuple(path[0])
    for a, b, length in zip(path, path[1:], lengths):
        if left <= 0.05:
            break
        length = min(length, left)
        if length < 0.01:
            continue
        heading = math.degrees(math.atan2(b[1] - a[1], b[0] - a[0]))
        actions += _turns((heading - yaw + 180.0) % 360.0 - 180.0, carried)
        actions += math.ceil(length / MAX_MOVE - 1e-9)
        carried, yaw, left = True, heading, left - length
        end = tuple(a + (b - a) * (length / max(float(np.linalg.norm(b - a)), 1e-12)))
    if look is not None:
        actions += _turns((look - yaw + 180.0) % 360.0 - 180.0, carried)
        yaw = look
    return Leg(actions, (float(end[0]), float(end[1])), yaw)


def stand_leg(ctx: TaskContext, object_id: int, purpose: str, start: Sequence[float] | None = None,
              yaw: float | None = None, item: int | None = None) -> Leg | None:
    """The walk (from the agent's spawn by default) to the nearest stand for ``purpose``,
    ending facing the object; None if there is no such stand. Stands are looked for on
    every other cell (4 times fewer ray checks), as the expert first looks for them: a goal
    with such a stand is one the expert finds a stand for."""
    start = tuple(ctx.agent.position) if start is None else tuple(start)
    yaw = ctx.agent.state.yaw if yaw is None else yaw
    stand = next(stands(ctx, object_id, purpose, start, item, stride=2), None)
    if stand is None:
        return None
    centre = ctx.object_centre(object_id)
    return walk_leg(ctx, start, yaw, stand, look=math.degrees(math.atan2(centre[1] - stand[1], centre[0] - stand[0])))


def user_leg(ctx: TaskContext, start: Sequence[float] | None = None, yaw: float | None = None) -> Leg | None:
    """The walk (from the agent's spawn by default) up to :data:`USER_STOP` metres from the
    user, ending facing them (as ``goto_user()`` walks); None if they cannot be approached."""
    start = tuple(ctx.agent.position) if start is None else tuple(start)
    yaw = ctx.agent.state.yaw if yaw is None else yaw
    user = ctx.user.position
    if math.dist(start, user) <= USER_STOP + 0.05:
        return Leg(0, (start[0], start[1]), yaw)
    stand = user_stand(ctx, start)
    if stand is None:
        return None
    for margin in (PLANNING_MARGIN, 0.0):
        grid = planning_grid(ctx, margin)
        if grid.reachable(start, stand):
            return walk_leg(ctx, start, yaw, stand, grid=grid,
                            look=math.degrees(math.atan2(user[1] - stand[1], user[0] - stand[0])))
    return None

"""The one door through which experts read privileged state.

Experts plan from the simulator's internal state (poses, the walkable floor, where objects
are and what a ray would hit), which a policy never sees. Everything they read goes through
:class:`Oracle`, so the privileged surface is small, documented and easy to audit: nothing
in ``legent_gym.experts`` touches the env, the world or MuJoCo except through this class.

The oracle reads the env's current episode lazily (``env.unwrapped.ctx``), so one oracle
serves a whole sequence of resets. It never changes the world.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import mujoco
import numpy as np

from legent_gym.agent.actions import ActionLimits
from legent_gym.world.builder import GROUP_HOUSE, GROUP_OBJECTS
from legent_gym.world.navigation import NavGrid

#: Extra clearance (metres) the expert keeps from obstacles beyond the body's radius: a
#: straight segment between walkable cells may pass half a cell closer to a corner than
#: the cells do, and the body's sweep stops at the first touch.
PLANNING_MARGIN = 0.06

_VIEW_GROUPS = np.zeros(6, dtype=np.uint8)
_VIEW_GROUPS[GROUP_HOUSE] = _VIEW_GROUPS[GROUP_OBJECTS] = 1


@dataclass(frozen=True)
class Pose:
    """The agent's pose: position (metres), yaw (degrees, 0 along +x, + turns left) and
    pitch (degrees, + looks down)."""

    x: float
    y: float
    yaw: float
    pitch: float


@dataclass(frozen=True)
class RayHit:
    """What a view ray from the head camera hits first."""

    distance: float
    point: np.ndarray
    object_id: int | None
    door_id: str | None


def direction_of(yaw: float, pitch: float) -> np.ndarray:
    """The unit view direction for a yaw and pitch in degrees (the head camera's convention)."""
    y, p = math.radians(yaw), math.radians(pitch)
    return np.array([math.cos(y) * math.cos(p), math.sin(y) * math.cos(p), -math.sin(p)])


def yaw_pitch_to(eye: np.ndarray, point: np.ndarray) -> tuple[float, float]:
    """The yaw and pitch (degrees) that look from ``eye`` straight at ``point``."""
    d = np.asarray(point, dtype=float) - eye
    yaw = math.degrees(math.atan2(d[1], d[0]))
    pitch = math.degrees(math.atan2(-d[2], math.hypot(d[0], d[1])))
    return yaw, pitch


class Oracle:
    """Privileged, read-only access to an env's episode for experts.

    Args:
        env: a ``HouseholdEnv`` or any wrapper of one.
    """

    def __init__(self, env):
        self._env = env.unwrapped

    # -- the episode -----------------------------------------------------------------------
    @property
    def _ctx(self):
        ctx = self._env.ctx
        if ctx is None:
            raise RuntimeError("the env has no episode yet: call reset() first")
        return ctx

    @property
    def episode_key(self) -> tuple:
        """Changes whenever the env starts a new episode (a new house or goal)."""
        return (id(self._ctx), id(self._env.goal))

    @property
    def task_name(self) -> str:
        return self._env.task_name

    @property
    def goal(self):
        """The sampled goal (a ``TaskInstance``: ``target``, ``receptacle``, ... object ids)."""
        return self._env.goal

    @property
    def limits(self) -> ActionLimits:
        return self._env.limits

    @property
    def action_type(self) -> str:
        return self._env.action_type

    @property
    def reach(self) -> float:
        return self._ctx.agent.reach

    @property
    def pitch_range(self) -> tuple[float, float]:
        lo, hi = self._ctx.agent.pitch_range
        return max(lo, self.limits.pitch_range[0]), min(hi, self.limits.pitch_range[1])

    @property
    def fovy(self) -> float:
        return self._ctx.agent.options.fovy

    @property
    def horizontal_fov(self) -> float:
        aspect = self._env.width / self._env.height
        return math.degrees(2 * math.atan(math.tan(math.radians(self.fovy) / 2) * aspect))

    # -- bodies ----------------------------------------------------------------------------
    @property
    def pose(self) -> Pose:
        s = self._ctx.agent.state
        return Pose(s.x, s.y, s.yaw, s.pitch)

    @property
    def eye(self) -> np.ndarray:
        return self._ctx.agent.camera_position

    @property
    def held(self) -> int | None:
        return self._ctx.agent.state.held

    @property
    def user_position(self) -> np.ndarray:
        return self._ctx.user.position

    def horizontal_distance(self, point: Sequence[float]) -> float:
        return self._ctx.agent.horizontal_distance(point)

    # -- objects ---------------------------------------------------------------------------
    def object_ids(self) -> list[int]:
        return [o.id for o in self._ctx.scene.objects]

    def door_ids(self) -> list[str]:
        return list(self._ctx.world.door_joint)

    def name_of(self, object_id: int) -> str:
        return self._ctx.name_of(object_id)

    def object_centre(self, object_id: int) -> np.ndarray:
        return self._ctx.object_centre(object_id)

    def aim_points(self, object_id: int) -> list[np.ndarray]:
        """Points on an object worth aiming at: the centre of its bounds, then its top face
        (centre), then points across its height and width."""
        world = self._ctx.world
        lo, hi = world.assets[object_id].bounds()
        body = world.object_body[object_id]
        rot = world.data.xmat[body].reshape(3, 3)
        origin = world.data.xpos[body]
        mid = (lo + hi) / 2
        half = (hi - lo) / 2
        local = [mid, (mid[0], mid[1], hi[2] - 0.02), (mid[0], mid[1], mid[2] + half[2] * 0.5),
                 (mid[0], mid[1], mid[2] - half[2] * 0.5)]
        for fx, fy in ((0.5, 0), (-0.5, 0), (0, 0.5), (0, -0.5)):
            local.append((mid[0] + fx * half[0], mid[1] + fy * half[1], mid[2]))
            local.append((mid[0] + fx * half[0], mid[1] + fy * half[1], hi[2] - 0.02))
        return [origin + rot @ np.asarray(p, dtype=float) for p in local]

    def surface_spots(self, host: int) -> list[np.ndarray]:
        """Where the held object could be put on ``host``: free points on its receptacle
        surfaces (world coordinates). Empty if it holds nothing."""
        ctx = self._ctx
        held = ctx.agent.state.held
        if held is None:
            return []
        world = ctx.world
        body = world.object_body[host]
        spots = []
        for rec in world.assets[host].receptacles:
            link_body = body if rec.link == "base" else world.model.body(f"obj_{host}_{rec.link}").id
            rot = world.data.xmat[link_body].reshape(3, 3)
            origin = world.data.xpos[link_body]
            for fx in np.linspace(-0.8, 0.8, 5):
                for fy in np.linspace(-0.8, 0.8, 5):
                    local = np.array([rec.center[0] + fx * rec.half_size[0], rec.center[1] + fy * rec.half_size[1],
                                      rec.height])
                    point = origin + rot @ local
                    # The body's own check: the spot it would put the item on, or why not.
                    spot = ctx.agent._free_spot(host, point, held)
                    if not isinstance(spot, str):
                        spots.append(point)
        return spots

    def can_put_at(self, host: int, point: np.ndarray) -> bool:
        """Whether ``put`` aimed at ``point`` (a looked-at point on ``host``) would find room."""
        held = self._ctx.agent.state.held
        return held is not None and not isinstance(self._ctx.agent._free_spot(host, point, held), str)

    def home_of(self, object_id: int) -> int | None:
        """The receptacle the object stood on when the house was made (None: the floor)."""
        return self._ctx.scene.object(object_id).on

    def is_interactable(self, object_id: int) -> bool:
        return self._ctx.scene.object(object_id).kind == "interactable"

    def is_visible(self, object_id: int) -> bool:
        """The object is in the agent's current view, unoccluded (the tasks' own test)."""
        return self._ctx.is_visible(self._ctx.agent, object_id)

    # -- rays ------------------------------------------------------------------------------
    @property
    def camera_height(self) -> float:
        return self._ctx.agent.options.camera_height

    def eye_at(self, xy: Sequence[float]) -> np.ndarray:
        """Where the head camera would be with the agent standing at ``xy``."""
        return np.array([xy[0], xy[1], self.camera_height], dtype=float)

    def cast(self, yaw: float, pitch: float, eye: np.ndarray | None = None) -> RayHit | None:
        """What the head camera's centre ray would hit at this yaw and pitch (held object
        ignored), as ``Body.look`` sees it; from ``eye`` if given (a hypothetical stand)."""
        ctx = self._ctx
        world = ctx.world
        eye = ctx.agent.camera_position if eye is None else np.asarray(eye, dtype=float)
        direction = direction_of(yaw, pitch)
        held = ctx.agent.state.held
        exclude = world.object_body[held] if held is not None else -1
        geomid = np.zeros(1, dtype=np.int32)
        dist = mujoco.mj_ray(world.model, world.data, eye, direction, _VIEW_GROUPS, 1, exclude, geomid)
        if dist < 0:
            return None
        g = int(geomid[0])
        obj = int(world.geom_object[g])
        return RayHit(float(dist), eye + direction * dist, obj if obj >= 0 else None, world.geom_door.get(g))

    # -- navigation ------------------------------------------------------------------------
    def planning_grid(self) -> NavGrid:
        """The expert's walkable grid: the episode's, with obstacles inflated by
        :data:`PLANNING_MARGIN` more and the user standing as an obstacle. Rebuilt when the
        episode changes or the user moves."""
        ctx = self._ctx
        user = ctx.user.position
        key = (self.episode_key, round(float(user[0]), 1), round(float(user[1]), 1))
        if getattr(self, "_grid_key", None) != key:
            nav = ctx.nav
            obstacles = nav.obstacles.copy()
            if ctx.world.scene.user is not None:
                rows, cols = np.ogrid[:nav.shape[0], :nav.shape[1]]
                cx = nav.origin[0] + (cols + 0.5) * nav.resolution
                cy = nav.origin[1] + (rows + 0.5) * nav.resolution
                obstacles |= np.hypot(cx - user[0], cy - user[1]) <= ctx.user.options.radius
            self._grid = NavGrid(nav.origin, nav.resolution, nav.floor, nav.walls, obstacles,
                                 nav.agent_radius + PLANNING_MARGIN, scene=nav.scene, footprints=nav.footprints)
            self._grid_key = key
        return self._grid

    def path_to(self, goal: Sequence[float], *, keep_clear: bool = True) -> list[tuple[float, float]]:
        """Corner points of the smoothed shortest path from the agent to ``goal``
        (``[]`` if none): on :meth:`planning_grid` when ``keep_clear`` and it joins the two,
        else on the episode's own grid (where a narrow passage may only be open without the
        extra margin, and where the user is no obstacle: for walking up to the user)."""
        start = tuple(self._ctx.agent.position)
        if keep_clear:
            grid = self.planning_grid()
            if grid.reachable(start, goal):
                path = grid.path(start, tuple(goal))
                if path:
                    return path
        return self._ctx.nav.path(start, tuple(goal))

    def standing_points(self, object_id: int, reach: float, limit: int = 400,
                        near: Sequence[float] | None = None, within: float = math.inf) -> list[tuple[float, float]]:
        """Walkable points from which the object's footprint is within ``reach`` (no wall
        between), the geodesically nearest to the agent first (at most ``limit``); with
        ``near``, only those within ``within`` metres of that point."""
        ctx = self._ctx
        nav = ctx.nav
        start = tuple(ctx.agent.position)
        component = nav.component(start)
        if component == 0:
            here = nav.nearest_walkable(start)
            if here is None:
                return []
            start, component = here, nav.component(here)
        corners = self._footprint(object_id)
        cells, _ = nav.reach_cells(corners, reach, component)
        if near is not None and len(cells):
            xy = np.asarray(nav.origin) + (cells[:, ::-1] + 0.5) * nav.resolution  # cell centres (x, y)
            cells = cells[np.hypot(xy[:, 0] - near[0], xy[:, 1] - near[1]) <= within]
        if len(cells) == 0:
            return []
        field = nav.distance_field(start)
        dist = field[cells[:, 0], cells[:, 1]]
        order = np.argsort(dist, kind="stable")[:limit]
        order = order[np.isfinite(dist[order])]
        return [nav.to_world(cells[i]) for i in order]

    def _footprint(self, object_id: int) -> np.ndarray:
        """The object's footprint where it is now (it may have been moved)."""
        return self._ctx.footprint(object_id)

    def reach_distance(self, xy: Sequence[float], object_id: int) -> float:
        """Horizontal metres from ``xy`` to the object's footprint (GoTo's "within reach")."""
        return self._ctx.reach_distance(xy, object_id)

    def geodesic(self, point: Sequence[float], goal: Sequence[float]) -> float:
        """Geodesic metres from ``point`` to ``goal`` on the episode's grid (inf: no path)."""
        nav = self._ctx.nav
        here = nav.nearest_walkable(tuple(point))
        if here is None:
            return math.inf
        return float(nav.distance_field(tuple(goal))[nav.to_cell(here)])

    def free_distance(self, heading: float, distance: float) -> float:
        """How far the agent could walk along ``heading`` (degrees) before touching anything."""
        return self._ctx.agent.free_distance(heading, distance)

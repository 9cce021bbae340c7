"""The one door through which experts read privileged state.

Experts plan from the simulator's internal state (poses, the walkable floor, where objects
are and what a ray would hit), which a policy never sees. Everything they read goes through
:class:`Oracle`, so the privileged surface is small, documented and easy to audit: nothing
in ``legent_gym.experts`` touches the env, the world or MuJoCo except through this class.

The oracle reads the env's episode engine (``env.unwrapped.episode``, an
:class:`~legent_gym.envs.episode.Episode`) lazily, so one oracle serves a whole sequence of
resets. It never changes the world.
"""

from __future__ import annotations

import math
from collections.abc import Iterator, Sequence
from dataclasses import dataclass

import numpy as np

from legent_gym.agent.actions import ActionLimits
from legent_gym.tasks import feasibility
from legent_gym.tasks.base import Task, TaskContext, TaskInstance
from legent_gym.tasks.feasibility import yaw_pitch_to
from legent_gym.tasks.registry import task_class
from legent_gym.world.navigation import NavGrid
from legent_gym.world.rays import RayHit, cast_ray

__all__ = ["GoalView", "Oracle", "Pose", "RayHit", "direction_of", "yaw_pitch_to"]


@dataclass(frozen=True)
class Pose:
    """The agent's pose: position (metres), yaw (degrees, 0 along +x, + turns left) and
    pitch (degrees, + looks down)."""

    x: float
    y: float
    yaw: float
    pitch: float


@dataclass(frozen=True)
class GoalView:
    """Where the task's current goal is as seen from the head camera: ``visible`` (in the
    view and unoccluded, the tasks' own test for objects; the user's head or chest for a
    person), ``bearing`` (degrees to turn right to face it, in [-180, 180)) and
    ``distance`` (horizontal metres from the camera). Privileged: for labels (auxiliary
    training targets, analysis), never for a policy's input."""

    visible: bool
    bearing: float
    distance: float

    def to_dict(self) -> dict:
        return {"visible": self.visible, "bearing": round(self.bearing, 2), "distance": round(self.distance, 3)}


def direction_of(yaw: float, pitch: float) -> np.ndarray:
    """The unit view direction for a yaw and pitch in degrees (the head camera's convention)."""
    y, p = math.radians(yaw), math.radians(pitch)
    return np.array([math.cos(y) * math.cos(p), math.sin(y) * math.cos(p), -math.sin(p)])


class Oracle:
    """Privileged, read-only access to an env's episode for experts.

    Args:
        env: an env with an episode engine and an action type (``HouseholdEnv``,
            ``SingleAgentEnv``), or any wrapper of one.
    """

    def __init__(self, env):
        unwrapped = env.unwrapped
        self._episode = unwrapped.episode
        self._action_type: str = unwrapped.action_type

    # -- the episode -----------------------------------------------------------------------
    @property
    def _ctx(self) -> TaskContext:
        ctx = self._episode.ctx
        if ctx is None:
            raise RuntimeError("the env has no episode yet: call reset() first")
        return ctx

    @property
    def episode_key(self) -> tuple:
        """Changes whenever the env starts a new episode (a new house or goal)."""
        return (id(self._ctx), id(self._episode.goal))

    @property
    def task_name(self) -> str:
        """The template task of the current goal (a Custom task's goals are template goals)."""
        task, goal = self._episode.task, self._episode.goal
        return task.name if goal is None else task.goal_task(goal)

    @property
    def task(self) -> type[Task]:
        """The registered class of :attr:`task_name`: its ``code`` is what the experts plan."""
        return task_class(self.task_name)

    @property
    def goal(self) -> TaskInstance:
        """The sampled goal (a ``TaskInstance``: ``target``, ``receptacle``, ... object ids)."""
        return self._episode.goal

    @property
    def limits(self) -> ActionLimits:
        return self._episode.limits

    @property
    def action_type(self) -> str:
        return self._action_type

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

    def horizontal_distance(self, point: Sequence[float] | np.ndarray) -> float:
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

    def aim_points(self, object_id: int) -> np.ndarray:
        """Points (N, 3) spread through an object's bounds, worth aiming at."""
        return feasibility.aim_points(self._ctx, object_id)

    def aims(self, object_id: int, eye: np.ndarray, reach: float, put: bool = False) -> list[tuple[float, float]]:
        """(yaw, pitch) pairs from ``eye`` whose view ray meets the object within ``reach``;
        with ``put``, a spot of its surface where the held object fits."""
        return feasibility.aims(self._ctx, np.asarray(eye, dtype=float), object_id, reach, item=self.held,
                                put=put, pitch_range=self.pitch_range, points=self._put_spots(object_id) if put else None)

    def _put_spots(self, host: int) -> np.ndarray:
        # Free spots change only when something is grabbed or put: keyed by what is held.
        key = (self.episode_key, host, self.held)
        if getattr(self, "_spots_key", None) != key:
            held = self.held
            if held is None:
                raise RuntimeError("free spots are looked for only while holding something")
            self._spots = feasibility.put_spots(self._ctx, host, held)
            self._spots_key = key
        return self._spots

    def seen_point(self, object_id: int, eye: np.ndarray, within: float) -> np.ndarray | None:
        """A point of the object within ``within`` metres of ``eye`` that a view ray reaches."""
        return feasibility.seen_point(self._ctx, np.asarray(eye, dtype=float), object_id, within, self.pitch_range,
                                      self.held)

    def centre_in_sight(self, object_id: int, eye: np.ndarray | None = None) -> bool:
        """A ray from ``eye`` (default: the head camera) to the object's centre meets it first."""
        eye = self.eye if eye is None else np.asarray(eye, dtype=float)
        return feasibility.centre_in_sight(self._ctx, eye, object_id, self.held)

    def can_put_at(self, host: int, point: np.ndarray) -> bool:
        """Whether ``put`` aimed at ``point`` (a looked-at point on ``host``) would find room."""
        held = self._ctx.agent.state.held
        return held is not None and feasibility.put_spot(self._ctx, host, point, held) is not None

    def home_of(self, object_id: int) -> int | None:
        """The receptacle the object stood on when the house was made (None: the floor)."""
        return self._ctx.scene.object(object_id).on

    def is_visible(self, object_id: int) -> bool:
        """The object is in the agent's current view, unoccluded (the tasks' own test)."""
        return self._ctx.is_visible(self._ctx.agent, object_id)

    def goal_view(self) -> GoalView:
        """:class:`GoalView` of what the task is about now: the user (a goal with no
        ``target``, ComeHere; once the target is held, a task whose code goes to the user,
        BringMe), the receptacle (PutOn once the object is held), else the goal's
        ``target`` object."""
        ctx, goal = self._ctx, self.goal
        target = getattr(goal, "target", None)
        held = ctx.agent.state.held
        if target is None or (held == target and "goto_user()" in self.task.code):
            return self._user_view()
        receptacle = getattr(goal, "receptacle", None)
        if held == target and receptacle is not None:
            target = receptacle
        return self._view_of(self.object_centre(target), ctx.is_visible(ctx.agent, target))

    def _view_of(self, point: np.ndarray, visible: bool) -> GoalView:
        eye = self.eye
        yaw, _ = yaw_pitch_to(eye, point)
        bearing = (self.pose.yaw - yaw + 180.0) % 360.0 - 180.0  # + yaw turns left; bearing is rightwards
        return GoalView(bool(visible), bearing, float(math.hypot(point[0] - eye[0], point[1] - eye[1])))

    def _user_view(self) -> GoalView:
        ctx = self._ctx
        head = ctx.user.camera_position
        chest = np.array([head[0], head[1], 0.7 * ctx.user.options.height])
        return self._view_of(head, ctx.sees_point(ctx.agent, head) or ctx.sees_point(ctx.agent, chest))

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
        eye = ctx.agent.camera_position if eye is None else np.asarray(eye, dtype=float)
        return cast_ray(ctx.world, eye, direction_of(yaw, pitch), ctx.agent.state.held)

    # -- navigation ------------------------------------------------------------------------
    def planning_grid(self) -> NavGrid:
        """The expert's walkable grid (see :func:`legent_gym.tasks.feasibility.planning_grid`):
        the episode's, with obstacles inflated by ``PLANNING_MARGIN`` more and the user
        standing as an obstacle."""
        return feasibility.planning_grid(self._ctx)

    def path_to(self, goal: Sequence[float], *, keep_clear: bool = True,
                start: Sequence[float] | np.ndarray | None = None) -> list[np.ndarray]:
        """The polyline to walk from the agent (or ``start``) to ``goal``, starting with the
        start point ([] if there is no path; see :func:`legent_gym.tasks.feasibility.walk_path`):
        on :meth:`planning_grid` when ``keep_clear`` and it joins the two, else on the
        episode's own grid (where a narrow passage may only be open without the margin)."""
        ctx = self._ctx
        start = tuple(ctx.agent.position) if start is None else (float(start[0]), float(start[1]))
        grids = [feasibility.planning_grid(ctx, m) for m in (feasibility.PLANNING_MARGIN, 0.0)] if keep_clear else []
        for grid in grids:
            if grid.reachable(start, goal):
                path = feasibility.walk_path(ctx, start, goal, grid)
                if path:
                    return path
        path = feasibility.walk_path(ctx, start, goal, ctx.nav)
        if path:
            return path
        # Off the grid (another policy pushed the agent against something), the nearest
        # walkable cell may lie across a wall: step back onto the floor in sight instead.
        for grid in [*grids, ctx.nav]:
            entry = _entry_point(grid, start, goal)
            if entry is not None:
                path = feasibility.walk_path(ctx, entry, goal, grid)
                if path:
                    return [np.asarray(start, dtype=float), *path]
        return []

    def stands(self, object_id: int, purpose: str) -> Iterator[tuple[float, float]]:
        """Walkable points serving ``purpose`` for the object ("sight", "aim", "put" or
        "see", see :mod:`legent_gym.tasks.feasibility`), geodesically nearest first: on every
        other cell of the planning grid (as the task samplers look: 4 times fewer ray checks),
        then on every cell, then (a user moved into a passage) on a grid without the extra
        margin."""
        ctx = self._ctx
        start = tuple(ctx.agent.position)
        item = self.held
        for grid, stride in ((None, 2), (None, 1), (feasibility.planning_grid(ctx, margin=0.0), 1)):
            yield from feasibility.stands(ctx, object_id, purpose, start, item, self.pitch_range, grid=grid,
                                          stride=stride)

    def user_stand(self) -> tuple[float, float] | None:
        """Where ``goto_user()`` walks to: the nearest point within talking distance of the
        user (see :func:`legent_gym.tasks.feasibility.user_stand`)."""
        ctx = self._ctx
        return feasibility.user_stand(ctx, tuple(ctx.agent.position))

    def stand_ok(self, xy: Sequence[float], object_id: int, purpose: str) -> bool:
        """Whether standing at ``xy`` serves ``purpose`` for the object."""
        points = self._put_spots(object_id) if purpose == "put" else None
        return feasibility.stand_ok(self._ctx, xy, object_id, purpose, self.held, self.pitch_range, points)

    def reach_distance(self, xy: Sequence[float], object_id: int) -> float:
        """Horizontal metres from ``xy`` to the object's footprint (GoTo's "within reach")."""
        return self._ctx.reach_distance(xy, object_id)

    def geodesic(self, point: Sequence[float], goal: Sequence[float]) -> float:
        """Geodesic metres from ``point`` to ``goal`` on the planning grid, else on the
        episode's own grid (inf: no path on either)."""
        for grid in (self.planning_grid(), self._ctx.nav):
            here = grid.nearest_walkable(tuple(point))
            if here is None or not grid.reachable(here, goal):
                continue
            # Off the grid (pushed against a wall, out of the door), the way back counts too.
            return float(grid.distance_field(tuple(goal))[grid.to_cell(here)]) + math.dist(here, point)
        return math.inf

    def free_distance(self, heading: float, distance: float) -> float:
        """How far the agent could walk along ``heading`` (degrees) before touching anything."""
        return self._ctx.agent.free_distance(heading, distance)


def _entry_point(grid: NavGrid, start: Sequence[float], goal: Sequence[float],
                 radius: float = 1.0) -> tuple[float, float] | None:
    """A walkable cell within ``radius`` of an off-grid ``start``, in sight of it (no wall
    between) and joined to ``goal``: the one nearest to ``start``, or None."""
    target = grid.component(goal)
    if target == 0:
        return None
    r = int(math.ceil(radius / grid.resolution))
    row, col = grid.to_cell(start)
    candidates = []
    for dr in range(-r, r + 1):
        for dc in range(-r, r + 1):
            cell = (row + dr, col + dc)
            if not (0 <= cell[0] < grid.shape[0] and 0 <= cell[1] < grid.shape[1]):
                continue
            if grid.walkable[cell] and grid.labels[cell] == target:
                xy = grid.to_world(cell)
                d = math.dist(xy, start)
                if d <= radius:
                    candidates.append((d, xy))
    for _, xy in sorted(candidates):
        if grid.line_of_sight(start, xy):
            return xy
    return None

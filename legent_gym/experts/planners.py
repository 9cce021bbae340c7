"""Motion planners: one per instruction of the intermediate code, each turning the current
privileged state into the next optimal action (a step of primitives), or ``None`` once the
instruction is done.

They follow LEGENT's planner (see ``docs/experts.md``): walk the corners of the smoothed
shortest path, turning first when the heading error exceeds 1 degree (at most 90 degrees a
turn) and then moving at most 2 m; a move that reaches a corner carries the turn towards the
next corner (or towards what the walk is for) in the same action. Unlike LEGENT's, every
plan is recomputed from the current state, so the expert can take over after any other
policy's actions (DAgger), and a multi-goal program visits every goal.

Standing points are chosen by what the next instruction needs, checked with rays from the
candidate spot before walking there: ``goto(a)`` stands where ``a``'s centre is within reach
and in sight, ``target(a)`` then aims the camera so that its centre ray hits ``a`` within
reach (for a put: hits a free spot of the receptacle's surface), ``find(a)`` walks until
``a`` is within 3 m and in sight.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence

import numpy as np

from legent_gym.agent.actions import MoveForward, RotateDown, RotateRight
from legent_gym.experts.oracle import Oracle, yaw_pitch_to

ANGLE_TOLERANCE = 1.0  # degrees: turn first when the heading error is larger (LEGENT)
ARRIVED = 0.05  # metres left on a path that count as arrived
MIN_CORNER_GAP = 0.01  # corners closer than this are dropped (LEGENT)
FIND_DISTANCE = 3.0  # find(a) stops once a is this close and in sight (LEGENT)
COME_HERE_STOP = 1.0  # goto_user() stops this far from the user (success is < 2 m)
REACH_MARGIN = 0.93  # aim only at points this fraction of the reach away, for rounding slack
STAND_SLACK = 0.06  # metres of reach a standing point keeps in hand (arrival is not exact)
DETOUR_STEP = 0.3  # metres walked sideways when the straight move is blocked


class PlanningError(RuntimeError):
    """No plan exists from here (the goal is unreachable or cannot be seen from anywhere)."""


def wrap(degrees: float) -> float:
    """An angle in (-180, 180]."""
    d = (degrees + 180.0) % 360.0 - 180.0
    return 180.0 if d == -180.0 else d


def _heading(a: Sequence[float], b: Sequence[float]) -> float:
    return math.degrees(math.atan2(b[1] - a[1], b[0] - a[0]))


class Planner:
    """Plans for one env's agent, through an :class:`Oracle`."""

    def __init__(self, oracle: Oracle):
        self.oracle = oracle
        self._stands: dict[tuple, tuple[float, float]] = {}
        self._bad_stands: set[tuple] = set()
        self._detour: tuple | None = None

    # -- primitives, rounded as they will be written -------------------------------------------
    def _turn(self, left_degrees: float) -> RotateRight | None:
        """A turn of ``left_degrees`` (+ is left), clipped to the turn limit; None if tiny."""
        limit = self.oracle.limits.max_rotate_right
        degrees = round(float(np.clip(-left_degrees, -limit, limit)), 1)
        return RotateRight(degrees) if abs(degrees) >= 0.1 else None

    def _tilt(self, down_degrees: float) -> RotateDown | None:
        limit = self.oracle.limits.max_rotate_down
        degrees = round(float(np.clip(down_degrees, -limit, limit)), 1)
        return RotateDown(degrees) if abs(degrees) >= 0.1 else None

    @staticmethod
    def _step(*primitives) -> tuple:
        return tuple(p for p in primitives if p is not None)

    # -- walking -------------------------------------------------------------------------------
    def walk(self, goal: Sequence[float], stop_short: float = 0.0,
             then_face: Sequence[float] | None = None, keep_clear: bool = True) -> tuple | None:
        """The next action along the shortest path to ``goal`` (stopping ``stop_short``
        metres before it), or None once there. ``then_face``: a point to turn towards with
        the last move."""
        o = self.oracle
        pose = o.pose
        path = o.path_to(goal, keep_clear=keep_clear)
        if not path:
            raise PlanningError(f"no walkable path from ({pose.x:.2f}, {pose.y:.2f}) to "
                                f"({goal[0]:.2f}, {goal[1]:.2f})")
        points = [np.array([pose.x, pose.y])]
        for p in path:  # path[0] is the agent's cell centre when it stands off the grid
            if np.linalg.norm(np.asarray(p) - points[-1]) >= MIN_CORNER_GAP:
                points.append(np.asarray(p, dtype=float))
        corners = _trim(points, stop_short)
        if not corners:
            return None
        level = self._tilt(-pose.pitch) if abs(pose.pitch) > 0.5 else None
        detour = self._detour
        self._detour = None
        if detour is not None and detour[0] == o.episode_key and abs(wrap(detour[1] - pose.yaw)) < 0.5:
            return self._step(MoveForward(detour[2]), level)
        target = corners[0]
        error = wrap(_heading((pose.x, pose.y), target) - pose.yaw)
        if abs(error) > ANGLE_TOLERANCE:
            return self._step(self._turn(error), level)
        distance = float(np.hypot(target[0] - pose.x, target[1] - pose.y))
        move = min(distance, o.limits.max_move)
        free = o.free_distance(pose.yaw, move)
        if free < min(move, DETOUR_STEP) - 0.01:
            return self._sidestep(goal)
        step = [MoveForward(round(move, 2))]
        if distance <= o.limits.max_move:  # the corner is reached in this move: turn on
            after = None
            if len(corners) > 1:
                after = _heading(target, corners[1])
            elif then_face is not None and np.hypot(then_face[0] - target[0], then_face[1] - target[1]) > 0.05:
                after = _heading(target, then_face)
            if after is not None:
                step.append(self._turn(wrap(after - pose.yaw)))
        step.append(level)
        return self._step(*step)

    def _sidestep(self, goal: Sequence[float]) -> tuple:
        """The straight move is blocked (the path grazes a corner, or someone stands in the
        way): turn to the free heading that gains most towards the goal, and walk a short
        way along it with the next action."""
        o = self.oracle
        pose = o.pose
        best, best_left = None, o.geodesic((pose.x, pose.y), goal)
        for delta in (15, -15, 30, -30, 45, -45, 60, -60, 90, -90, 120, -120, 150, -150, 180):
            heading = pose.yaw + delta
            if o.free_distance(heading, DETOUR_STEP) < DETOUR_STEP - 1e-3:
                continue
            rad = math.radians(heading)
            landing = (pose.x + math.cos(rad) * DETOUR_STEP, pose.y + math.sin(rad) * DETOUR_STEP)
            left = o.geodesic(landing, goal)
            if left < best_left - 0.05:
                best, best_left = delta, left
        if best is None:
            raise PlanningError(f"stuck at ({pose.x:.2f}, {pose.y:.2f}): every way forward is blocked")
        turn = self._turn(best)
        self._detour = (o.episode_key, pose.yaw - turn.degrees, DETOUR_STEP)
        return (turn,)

    def face(self, point: Sequence[float]) -> tuple | None:
        """Turn (yaw and pitch) to look straight at ``point``; None if already looking."""
        o = self.oracle
        pose = o.pose
        yaw, pitch = yaw_pitch_to(o.eye, np.asarray(point, dtype=float))
        lo, hi = o.pitch_range
        pitch = float(np.clip(pitch, lo, hi))
        error, tilt = wrap(yaw - pose.yaw), pitch - pose.pitch
        if abs(error) <= ANGLE_TOLERANCE and abs(tilt) <= ANGLE_TOLERANCE:
            return None
        step = self._step(self._turn(error) if abs(error) > ANGLE_TOLERANCE else None,
                          self._tilt(tilt) if abs(tilt) > ANGLE_TOLERANCE else None)
        return step or None

    # -- standing points -----------------------------------------------------------------------
    def _reject_stand(self, object_id: int, purpose: str) -> None:
        """The stand chosen for this purpose did not work on arrival: never choose it again."""
        o = self.oracle
        key = (o.episode_key, object_id, purpose, o.held)
        stand = self._stands.pop(key, None)
        if stand is not None:
            self._bad_stands.add((key, stand))

    def _stand(self, object_id: int, purpose: str, footprint_reach: float,
               good: Callable[[tuple[float, float]], bool]) -> tuple[float, float]:
        """The geodesically nearest walkable spot where ``good`` holds (kept for the
        episode while it still holds, so the goal does not flicker as the agent walks)."""
        o = self.oracle
        key = (o.episode_key, object_id, purpose, o.held)
        stand = self._stands.get(key)
        if stand is not None and (key, stand) not in self._bad_stands and good(stand):
            return stand
        for candidate in o.standing_points(object_id, footprint_reach):
            if (key, candidate) not in self._bad_stands and good(candidate):
                self._stands[key] = candidate
                return candidate
        raise PlanningError(f"no standing point from which object {object_id} ({o.name_of(object_id)}) "
                            f"can be {'seen' if purpose == 'see' else 'reached'}")

    def _aim(self, object_id: int, eye: np.ndarray, put: bool, reach: float | None = None,
             from_pose: tuple[float, float] | None = None) -> tuple[float, float] | None:
        """A (yaw, pitch) from ``eye`` whose centre ray hits the object within reach (for a
        put: a free spot on its surface), or None. With ``from_pose`` (the current yaw and
        pitch), angles are rounded as the turn that reaches them will be."""
        o = self.oracle
        reach = o.reach if reach is None else reach
        lo, hi = o.pitch_range
        points = o.surface_spots(object_id) if put else o.aim_points(object_id)
        points.sort(key=lambda p: float(np.hypot(p[0] - eye[0], p[1] - eye[1])))
        for point in points:
            if np.hypot(point[0] - eye[0], point[1] - eye[1]) > reach * REACH_MARGIN:
                continue
            yaw, pitch = yaw_pitch_to(eye, point)
            if not lo <= pitch <= hi:
                continue
            if from_pose is not None:
                yaw = from_pose[0] + round(wrap(yaw - from_pose[0]), 1)
                pitch = from_pose[1] + round(pitch - from_pose[1], 1)
            if self._hits(object_id, eye, yaw, pitch, put, reach):
                return yaw, pitch
        return None

    def _hits(self, object_id: int, eye: np.ndarray, yaw: float, pitch: float, put: bool,
              reach: float) -> bool:
        hit = self.oracle.cast(yaw, pitch, eye)
        if hit is None or hit.object_id != object_id:
            return False
        if np.hypot(hit.point[0] - eye[0], hit.point[1] - eye[1]) > reach or hit.distance > 2 * reach:
            return False
        return not put or self.oracle.can_put_at(object_id, hit.point)

    # -- the instructions ----------------------------------------------------------------------
    def goto_user(self) -> tuple | None:
        o = self.oracle
        user = o.user_position
        if o.horizontal_distance(user) <= COME_HERE_STOP + ARRIVED:
            return None
        return self.walk(user, stop_short=COME_HERE_STOP, then_face=user, keep_clear=False)

    def goto(self, object_id: int) -> tuple | None:
        """Walk to where the object is within reach and in sight, and face it. When holding
        something, "within reach" means: a free spot of its surface can be aimed at."""
        o = self.oracle
        put = o.held is not None and o.held != object_id
        stand = self._reach_stand(object_id, put)
        centre = o.object_centre(object_id)
        step = self.walk(stand, then_face=centre)
        if step is not None:
            return step
        return self.face(centre)

    def _reach_stand(self, object_id: int, put: bool) -> tuple[float, float]:
        o = self.oracle
        reach = o.reach

        def strong(xy):  # within reach and the centre in sight (GoTo's success test)
            eye = o.eye_at(xy)
            centre = o.object_centre(object_id)
            if o.reach_distance(xy, object_id) > reach - STAND_SLACK:
                return False
            yaw, pitch = yaw_pitch_to(eye, centre)
            lo, hi = o.pitch_range
            if not lo <= pitch <= hi:
                return False
            hit = o.cast(yaw, pitch, eye)
            if hit is None or hit.object_id != object_id:
                return False
            return self._aim(object_id, eye, put, reach=(reach - STAND_SLACK) / REACH_MARGIN) is not None

        def weak(xy):
            return self._aim(object_id, o.eye_at(xy), put, reach=(reach - STAND_SLACK) / REACH_MARGIN) is not None

        purpose = "put" if put else "reach"
        try:
            return self._stand(object_id, purpose, reach, strong)
        except PlanningError:
            return self._stand(object_id, purpose + "-weak", reach, weak)

    def target(self, object_id: int) -> tuple[tuple | None, bool]:
        """Aim so that ``interact()`` acts on the object. Returns ``(step, aimed)``: the next
        action (None when already aimed) and whether the pose after it is aimed."""
        o = self.oracle
        put = o.held is not None and o.held != object_id
        pose = o.pose
        eye = o.eye
        if self._hits(object_id, eye, pose.yaw, pose.pitch, put, o.reach):
            return None, True
        aim = self._aim(object_id, eye, put, from_pose=(pose.yaw, pose.pitch))
        for _ in range(3):
            if aim is not None:
                break
            # Not from here: walk to a spot that has an aim first (another one if this is it).
            stand = self._reach_stand(object_id, put)
            step = self.walk(stand, then_face=o.object_centre(object_id))
            if step is not None:
                return step, False
            for purpose in ("put", "put-weak") if put else ("reach", "reach-weak"):
                self._reject_stand(object_id, purpose)
        if aim is None:
            raise PlanningError(f"object {object_id} ({o.name_of(object_id)}) cannot be aimed at "
                                "from its standing points")
        yaw, pitch = aim
        error = wrap(yaw - pose.yaw)
        step = self._step(self._turn(error), self._tilt(pitch - pose.pitch))
        limit = o.limits.max_rotate_right
        return step, abs(error) <= limit and abs(pitch - pose.pitch) <= o.limits.max_rotate_down

    def find(self, object_id: int) -> tuple | None:
        """Walk until the object is within 3 m and in sight, then look at it."""
        o = self.oracle
        seen = self._visible_point(object_id, o.eye)
        if seen is not None:
            if o.is_visible(object_id):
                return None
            return self.face(seen)

        def good(xy):
            return self._visible_point(object_id, o.eye_at(xy)) is not None

        stand = self._stand(object_id, "see", FIND_DISTANCE, good)
        step = self.walk(stand, then_face=o.object_centre(object_id))
        if step is None:
            return self.face(o.object_centre(object_id))
        return step

    def _visible_point(self, object_id: int, eye: np.ndarray) -> np.ndarray | None:
        """A point of the object within 3 m of ``eye`` (horizontally) that a ray reaches."""
        o = self.oracle
        lo, hi = o.pitch_range
        for point in o.aim_points(object_id):
            if np.hypot(point[0] - eye[0], point[1] - eye[1]) > FIND_DISTANCE:
                continue
            yaw, pitch = yaw_pitch_to(eye, point)
            if not lo <= pitch <= hi:
                continue
            hit = o.cast(yaw, pitch, eye)
            if hit is not None and hit.object_id == object_id:
                return point
        return None


def _trim(points: list[np.ndarray], stop_short: float) -> list[np.ndarray]:
    """The corners after the first point of a path cut ``stop_short`` metres before its end;
    empty when what is left is shorter than ``ARRIVED``."""
    lengths = [float(np.linalg.norm(b - a)) for a, b in zip(points, points[1:])]
    keep = sum(lengths) - stop_short
    if keep <= ARRIVED:
        return []
    out, run = [], 0.0
    for a, b, length in zip(points, points[1:], lengths):
        if run + length >= keep - 1e-9:
            out.append(a + (b - a) * ((keep - run) / max(length, 1e-12)))
            return out
        out.append(b)
        run += length
    return out

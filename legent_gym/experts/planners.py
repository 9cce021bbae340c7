"""Motion planners: one per instruction of the intermediate code, each turning the current
privileged state into the next optimal action (a step of primitives), or ``None`` once the
instruction is done.

They follow LEGENT's planner (see ``docs/experts.md``): walk the corners of the smoothed
shortest path, turning first when the heading error exceeds 1 degree (at most 90 degrees a
turn) and then moving at most 2 m; a move that reaches a corner carries the turn towards the
next corner (or, on the last one, the turn and tilt towards what the walk is for) in the
same action. Unlike LEGENT's, every plan is recomputed from the current state, so the expert
can take over after any other policy's actions (DAgger), and a multi-goal program visits
every goal.

Standing points ("stands") are chosen by what the walk is for, with the checks the task
samplers use (:mod:`legent_gym.tasks.feasibility`), so a sampled goal always has one:
``goto(a)`` alone stands where ``a`` is within reach and its centre in sight (GoTo's
success test); ``goto(a)`` before ``target(a)``, and ``target(a)`` itself, stand where a
view ray meets ``a`` within reach (holding something: a free spot of ``a``'s surface);
``find(a)`` walks until ``a`` is within 3 m and in sight. A stand that does not serve on
arrival (arrival is never exact) is dropped and the next nearest one is taken.

``find(a)`` has two strategies. ``"direct"`` (LEGENT's) turns and walks straight to ``a``
even while it is out of view: the planner knows where it is. ``"scan"`` first looks
around where the agent stands, turning right by ``SCAN_TURN`` degrees until ``a`` is in
view, and only walks (as ``"direct"``) when a whole turn did not show it. Its turns are
ones a policy can learn from the image alone; a policy cloned from ``"direct"`` learns to
turn blindly and to answer before it sees the object (docs/results.md).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import NamedTuple

import numpy as np

from legent_gym.agent.actions import Action, MoveForward, RotateDown, RotateRight
from legent_gym.experts.oracle import Oracle, yaw_pitch_to
from legent_gym.tasks.feasibility import ANGLE_TOLERANCE, FIND_DISTANCE
from legent_gym.tasks.feasibility import USER_STOP as COME_HERE_STOP

__all__ = ["Planner", "PlanningError", "wrap"]

ARRIVED = 0.05  # metres left on a path that count as arrived
AIM_EPSILON = 0.01  # metres of reach an aim keeps in hand against rounding
DETOUR_STEP = 0.3  # metres walked sideways when the straight move is blocked
STAND_RETRIES = 3  # stands tried in a row on arrival before giving up
# metres round a stand that failed on arrival where no other stand is tried: its neighbour
# on the grid sees the object past the same obstacle (a plant's leaves) and fails the same
FAILED_STAND_CLEARANCE = 0.25
SCAN_TURN = 60.0  # degrees turned right per look of a scan: the 90-degree views overlap by 30
SCAN_PITCH = 20.0  # degrees down a scan looks: objects stand on furniture below the eye
FIND_STRATEGIES = ("direct", "scan")

#: A point (x, y[, z]): a sequence of floats or an array.
Point = Sequence[float] | np.ndarray
#: A function of a standing point (x, y) giving the (yaw, pitch) to look at from there.
Look = Callable[[Point], "tuple[float, float] | None"]


class PlanningError(RuntimeError):
    """No plan exists from here (the goal is unreachable or cannot be seen from anywhere)."""


def wrap(degrees: float) -> float:
    """An angle in (-180, 180]."""
    d = (degrees + 180.0) % 360.0 - 180.0
    return 180.0 if d == -180.0 else d


def _heading(a: Point, b: Point) -> float:
    return math.degrees(math.atan2(b[1] - a[1], b[0] - a[0]))


class _Scan(NamedTuple):
    """A look around in place for an object: where it started and whether it went full circle."""

    key: tuple  # (episode key, object id)
    here: tuple[float, float]
    start_yaw: float
    complete: bool = False


class Planner:
    """Plans for one env's agent, through an :class:`Oracle`.

    ``find_strategy``: how ``find(a)`` proceeds while ``a`` is out of view, ``"direct"``
    (turn and walk straight to it, LEGENT's) or ``"scan"`` (look around first); see the
    module docstring."""

    def __init__(self, oracle: Oracle, find_strategy: str = "direct"):
        if find_strategy not in FIND_STRATEGIES:
            raise ValueError(f"find_strategy must be one of {FIND_STRATEGIES}, got {find_strategy!r}")
        self.oracle = oracle
        self.find_strategy = find_strategy
        self._stands: dict[tuple, tuple[float, float]] = {}
        self._bad_stands: set[tuple] = set()
        self._detour: tuple | None = None
        self._scan: _Scan | None = None

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
    def _corners(self, start: np.ndarray, goal: Sequence[float], stop_short: float,
                 keep_clear: bool) -> list[np.ndarray]:
        """The corners still to walk from ``start`` (the agent's position, or where a move
        will take it) to ``goal`` stopping ``stop_short`` before it; [] once there."""
        points = self.oracle.path_to(goal, keep_clear=keep_clear, start=start)
        if not points:
            raise PlanningError(f"no walkable path from ({start[0]:.2f}, {start[1]:.2f}) to "
                                f"({goal[0]:.2f}, {goal[1]:.2f})")
        return _trim(points, stop_short)

    def walk(self, goal: Sequence[float], stop_short: float = 0.0, then_look: Look | None = None,
             keep_clear: bool = True) -> tuple | None:
        """The next action along the shortest path to ``goal`` (stopping ``stop_short``
        metres before it), or None once there. Every move carries the turn towards the
        corner after it (as replanned from where the move ends, so the next action finds no
        heading error); the move that arrives carries the turn and tilt ``then_look`` asks
        for from there."""
        o = self.oracle
        pose = o.pose
        here = np.array([pose.x, pose.y])
        corners = self._corners(here, goal, stop_short, keep_clear)
        if not corners:
            return None
        level = self._tilt(-pose.pitch) if abs(pose.pitch) > 0.5 else None
        detour = self._detour
        self._detour = None
        if detour is not None and detour[0] == o.episode_key and abs(wrap(detour[1] - pose.yaw)) < 0.5:
            return self._step(MoveForward(detour[2]), level)
        target = corners[0]
        error = wrap(_heading(here, target) - pose.yaw)
        if abs(error) > ANGLE_TOLERANCE:
            return self._step(self._turn(error), level)
        distance = float(np.hypot(target[0] - pose.x, target[1] - pose.y))
        move = round(min(distance, o.limits.max_move), 2)
        if move < 0.01:
            return None
        free = o.free_distance(pose.yaw, move)
        if free < min(move, DETOUR_STEP) - 0.01:
            return self._sidestep(goal)
        step: list[Action | None] = [MoveForward(move)]
        if free >= move - 1e-3:  # the move will end where planned: turn on from there
            rad = math.radians(pose.yaw)
            end = np.array([pose.x + math.cos(rad) * move, pose.y + math.sin(rad) * move])
            after = self._corners(end, goal, stop_short, keep_clear)
            if after:
                turn = wrap(_heading(end, after[0]) - pose.yaw)
                step += [self._turn(turn) if abs(turn) > ANGLE_TOLERANCE else None, level]
            else:
                look = then_look(end) if then_look is not None else None
                if look is None:
                    step.append(level)
                else:
                    step += [self._turn(wrap(look[0] - pose.yaw)), self._tilt(look[1] - pose.pitch)]
        else:
            step.append(level)
        return self._step(*step)

    def _sidestep(self, goal: Sequence[float]) -> tuple:
        """The straight move is blocked (the path grazes a corner, or someone stands in the
        way): turn to the free heading that gains most towards the goal, and walk a short
        way along it with the next action."""
        o = self.oracle
        pose = o.pose
        now = o.geodesic((pose.x, pose.y), goal)
        # A full step first; squeezed against something (after another policy's moves),
        # shorter ones that still gain.
        for step_length, gain in ((DETOUR_STEP, 0.05), (DETOUR_STEP / 2, 0.02), (DETOUR_STEP / 3, 0.01)):
            best, best_left = None, now - gain
            for delta in (15, -15, 30, -30, 45, -45, 60, -60, 90, -90, 120, -120, 150, -150, 180):
                heading = pose.yaw + delta
                if o.free_distance(heading, step_length) < step_length - 1e-3:
                    continue
                rad = math.radians(heading)
                landing = (pose.x + math.cos(rad) * step_length, pose.y + math.sin(rad) * step_length)
                left = o.geodesic(landing, goal)
                if left < best_left:
                    best, best_left = delta, left
            if best is not None:
                turn = self._turn(best)
                if turn is None:  # |best| >= 15 degrees: never a tiny turn
                    raise RuntimeError(f"a detour turn of {best} degrees came out empty")
                self._detour = (o.episode_key, pose.yaw - turn.degrees, round(step_length, 2))
                return (turn,)
        raise PlanningError(f"stuck at ({pose.x:.2f}, {pose.y:.2f}): every way forward is blocked")

    def face(self, point: Point) -> tuple | None:
        """Turn (yaw and pitch) to look straight at ``point``; None if already looking."""
        o = self.oracle
        pose = o.pose
        yaw, pitch = self._angles_to(o.eye, point)
        error, tilt = wrap(yaw - pose.yaw), pitch - pose.pitch
        if abs(error) <= ANGLE_TOLERANCE and abs(tilt) <= ANGLE_TOLERANCE:
            return None
        step = self._step(self._turn(error) if abs(error) > ANGLE_TOLERANCE else None,
                          self._tilt(tilt) if abs(tilt) > ANGLE_TOLERANCE else None)
        return step or None

    def _angles_to(self, eye: np.ndarray, point: Point) -> tuple[float, float]:
        """(yaw, pitch) looking from ``eye`` at ``point``, the pitch within the head's range."""
        yaw, pitch = yaw_pitch_to(eye, point)
        lo, hi = self.oracle.pitch_range
        return yaw, float(np.clip(pitch, lo, hi))

    # -- standing points -----------------------------------------------------------------------
    def _stand_key(self, object_id: int, purpose: str) -> tuple:
        o = self.oracle
        centre = o.object_centre(object_id)
        return (o.episode_key, object_id, purpose, o.held, round(float(centre[0]), 2), round(float(centre[1]), 2))

    def _reject_stand(self, object_id: int, purpose: str) -> None:
        """The stand chosen for this purpose did not serve on arrival: never choose it again."""
        key = self._stand_key(object_id, purpose)
        stand = self._stands.pop(key, None)
        if stand is not None:
            self._bad_stands.add((key, stand))

    def _stand(self, object_id: int, purposes: Sequence[str]) -> tuple[tuple[float, float], str]:
        """The geodesically nearest stand serving the first purpose that has one, and that
        purpose (kept for the episode while it still serves, so the goal does not flicker as
        the agent walks)."""
        o = self.oracle
        for purpose in purposes:
            key = self._stand_key(object_id, purpose)
            stand = self._stands.get(key)
            if stand is not None and o.stand_ok(stand, object_id, purpose):
                return stand, purpose
            failed = [stand for bad_key, stand in self._bad_stands if bad_key == key]
            for candidate in o.stands(object_id, purpose):
                if all(np.hypot(candidate[0] - f[0], candidate[1] - f[1]) > FAILED_STAND_CLEARANCE
                       for f in failed):
                    self._stands[key] = candidate
                    return candidate, purpose
        what = {"sight": "reached and seen", "aim": "reached", "put": "reached with a free spot",
                "see": "seen"}[purposes[-1]]
        raise PlanningError(f"no standing point from which object {object_id} ({o.name_of(object_id)}) "
                            f"can be {what}")

    # -- aiming --------------------------------------------------------------------------------
    def _hits(self, object_id: int, eye: np.ndarray, yaw: float, pitch: float, put: bool) -> bool:
        """Whether the view ray at (yaw, pitch) from ``eye`` meets the object within reach
        (for a put: a spot of its surface with room for the held object)."""
        o = self.oracle
        hit = o.cast(yaw, pitch, eye)
        if hit is None or hit.object_id != object_id:
            return False
        if np.hypot(hit.point[0] - eye[0], hit.point[1] - eye[1]) > o.reach or hit.distance > 2 * o.reach:
            return False
        if put:
            return o.can_put_at(object_id, hit.point)
        # A grab checks reach to the object's centre too (see feasibility.aims).
        centre = o.object_centre(object_id)
        return bool(np.hypot(centre[0] - eye[0], centre[1] - eye[1]) <= o.reach
                    and np.linalg.norm(centre - eye) <= 2 * o.reach)

    def _aim(self, object_id: int, eye: np.ndarray, yaw0: float, pitch0: float, put: bool) -> tuple[float, float] | None:
        """The (yaw, pitch) nearest to (``yaw0``, ``pitch0``) whose view ray from ``eye``
        meets the object within reach, rounded as the turn that reaches it will be, or None."""
        o = self.oracle
        candidates = o.aims(object_id, eye, o.reach - AIM_EPSILON, put)
        candidates.sort(key=lambda a: abs(wrap(a[0] - yaw0)) + abs(a[1] - pitch0))
        lo, hi = o.pitch_range
        for yaw, pitch in candidates:
            yaw = yaw0 + round(wrap(yaw - yaw0), 1)
            pitch = float(np.clip(pitch0 + round(pitch - pitch0, 1), lo, hi))
            if self._hits(object_id, eye, yaw, pitch, put):
                return yaw, pitch
        return None

    def _look_for(self, object_id: int, purpose: str, yaw0: float, pitch0: float) -> Look:
        """Where to look from the end of a walk to a stand for ``purpose``: the aim for an
        interaction, else the object's centre (or the point of it in sight)."""
        o = self.oracle

        def look(xy):
            eye = o.eye_at(xy)
            if purpose in ("aim", "put"):
                aim = self._aim(object_id, eye, yaw0, pitch0, purpose == "put")
                if aim is not None:
                    return aim
            if purpose == "see":
                seen = o.seen_point(object_id, eye, FIND_DISTANCE)
                if seen is not None:
                    return self._angles_to(eye, seen)
            return self._angles_to(eye, o.object_centre(object_id))

        return look

    # -- the instructions ----------------------------------------------------------------------
    def goto_user(self) -> tuple | None:
        """Walk until within talking distance (1 m) of the user, and face them."""
        o = self.oracle
        user = o.user_position
        if o.horizontal_distance(user) <= COME_HERE_STOP + ARRIVED:
            return None
        # The stand moves with the user only: it is where the shortest way to them first
        # comes within 1 m, which stays put as the agent walks that way.
        key = (o.episode_key, "user", round(float(user[0]), 2), round(float(user[1]), 2))
        stand = self._stands.get(key) or o.user_stand()
        if stand is None:
            raise PlanningError(f"the user at ({user[0]:.2f}, {user[1]:.2f}) cannot be approached")
        self._stands[key] = stand
        return self.walk(stand, then_look=lambda xy: (_heading(xy, user), 0.0))

    def goto(self, object_id: int, then_target: bool = False) -> tuple | None:
        """Walk to where the object is within reach and in sight, and face it. Before a
        ``target`` of the same object (``then_target``), walk to where it can be aimed at
        instead and leave the facing to ``target``. When holding something, "within reach"
        means: a free spot of its surface can be aimed at."""
        o = self.oracle
        put = o.held is not None and o.held != object_id
        purposes = ("put",) if put else ("aim",) if then_target else ("sight", "aim")
        for _ in range(STAND_RETRIES):
            stand, purpose = self._stand(object_id, purposes)
            pose = o.pose
            step = self.walk(stand, then_look=self._look_for(object_id, purpose, pose.yaw, pose.pitch))
            if step is not None:
                return step
            if purpose in ("aim", "put"):
                if then_target or self._aim(object_id, o.eye, pose.yaw, pose.pitch, put) is not None:
                    return None  # target() aims (and walks on if it cannot aim from here)
            elif o.is_visible(object_id):
                return None
            elif o.centre_in_sight(object_id):
                return self.face(o.object_centre(object_id))
            self._reject_stand(object_id, purpose)
        raise PlanningError(f"object {object_id} ({o.name_of(object_id)}) is not in sight from its standing points")

    def target(self, object_id: int) -> tuple[tuple | None, bool]:
        """Aim so that ``interact()`` acts on the object. Returns ``(step, aimed)``: the next
        action (None when already aimed) and whether the pose after it is aimed."""
        o = self.oracle
        put = o.held is not None and o.held != object_id
        purpose = "put" if put else "aim"
        for _ in range(STAND_RETRIES):
            pose = o.pose
            eye = o.eye
            if self._hits(object_id, eye, pose.yaw, pose.pitch, put):
                return None, True
            aim = self._aim(object_id, eye, pose.yaw, pose.pitch, put)
            if aim is not None:
                yaw, pitch = aim
                error = wrap(yaw - pose.yaw)
                turn = self._step(self._turn(error), self._tilt(pitch - pose.pitch))
                limits = o.limits
                return turn, abs(error) <= limits.max_rotate_right and abs(pitch - pose.pitch) <= limits.max_rotate_down
            # Not from here: walk to a stand that has an aim (another one if this is it).
            stand, _ = self._stand(object_id, (purpose,))
            step = self.walk(stand, then_look=self._look_for(object_id, purpose, pose.yaw, pose.pitch))
            if step is not None:
                return step, False
            self._reject_stand(object_id, purpose)
        raise PlanningError(f"object {object_id} ({o.name_of(object_id)}) cannot be aimed at "
                            "from its standing points")

    def _scan_step(self, object_id: int) -> tuple | None:
        """The next look of a scan for the object from where the agent stands, or None when
        a whole turn from here (or, once one went full circle, from anywhere) did not show it.

        The scan's progress is read from the pose (how far right the head has turned since
        the scan began), not counted, so that actions the expert did not choose (another
        policy's, a perturbation) cannot throw it off; a move before it went full circle
        starts it again from the new place."""
        o = self.oracle
        pose = o.pose
        key = (o.episode_key, object_id)
        here = (round(float(pose.x), 2), round(float(pose.y), 2))
        scan = self._scan
        if scan is None or scan.key != key or (scan.here != here and not scan.complete):
            scan = self._scan = _Scan(key, here, float(pose.yaw))
        if scan.complete:
            return None
        turned = (scan.start_yaw - pose.yaw) % 360.0  # yaw grows to the left
        if turned + SCAN_TURN > 360.0 - SCAN_TURN / 2:  # the next look would repeat the first
            self._scan = scan._replace(complete=True)
            return None
        tilt = self._tilt(SCAN_PITCH - pose.pitch) if abs(SCAN_PITCH - pose.pitch) > 0.5 else None
        return self._step(RotateRight(SCAN_TURN), tilt)

    def find(self, object_id: int) -> tuple | None:
        """Walk until the object is within 3 m and in sight, then look at it (with the
        ``"scan"`` strategy: look around in place first, while it is out of view)."""
        o = self.oracle
        if self.find_strategy == "scan" and not o.is_visible(object_id):
            step = self._scan_step(object_id)
            if step is not None:
                return step
        for _ in range(STAND_RETRIES):
            seen = o.seen_point(object_id, o.eye, FIND_DISTANCE)
            if seen is not None:
                if o.is_visible(object_id):
                    return None
                return self.face(seen)
            pose = o.pose
            stand, _ = self._stand(object_id, ("see",))
            step = self.walk(stand, then_look=self._look_for(object_id, "see", pose.yaw, pose.pitch))
            if step is not None:
                return step
            self._reject_stand(object_id, "see")
        raise PlanningError(f"object {object_id} ({o.name_of(object_id)}) is not in sight from its standing points")


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


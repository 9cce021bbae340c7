"""The embodied agent (and the user): a kinematic, person-sized body in a built world.

The body moves kinematically (the paper's actions are teleport-like: move forward N
metres, turn N degrees) but never through things: a move sweeps the body's disc against the
world's collision geometry in its height band (walls, furniture, closed doors, objects on
the floor, the other avatar; see :mod:`legent_gym.agent.clearance`), stops at the first
obstacle and reports the distance actually moved.

Interaction goes through the camera's image centre, as in LEGENT: a ray from the head
camera along the view axis picks what the agent looks at. Every interaction returns an
:class:`Outcome`; a failed one says why (out of reach, nothing there, no room, ...).

Reach: an interaction succeeds only if the point the agent looks at is within
``reach`` metres (default 1.5) of the agent's centre, measured horizontally, and within
``2 * reach`` along the view ray.

The body is drawn as a humanoid (:mod:`legent_gym.world.humanoid`) that its
:class:`~legent_gym.agent.motion.Animator` poses after every change: the walk cycle when it
moved, the head's pitch, the right arm reaching for what an interaction aimed at (also when
the interaction failed: the arm shows the attempt), both hands on what it carries. Each
step's poses are kept in :attr:`Body.motion` for environments that show the frames in
between (``frames_per_step``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import cast

import mujoco
import numpy as np

from legent_gym.agent.clearance import ClearanceMap
from legent_gym.agent.motion import Animator, IKSolution, Keyframe, MotionLog
from legent_gym.world.builder import GROUP_COLLISION, World
from legent_gym.world.humanoid import appearance_for
from legent_gym.world.rays import RayHit, cast_ray
from legent_gym.world.scene import Spawn

DEFAULT_REACH = 1.5
PITCH_RANGE = (-60.0, 60.0)  # degrees; + looks down
SETTLE_SECONDS = 1.0
HAND_FORWARD, HAND_HEIGHT = 0.35, 1.0
#: Where a carried object is held out to the other person when near and facing them.
HANDOVER_FORWARD, HANDOVER_HEIGHT = 0.5, 1.1
#: Handing over: the other person within this many metres and this many degrees of the heading.
HANDOVER_DISTANCE, HANDOVER_ANGLE = 2.0, 45.0
#: A move stops this far short of what it would touch (metres).
SKIN = 0.02


@dataclass
class Outcome:
    """What one primitive did. ``reason`` explains a failure (or a clipped value)."""

    ok: bool
    reason: str | None = None
    moved: float = 0.0
    target: int | str | None = None


@dataclass
class BodyState:
    x: float
    y: float
    yaw: float  # degrees, 0 looks along +x, + turns left
    pitch: float = 0.0  # degrees, + looks down
    held: int | None = None


def _names(world: World, object_id: int) -> str:
    return f"{object_id} ({world.assets[object_id].names[0]})"


def _hit_object(hit: RayHit) -> int:
    """The scene object a resolved hit names (one that names no door always names one)."""
    if hit.object_id is None:
        raise ValueError("the hit names neither a scene object nor a door")
    return hit.object_id


class Body:
    """A kinematic avatar (``name`` is ``"agent"`` or ``"user"``) in a world, standing at
    ``spawn`` (default: the built scene's spawn for it)."""

    def __init__(self, world: World, name: str = "agent", *, reach: float = DEFAULT_REACH,
                 pitch_range: tuple[float, float] = PITCH_RANGE, other: str | None = None,
                 spawn: Spawn | None = None, record_motion: bool = False):
        self.world = world
        self.name = name
        self.options = world.options.agent if name == "agent" else world.options.user
        self.reach = reach
        self.pitch_range = pitch_range
        if spawn is None:  # the built scene's spawn
            spawn = world.scene.agent if name == "agent" else (world.scene.user or world.scene.agent)
        self.state = BodyState(spawn.position[0], spawn.position[1], spawn.yaw)
        self._other = other
        #: The height band the body collides in: from above the floor to chest height.
        self.collision_band = (0.06, min(1.2, self.options.height - 0.05))
        self._batch_depth = 0
        self._unsynced = False
        self._clearance_map: ClearanceMap | None = None
        self.animator = Animator(world.model, name, self.options.height, appearance_for(name, world.scene.seed))
        #: Metres walked so far (the walk cycle's phase), whether the last primitive walked,
        #: and the right arm's pose for the last interaction (None: it did not reach).
        self.walked = 0.0
        self._walking = False
        self._reach: IKSolution | None = None
        #: The carrying pose of both arms, for (the object held, whether it is held out).
        self._carry_pose: tuple[tuple[int, bool], tuple[np.ndarray, np.ndarray]] | None = None
        #: The object this step picked up and where it lay (shown there until the hand gets there).
        self._picked_from: tuple[int, np.ndarray] | None = None
        #: Whether each step's poses are kept in :attr:`motion` (for :meth:`show_motion`).
        self.record_motion = record_motion
        self.motion = MotionLog(self.keyframe())
        self._sync()

    # -- pose ------------------------------------------------------------------------------
    @property
    def position(self) -> np.ndarray:
        return np.array([self.state.x, self.state.y])

    @property
    def xy(self) -> tuple[float, float]:
        """(x, y) as plain floats: what per-step arithmetic wants (no array to build)."""
        return (self.state.x, self.state.y)

    @property
    def camera_position(self) -> np.ndarray:
        return np.array([self.state.x, self.state.y, self.options.camera_height])

    def view_direction(self) -> np.ndarray:
        yaw, pitch = math.radians(self.state.yaw), math.radians(self.state.pitch)
        return np.array([math.cos(yaw) * math.cos(pitch), math.sin(yaw) * math.cos(pitch), -math.sin(pitch)])

    def place(self, x: float, y: float, yaw: float, pitch: float = 0.0) -> None:
        self.state.x, self.state.y, self.state.yaw = float(x), float(y), float(yaw) % 360.0
        self.state.pitch = _clamp(float(pitch), *self.pitch_range)
        self._walking, self._reach = False, None
        self._sync()
        self._log_start()

    # -- the person's pose ------------------------------------------------------------------
    def keyframe(self) -> Keyframe:
        """The pose the person shows now (see :mod:`legent_gym.agent.motion`)."""
        s = self.state
        reach = self._reach.angles if self._reach is not None else None
        return Keyframe(s.x, s.y, s.yaw, s.pitch, self.walked, self._walking, reach, self._carry_arms())

    def _carry_arms(self) -> tuple[np.ndarray, np.ndarray] | None:
        """Both arms' angles holding the carried object (None when carrying nothing)."""
        held = self.state.held
        if held is None:
            return None
        handing = self._handing_over()
        cached = self._carry_pose
        if cached is not None and cached[0] == (held, handing):
            return cached[1]
        centre, half_width = self._carried_centre(held, handing)
        grip = min(max(half_width, 0.04), 0.14) + 0.015
        ik = self.animator.ik
        right = ik.towards("right", centre + (0.0, -grip, 0.0))
        left = ik.towards("left", centre + (0.0, grip, 0.0))
        arms = (right.angles, left.angles)
        self._carry_pose = ((held, handing), arms)
        return arms

    def _carried_centre(self, held: int, handing: bool) -> tuple[np.ndarray, float]:
        """Where the carried object's centre is held, in the person's frame, and its half width."""
        lo, hi = self.world.assets[held].bounds()
        forward, height = (HANDOVER_FORWARD, HANDOVER_HEIGHT) if handing else (HAND_FORWARD, HAND_HEIGHT)
        return np.array([forward, 0.0, height]), float(hi[1] - lo[1]) / 2

    def _handing_over(self) -> bool:
        """Whether the other person is near and in front (the carried object is held out)."""
        other = self._other_position()
        if other is None or self.name != "agent":
            return False
        dx, dy = other[0] - self.state.x, other[1] - self.state.y
        if math.hypot(dx, dy) > HANDOVER_DISTANCE:
            return False
        off = (math.degrees(math.atan2(dy, dx)) - self.state.yaw + 180.0) % 360.0 - 180.0
        return abs(off) <= HANDOVER_ANGLE

    def _aim(self, point) -> None:
        """Reach the right arm for a world ``point`` (the arm shows the attempt if it is
        beyond the arm's reach)."""
        yaw = math.radians(self.state.yaw)
        dx, dy = float(point[0]) - self.state.x, float(point[1]) - self.state.y
        local = (math.cos(yaw) * dx + math.sin(yaw) * dy, -math.sin(yaw) * dx + math.cos(yaw) * dy, float(point[2]))
        self._walking = False
        self._reach = self.animator.ik.towards("right", local)
        self._log()

    def _log_start(self) -> None:
        """Begin this step's pose log (only when poses are recorded)."""
        if self.record_motion:
            self.motion = MotionLog(self.keyframe())

    def _log(self) -> None:
        """Add the pose now to this step's log (only when poses are recorded)."""
        if self.record_motion:
            self.motion.add(self.keyframe())

    def show_motion(self, t: float) -> None:
        """Pose the person (and what it carries) as it was a share ``t`` (0-1) through the
        step's motion; ``show_motion(1.0)`` puts back the pose the step ended in."""
        if t >= 1.0:
            self._write_pose()
            mujoco.mj_camlight(self.world.model, self.world.data)
            return
        frame, shuffle, reach_share = self.motion.at(t)
        world = self.world
        world.set_body_pose(self.name, frame.x, frame.y, frame.yaw, frame.pitch)
        self.animator.show(world.data, frame, shuffle=shuffle, reach_share=reach_share)
        held = self.state.held
        if held is not None:
            picked = self._picked_from
            if frame.carry is None and picked is not None and picked[0] == held:
                self._lay(held, picked[1])  # still reaching for it: where it lay
            else:
                self._carry(frame)
        mujoco.mj_kinematics(world.model, world.data)
        mujoco.mj_camlight(world.model, world.data)

    def _lay(self, item: int, qpos: np.ndarray) -> None:
        model = self.world.model
        joint = model.body_jntadr[self.world.object_body[item]]
        adr = model.jnt_qposadr[joint]
        self.world.data.qpos[adr:adr + 7] = qpos

    def batched(self) -> _Batch:
        """A context manager: several moves and turns with one update of the world at the end.

        Inside, moves and turns change the body's state only; the world (mocap pose,
        kinematics, cameras) is brought up to date once when the block ends, and before any
        interaction. Nothing in between reads the body's own pose from the world (moves sweep
        against collision geometry, which the avatar has none of), so the outcome is the
        same as updating after every primitive.
        """
        return _Batch(self)

    def begin_batch(self) -> None:
        """Hold world updates until the matching :meth:`end_batch` (see :meth:`batched`).
        The outermost one begins a step: the person's pose log starts again, from a stand."""
        if self._batch_depth == 0:
            if self._walking or self._reach is not None:
                self._walking, self._reach = False, None
                self._unsynced = True  # the idle pose is due, even if nothing moves
            self._log_start()
            self._picked_from = None
        self._batch_depth += 1

    def end_batch(self) -> None:
        """Close a :meth:`begin_batch`; the outermost one brings the world up to date."""
        self._batch_depth -= 1
        if self._batch_depth == 0:
            self._flush()

    def _flush(self) -> None:
        """Bring the world up to date with a batched pose change, if one is pending (also
        inside a batch: an interaction must see the pose the moves before it left)."""
        if self._unsynced:
            self._unsynced = False
            self._write_pose()

    def _sync(self) -> None:
        """Write the body's pose to the world, or note that it is due (inside a batch)."""
        if self._batch_depth:
            self._unsynced = True
            return
        self._write_pose()

    def _write_pose(self) -> None:
        s = self.state
        self.world.set_body_pose(self.name, s.x, s.y, s.yaw, s.pitch)
        frame = self.keyframe()
        self.animator.show(self.world.data, frame)
        if s.held is not None:
            self._carry(frame)
        mujoco.mj_kinematics(self.world.model, self.world.data)
        # Cameras are placed by mj_camlight, not mj_kinematics: without it the head camera
        # keeps rendering the spawn pose however the body moves.
        mujoco.mj_camlight(self.world.model, self.world.data)

    # -- locomotion ------------------------------------------------------------------------
    def free_distance(self, direction_deg: float, distance: float) -> float:
        """How far the body can go along a heading before touching anything (<= distance).

        The body is a disc of its radius swept over the floor; it stops ``SKIN`` short of the
        first collision geom reaching into its height band (see
        :mod:`legent_gym.agent.clearance`) or of the other avatar.
        """
        if distance <= 0:
            return 0.0
        yaw = math.radians(direction_deg)
        fx, fy = math.cos(yaw), math.sin(yaw)
        r = self.options.radius
        exclude = self.world.object_body[self.state.held] if self.state.held is not None else -1
        clearance = self._clearance_map or self._clearance()
        x, y = self.state.x, self.state.y
        best = distance
        dist_map, boxes = clearance.snapshot(exclude)
        if not clearance.segment_clear(dist_map, x, y, fx, fy, distance + r + SKIN, r):
            best = min(best, clearance.sweep(boxes, x, y, fx, fy, distance + SKIN, r) - SKIN)
        other = self._other_position()
        if other is not None:
            best = min(best, _circle_hit(x, y, fx, fy, other, r + self._other_radius(), distance))
        return max(0.0, best)

    def _clearance(self) -> ClearanceMap:
        """The world's clearance map for this body's height band (made on first use, shared
        by the bodies in the world)."""
        if self._clearance_map is None:
            z_range = self.collision_band
            key = ("clearance", z_range)
            # world.derived holds what each module put there: under this key, a ClearanceMap
            found = cast("ClearanceMap | None", self.world.derived.get(key))
            if found is None:
                found = ClearanceMap(self.world, z_range)
                self.world.derived[key] = found
            self._clearance_map = found
        return self._clearance_map

    def move_forward(self, distance: float) -> Outcome:
        free = self.free_distance(self.state.yaw, distance)
        yaw = math.radians(self.state.yaw)
        self.state.x += math.cos(yaw) * free
        self.state.y += math.sin(yaw) * free
        self.walked += free
        self._walking, self._reach = free > 1e-6, None
        self._sync()
        self._log()
        if free + 1e-6 < distance:
            return Outcome(True, f"blocked after {free:.2f} m of {distance:.2f} m", moved=free)
        return Outcome(True, moved=free)

    def rotate_right(self, degrees: float) -> Outcome:
        self.state.yaw = (self.state.yaw - degrees) % 360.0
        self._walking, self._reach = False, None
        self._sync()
        self._log()
        return Outcome(True)

    def rotate_down(self, degrees: float) -> Outcome:
        wanted = self.state.pitch + degrees
        self.state.pitch = _clamp(float(wanted), *self.pitch_range)
        self._walking, self._reach = False, None
        self._sync()
        self._log()
        if self.state.pitch != wanted:
            return Outcome(True, f"pitch clamped to {self.state.pitch:.0f} degrees (range {self.pitch_range})")
        return Outcome(True)

    def _other_position(self) -> tuple[float, float] | None:
        if self._other is None:
            return None
        mocap = self.world.avatar_mocap_ids(self._other)[0]
        x, y, z = self.world.data.mocap_pos[mocap].tolist()
        return None if z < -1 else (x, y)

    def _other_radius(self) -> float:
        return (self.world.options.user if self._other == "user" else self.world.options.agent).radius

    # -- looking ---------------------------------------------------------------------------
    def look(self) -> RayHit | None:
        """What is at the image centre (the first visible surface along the view axis; the
        held object is no obstacle)."""
        return cast_ray(self.world, self.camera_position, self.view_direction(), self.state.held)

    def horizontal_distance(self, point) -> float:
        return math.hypot(float(point[0]) - self.state.x, float(point[1]) - self.state.y)

    def _in_reach(self, hit: RayHit) -> str | None:
        d = self.horizontal_distance(hit.point)
        if d > self.reach or hit.distance > 2 * self.reach:
            return f"out of reach ({d:.2f} m away, reach {self.reach:.2f} m)"
        return None

    def _resolve(self, target: int | str | None, aim: bool = True) -> RayHit | str:
        """The hit to act on (what the image centre shows, or an addressed target; it names a
        scene object or a door), or a sentence saying why there is none within reach. With
        ``aim``, the right arm reaches for it (see :meth:`_aim`)."""
        self._flush()  # interactions see the world as it is after the moves before them
        if target is None:
            looked = self.look()
            if looked is None or (looked.object_id is None and looked.door_id is None):
                self._aim(self.camera_position + self.view_direction() * self.reach)
                return "nothing to interact with at the image centre"
            hit = looked
        elif isinstance(target, str):
            if target not in self.world.door_joint:
                self._aim(self.camera_position + self.view_direction() * self.reach)
                return f"no door with id {target!r}"
            centre = self.world.data.xipos[self.world.door_body[target]]
            hit = RayHit(float(np.linalg.norm(centre - self.camera_position)), centre.copy(), door_id=target)
        else:
            if target not in self.world.object_body:
                self._aim(self.camera_position + self.view_direction() * self.reach)
                return f"no object with id {target}"
            centre = self.world.object_centre(target)
            hit = RayHit(float(np.linalg.norm(centre - self.camera_position)), centre, object_id=int(target))
        if aim:
            self._aim(hit.point)
        problem = self._in_reach(hit)
        return problem if problem else hit

    # -- interactions ----------------------------------------------------------------------
    def grab(self, target: int | None = None) -> Outcome:
        outcome = self._grab(target)
        self._sync()  # the arm's reach, or the hands on what it now carries
        return outcome

    def _grab(self, target: int | None, aim: bool = True) -> Outcome:
        if self.state.held is not None:
            return Outcome(False, f"hands are full: holding {_names(self.world, self.state.held)}")
        hit = self._resolve(target, aim)
        if isinstance(hit, str):
            return Outcome(False, hit)
        if hit.object_id is None:
            return Outcome(False, "that is a door: it cannot be picked up")
        if self.world.scene.object(hit.object_id).kind != "interactable":
            return Outcome(False, f"object {_names(self.world, hit.object_id)} cannot be picked up")
        model = self.world.model
        adr = model.jnt_qposadr[model.body_jntadr[self.world.object_body[hit.object_id]]]
        self._picked_from = (hit.object_id, self.world.data.qpos[adr:adr + 7].copy())
        self.state.held = hit.object_id
        self._set_collisions(hit.object_id, enabled=False)
        self._carry()
        mujoco.mj_kinematics(self.world.model, self.world.data)
        return Outcome(True, target=hit.object_id)

    def put(self, target: int | None = None) -> Outcome:
        outcome = self._put(target)
        self._sync()
        return outcome

    def _put(self, target: int | None) -> Outcome:
        held = self.state.held
        if held is None:
            return Outcome(False, "not holding anything")
        hit = self._resolve(target)
        if isinstance(hit, str):
            return Outcome(False, hit)
        if hit.object_id is None:
            return Outcome(False, "there is no surface to put things on at the image centre")
        spot = self.free_spot(hit.object_id, hit.point if target is None else None, held)
        if isinstance(spot, str):
            return Outcome(False, spot)
        self._release(held, spot)
        return Outcome(True, target=hit.object_id)

    def open(self, target: int | str | None = None) -> Outcome:
        outcome = self._articulate(target, opening=True)
        self._sync()
        return outcome

    def close(self, target: int | str | None = None) -> Outcome:
        outcome = self._articulate(target, opening=False)
        self._sync()
        return outcome

    def interact(self, target: int | str | None = None) -> Outcome:
        """LEGENT's generic action: put when holding, else grab, else open or close."""
        if self.state.held is not None:
            return self.put(target if isinstance(target, int) else None)
        hit = self._resolve(target)
        if isinstance(hit, str):
            self._sync()
            return Outcome(False, hit)
        if hit.object_id is not None and self.world.scene.object(hit.object_id).kind == "interactable":
            outcome = self._grab(hit.object_id, aim=False)  # the arm already reaches for it
            self._sync()
            return outcome
        joint = self._joint_for(hit)
        if joint is None:
            self._sync()
            return Outcome(False, f"object {_names(self.world, _hit_object(hit))} cannot be picked up or opened")
        lo, hi = self.world.model.jnt_range[joint]
        value = self.world.data.qpos[self.world.model.jnt_qposadr[joint]]
        is_open = abs(value) > 0.5 * max(abs(lo), abs(hi))
        outcome = self._articulate(hit.door_id if hit.door_id else hit.object_id, opening=not is_open)
        self._sync()
        return outcome

    # -- helpers ---------------------------------------------------------------------------
    def _joint_for(self, hit: RayHit, opening: bool | None = None) -> int | None:
        """The joint an open/close acts on: the door's hinge, or the looked-at furniture part."""
        if hit.door_id is not None:
            return self.world.door_joint.get(hit.door_id)
        joints = self.world.object_joints.get(_hit_object(hit), {})
        if not joints:
            return None
        model = self.world.model
        if hit.geom >= 0:  # the link that was looked at, if it moves
            body = model.geom_bodyid[hit.geom]
            for jid in joints.values():
                if model.jnt_bodyid[jid] == body:
                    return jid
        for jid in joints.values():  # else the first one that can change
            value = self.world.data.qpos[model.jnt_qposadr[jid]]
            lo, hi = model.jnt_range[jid]
            limit = hi if abs(hi) > abs(lo) else lo
            if opening is None or (opening and abs(value) < 0.5 * abs(limit)) or \
                    (not opening and abs(value) >= 0.5 * abs(limit)):
                return jid
        return next(iter(joints.values()))

    def _articulate(self, target: int | str | None, opening: bool) -> Outcome:
        hit = self._resolve(target)
        if isinstance(hit, str):
            return Outcome(False, hit)
        joint = self._joint_for(hit, opening)
        what = f"door {hit.door_id!r}" if hit.door_id else f"object {_names(self.world, _hit_object(hit))}"
        if joint is None:
            return Outcome(False, f"{what} has nothing to open or close")
        model, data = self.world.model, self.world.data
        lo, hi = model.jnt_range[joint]
        limit = hi if abs(hi) > abs(lo) else lo
        adr = model.jnt_qposadr[joint]
        goal = limit if opening else 0.0
        if abs(data.qpos[adr] - goal) < 1e-3:
            return Outcome(False, f"{what} is already {'open' if opening else 'closed'}")
        data.qpos[adr] = goal
        data.qvel[model.jnt_dofadr[joint]] = 0.0
        if hit.door_id is None:
            self._settle(0.3)  # things inside a drawer or on a door move with it
        mujoco.mj_kinematics(model, data)
        return Outcome(True, target=hit.door_id or hit.object_id)

    def _carry(self, frame: Keyframe | None = None) -> None:
        """Put the carried object between the hands, for the pose ``frame`` (default: now)."""
        held = self.state.held
        if held is None:
            raise RuntimeError(f"{self.name} carries nothing: it holds no object")
        model, data = self.world.model, self.world.data
        x, y, yaw_deg = (self.state.x, self.state.y, self.state.yaw) if frame is None else (frame.x, frame.y, frame.yaw)
        yaw = math.radians(yaw_deg)
        lo, hi = self.world.assets[held].bounds()
        centre, _ = self._carried_centre(held, self._handing_over())
        pos = (x + math.cos(yaw) * centre[0], y + math.sin(yaw) * centre[0], centre[2] - (lo[2] + hi[2]) / 2)
        joint = model.body_jntadr[self.world.object_body[held]]
        adr, dof = model.jnt_qposadr[joint], model.jnt_dofadr[joint]
        data.qpos[adr:adr + 3] = pos
        data.qpos[adr + 3:adr + 7] = (math.cos(yaw / 2), 0, 0, math.sin(yaw / 2))
        data.qvel[dof:dof + 6] = 0

    def _set_collisions(self, object_id: int, enabled: bool) -> None:
        model = self.world.model
        body = self.world.object_body[object_id]
        for g in range(model.body_geomadr[body], model.body_geomadr[body] + model.body_geomnum[body]):
            if model.geom_group[g] == GROUP_COLLISION:
                model.geom_contype[g] = model.geom_conaffinity[g] = 1 if enabled else 0

    def free_spot(self, host: int, near: np.ndarray | None, item: int) -> np.ndarray | str:
        """Where on ``host``'s receptacles ``put`` would set ``item`` down (near a
        looked-at point ``near``, else anywhere), or a sentence saying why nowhere."""
        world = self.world
        asset = world.assets[host]
        if not asset.receptacles:
            return f"object {_names(world, host)} has no surface to put things on"
        item_lo, item_hi = world.assets[item].bounds()
        item_r, item_h = world.assets[item].footprint_radius(), float(item_hi[2] - item_lo[2])
        body = world.object_body[host]
        # What stands there already, each as a circle round its footprint: a spot is taken
        # when the two circles come within 2 cm (a big object's edge reaches far from its
        # centre; the item set down on it would be thrown off).
        others = [(world.object_position(o), world.assets[o].footprint_radius())
                  for o in world.free_objects if o not in (item, host)]
        candidates = []
        for rec in asset.receptacles:
            link_body = body if rec.link == "base" else world.model.body(f"obj_{host}_{rec.link}").id
            rot = world.data.xmat[link_body].reshape(3, 3)
            origin = world.data.xpos[link_body]
            if rec.clearance < item_h:
                continue
            hx, hy = rec.half_size[0] - item_r * 0.6, rec.half_size[1] - item_r * 0.6
            if hx < 0 or hy < 0:
                continue
            if near is not None:
                local = rot.T @ (near - origin)
                if abs(local[2] - rec.height) > 0.06:
                    continue
                points = [(np.clip(local[0], rec.center[0] - hx, rec.center[0] + hx),
                           np.clip(local[1], rec.center[1] - hy, rec.center[1] + hy))]
            else:
                points = [(rec.center[0] + fx * hx, rec.center[1] + fy * hy)
                          for fx in (0, -0.6, 0.6) for fy in (0, -0.6, 0.6)]
            for px, py in points:
                candidates.append(origin + rot @ np.array([px, py, rec.height]))
        if not candidates:
            return (f"no surface of object {_names(world, host)} at the image centre" if near is not None
                    else f"object {_names(world, host)} has no surface the item fits on")
        for spot in candidates:
            crowded = any(np.hypot(*(pos[:2] - spot[:2])) < item_r + radius + 0.02 and abs(pos[2] - spot[2]) < 0.15
                          for pos, radius in others)
            if not crowded:
                return spot
        return f"no room on object {_names(world, host)}"

    def _release(self, item: int, spot: np.ndarray) -> None:
        model, data = self.world.model, self.world.data
        lo, _ = self.world.assets[item].bounds()
        joint = model.body_jntadr[self.world.object_body[item]]
        adr, dof = model.jnt_qposadr[joint], model.jnt_dofadr[joint]
        data.qpos[adr:adr + 3] = (spot[0], spot[1], spot[2] - lo[2] + 0.01)  # released just above
        data.qvel[dof:dof + 6] = 0
        self.state.held = None
        self._set_collisions(item, enabled=True)
        self._settle(SETTLE_SECONDS)

    def _settle(self, seconds: float) -> None:
        """Run physics until things come to rest (or ``seconds`` of simulated time pass)."""
        model, data = self.world.model, self.world.data
        steps = int(seconds / model.opt.timestep)
        for i in range(steps):
            mujoco.mj_step(model, data)
            if i > 20 and i % 10 == 0 and np.abs(data.qvel).max() < 1e-3:
                break
        if self.state.held is not None:
            self._carry()
        # Avatars are mocap bodies: physics never moves them, so nothing else to restore.


class _Batch:
    """See :meth:`Body.batched` (a plain class: cheaper than a generator context manager)."""

    __slots__ = ("body",)

    def __init__(self, body: Body):
        self.body = body

    def __enter__(self) -> Body:
        self.body.begin_batch()
        return self.body

    def __exit__(self, *exc) -> None:
        self.body.end_batch()


def _clamp(value: float, low: float, high: float) -> float:
    """``float(np.clip(value, low, high))`` without numpy's overhead (a few times a step)."""
    return float(min(max(value, low), high))


def _circle_hit(x: float, y: float, fx: float, fy: float, centre: tuple[float, float], radius: float,
                limit: float) -> float:
    """Distance along a ray from (x, y) along the unit (fx, fy) to where it enters a circle
    (``limit`` if never)."""
    rx, ry = centre[0] - x, centre[1] - y
    along = rx * fx + ry * fy
    perp2 = rx * rx + ry * ry - along * along
    if along < 0 or perp2 > radius * radius:
        return limit
    return max(0.0, along - math.sqrt(radius * radius - perp2))

"""How a person moves: the walk cycle, the idle pose, the head's pitch and the arm's reach.

A :class:`~legent_gym.agent.body.Body` tells its :class:`Animator` what it did (walked so
far, turned, reached for a point, carries something) and the animator writes the joint
angles of the person's humanoid (:mod:`legent_gym.world.humanoid`) into the world's
``qpos``. Poses are functions of the body's state, never of time, so the same actions give
the same images:

* walking: legs and arms swing in phase with the distance walked (one cycle every
  :data:`STRIDE_CYCLE` body heights);
* standing: the idle pose (arms loose at the sides); a step that only turned shows the
  idle pose at its end, and a small shuffle in the frames between;
* the head pitches with ``rotate_down`` (a share of the camera's pitch);
* reaching (when not carrying): the right arm's shoulder and elbow come from damped-least-squares IK
  (:class:`ArmIK`) to the point the interaction aimed at (the object, the surface spot,
  the handle); a point beyond the arm is reached towards with the arm straight;
* carrying: both hands hold the carried object; near the other person and facing them,
  the arms reach out to hand it over.

:class:`MotionLog` keeps the poses a step passed through, so that an environment with
``frames_per_step > 1`` can show the walk along the swept path and the reach, frame by
frame, before the step's observation.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from functools import lru_cache

import mujoco
import numpy as np

from legent_gym.world.humanoid import (
    ARM_JOINTS,
    IDLE_POSE,
    JOINT_HIGH,
    JOINT_INDEX,
    JOINT_LOW,
    JOINTS,
    ROBOT,
    Appearance,
    PoseWriter,
    proportions,
    skeleton_model,
)

#: A full walk cycle (two steps) per this many body heights walked.
STRIDE_CYCLE = 0.8
#: How much of the camera's pitch the head follows.
HEAD_PITCH_SHARE = 0.6
#: IK: damping, iterations, and the error that counts as reached (metres).
IK_DAMPING = 0.03
IK_ITERATIONS = 40
IK_TOLERANCE = 0.005
#: The shoulder twists the closed-form starting poses try (radians, the twist's range).
TWISTS_ARRAY = np.linspace(-1.39, 1.57, 17)
#: A target counts as reachable within this share of the straight arm's length.
REACH_MARGIN = 0.995


@dataclass(frozen=True)
class IKSolution:
    """An arm pose: the four arm angles (shoulder flex, abduct, twist, elbow; radians),
    where the hand ends (person frame), its distance to the target, and whether the
    target was reached (``reason`` says why not)."""

    angles: np.ndarray
    hand: np.ndarray
    error: float
    ok: bool
    reason: str | None = None


class ArmIK:
    """Damped-least-squares IK of a person's arm (shoulder: three hinges; elbow: one) on the
    person's skeleton model alone. Targets are in the person's frame (x forward, y left, z
    up, origin on the floor between the feet)."""

    def __init__(self, height: float, look: Appearance):
        self.model = skeleton_model(height, look)
        self.data = mujoco.MjData(self.model)
        self.proportions = proportions(height * look.height_scale, look.girth)
        self.writer = PoseWriter(self.model, "person")
        self._joint_ids = {s: np.array([self.model.joint(f"person/{JOINTS[i].name}").id for i in ARM_JOINTS[s]])
                           for s in ARM_JOINTS}
        self._qpos = {s: self.writer.addresses[list(ARM_JOINTS[s])] for s in ARM_JOINTS}
        self._low = {s: JOINT_LOW[list(ARM_JOINTS[s])] for s in ARM_JOINTS}
        self._high = {s: JOINT_HIGH[list(ARM_JOINTS[s])] for s in ARM_JOINTS}
        #: towards() by side and exact target: carrying poses repeat every episode. (Exact: a
        #: rounded key would give a target the pose found for another one, and the same
        #: episode would look different after other episodes in the same process.)
        self._memo: dict[tuple, IKSolution] = {}

    def hand(self, side: str, angles: np.ndarray) -> np.ndarray:
        """Where the hand site is for these arm angles (forward kinematics)."""
        self.data.qpos[self._qpos[side]] = angles
        mujoco.mj_kinematics(self.model, self.data)
        return self.data.site_xpos[self.writer.hand_sites[side]].copy()

    def solve(self, side: str, target, start: np.ndarray | None = None) -> IKSolution:
        """The arm pose that brings the ``side`` hand to ``target``, within the joints'
        limits. A target farther from the shoulder than the straight arm (or too close to
        it to bend to) is refused with the reason; so is one no pose reaches within 2 cm."""
        target = np.asarray(target, dtype=float)
        shoulder = self.proportions.shoulder(side)
        span = float(np.linalg.norm(target - shoulder))
        length = self.proportions.arm_length
        if span > length * REACH_MARGIN:
            return self._refused(side, target, self._beyond(span))
        if span < 0.2 * length:
            return self._refused(side, target, f"too close to the shoulder to reach ({span:.2f} m)")
        best: IKSolution | None = None
        for guess in self._starts(side, target, start):
            found = self._descend(side, target, guess)
            if best is None or found.error < best.error:
                best = found
            if found.error <= IK_TOLERANCE:
                break
        assert best is not None
        if best.error > 0.02:
            return replace(best, ok=False, reason=f"no arm pose reaches the point ({best.error * 100:.1f} cm short)")
        return best

    def towards(self, side: str, target, start: np.ndarray | None = None) -> IKSolution:
        """:meth:`solve`, but a target beyond the arm is replaced by the point the arm,
        straight, reaches on the way to it (what a person shows when trying): the pose is
        returned with ``ok`` False and the reason."""
        target = np.asarray(target, dtype=float)
        key = (side, *target.tolist()) if start is None else None
        found = self._memo.get(key) if key is not None else None
        if found is None:
            found = self._towards(side, target, start)
            if key is not None:
                if len(self._memo) >= 4096:
                    self._memo.clear()
                self._memo[key] = found
        return found

    def _towards(self, side: str, target: np.ndarray, start: np.ndarray | None) -> IKSolution:
        shoulder = self.proportions.shoulder(side)
        offset = target - shoulder
        span = float(np.linalg.norm(offset))
        arm = self.proportions.arm_length
        if span > arm * 0.97:
            reached = self.solve(side, shoulder + offset * (arm * 0.97 / span), start)
            reason = (self._beyond(span) if span > arm * REACH_MARGIN else reached.reason)
            return replace(reached, ok=span <= arm * REACH_MARGIN and reached.ok, reason=reason)
        if span < 0.2 * arm:
            return self.solve(side, shoulder + offset / max(span, 1e-6) * 0.3 * arm, start)
        return self.solve(side, target, start)

    def _beyond(self, span: float) -> str:
        return f"out of the arm's reach: {span:.2f} m from the shoulder, arm {self.proportions.arm_length:.2f} m"

    def _refused(self, side: str, target: np.ndarray, reason: str) -> IKSolution:
        angles = np.zeros(4)
        hand = self.hand(side, angles)
        return IKSolution(angles, hand, float(np.linalg.norm(target - hand)), False, reason)

    def _starts(self, side: str, target: np.ndarray, start: np.ndarray | None):
        """Starting poses for the descent: ``start`` if given, then closed-form poses (the
        elbow from the law of cosines; flex and abduction that point the bent arm at the
        target, for a few twists), the ones inside the joints' limits first."""
        if start is not None:
            yield np.clip(start, self._low[side], self._high[side])
        p = self.proportions
        a, b = p.upper_arm, p.lower_arm + p.hand
        d = target - p.shoulder(side)
        cos_e = (d @ d - a * a - b * b) / (2 * a * b)
        elbow = math.acos(min(max(cos_e, -1.0), 1.0))
        s = 1.0 if side == "left" else -1.0
        # The bent arm (twist 0, shoulder at rest) turned by each twist, all at once.
        bx, bz = b * math.sin(elbow), -a - b * math.cos(elbow)
        twists = TWISTS_ARRAY
        wx, wy = np.cos(s * twists) * bx, np.sin(s * twists) * bx
        rest = wx * wx + wy * wy + bz * bz - wx * wx - d[1] ** 2
        ok = rest >= 0
        root = np.sqrt(np.where(ok, rest, 0.0))
        pz = np.concatenate([-root, root])
        wx2, wy2, tw2, ok2 = np.tile(wx, 2), np.tile(wy, 2), np.tile(twists, 2), np.tile(ok, 2)
        abduct = _wrap_array(s * (np.arctan2(pz, d[1]) - np.arctan2(bz, wy2)))
        flex = _wrap_array(np.arctan2(wx2, pz) - math.atan2(d[0], d[2]))
        poses = np.stack([flex, abduct, tw2, np.full_like(flex, elbow)], axis=1)[ok2]
        low, high = self._low[side], self._high[side]
        outside = (np.maximum(low - poses, 0) + np.maximum(poses - high, 0)).sum(axis=1)
        order = np.lexsort((np.abs(poses[:, 2]), np.round(outside, 3)))
        yield from np.clip(poses[order], low, high)
        for guess in ((0.6, 0.2, 0.0, 1.2), (2.0, 0.2, 0.0, 0.4)):
            yield np.array(guess)

    def _descend(self, side: str, target: np.ndarray, q: np.ndarray) -> IKSolution:
        model, data = self.model, self.data
        adr, joints, site = self._qpos[side], self._joint_ids[side], self.writer.hand_sites[side]
        low, high = self._low[side], self._high[side]
        jac = np.empty((3, 4))
        damping = IK_DAMPING ** 2 * np.eye(3)
        hand = np.zeros(3)
        error = np.inf
        for _ in range(IK_ITERATIONS):
            data.qpos[adr] = q
            mujoco.mj_kinematics(model, data)
            hand = data.site_xpos[site].copy()
            e = target - hand
            error = float(np.linalg.norm(e))
            if error <= IK_TOLERANCE * 0.2:
                break
            # Columns: each hinge's axis crossed with the lever from its anchor to the hand.
            jac[:] = np.cross(data.xaxis[joints], hand - data.xanchor[joints]).T
            step = jac.T @ np.linalg.solve(jac @ jac.T + damping, e)
            q = np.clip(q + step, low, high)
        return IKSolution(q.copy(), hand, error, error <= 0.02)


def _wrap_array(angle: np.ndarray) -> np.ndarray:
    return (angle + np.pi) % (2 * np.pi) - np.pi


def arm_ik(height: float, look: Appearance) -> ArmIK:
    """The IK of a person of this height and build (made once per build, shared by every
    body: colours do not change an arm)."""
    return _arm_ik(height, look.height_scale, look.girth)


@lru_cache(maxsize=32)
def _arm_ik(height: float, height_scale: float, girth: float) -> ArmIK:
    return ArmIK(height, replace(ROBOT, height_scale=height_scale, girth=girth))


# -- poses ---------------------------------------------------------------------------------

_J = JOINT_INDEX


@dataclass(frozen=True)
class Keyframe:
    """A body's pose at one moment: where it stands, how far it has walked, and what its
    arms do (``reach``: the right arm's angles; ``carry``: both arms' angles)."""

    x: float
    y: float
    yaw: float
    pitch: float
    walked: float
    walking: bool = False
    reach: np.ndarray | None = field(default=None, compare=False)
    carry: tuple[np.ndarray, np.ndarray] | None = field(default=None, compare=False)


def joint_angles(frame: Keyframe, height: float, *, shuffle: float = 0.0, reach_share: float = 1.0) -> np.ndarray:
    """The joint angles (radians, :data:`~legent_gym.world.humanoid.JOINTS` order) of a
    person of ``height`` in ``frame``. ``shuffle`` (0-1) adds the small steps of turning in
    place; ``reach_share`` (0-1) how far along the reach the arm is."""
    q = IDLE_POSE.copy()
    q[_J["neck"]] = math.radians(min(max(frame.pitch * HEAD_PITCH_SHARE, -40.0), 50.0))
    if frame.walking or shuffle:
        if frame.walking:
            phase = 2.0 * math.pi * frame.walked / (STRIDE_CYCLE * height)
            amplitude = 1.0
        else:
            phase, amplitude = 2.0 * math.pi * shuffle, 0.35
        s = math.sin(phase)
        for side, sign in (("right", 1.0), ("left", -1.0)):
            hip = math.radians(26.0) * amplitude * sign * s
            knee = math.radians(8.0 + 42.0 * max(0.0, -sign * math.cos(phase))) * amplitude
            q[_J[f"{side}_hip"]] = hip
            q[_J[f"{side}_knee"]] = knee
            q[_J[f"{side}_shoulder_flex"]] = -math.radians(22.0) * amplitude * sign * s
            q[_J[f"{side}_elbow"]] = math.radians(18.0)
    if frame.carry is not None:
        q[list(ARM_JOINTS["right"])] = frame.carry[0]
        q[list(ARM_JOINTS["left"])] = frame.carry[1]
    if frame.reach is not None and reach_share > 0 and frame.carry is None:  # carrying wins: the hands hold it
        arm = list(ARM_JOINTS["right"])
        q[arm] = q[arm] * (1.0 - reach_share) + frame.reach * reach_share
    # Within the joints' limits by construction: the swings are smaller than the ranges, the
    # IK keeps its poses inside them, and a blend of two poses inside stays inside.
    return q


class Animator:
    """Poses one person of a built world (see the module docstring)."""

    def __init__(self, model: mujoco.MjModel, who: str, height: float, look: Appearance):
        self.writer = PoseWriter(model, who)
        self.height = height * look.height_scale
        self._build = (height, look)
        self._ik: ArmIK | None = None

    @property
    def ik(self) -> ArmIK:
        """The person's arm IK (made on first use: a person who never reaches needs none)."""
        if self._ik is None:
            self._ik = arm_ik(*self._build)
        return self._ik

    def show(self, data: mujoco.MjData, frame: Keyframe, **kw) -> None:
        """Write the pose of ``frame`` (see :func:`joint_angles`) into ``data.qpos``."""
        self.writer.write(data, joint_angles(frame, self.height, **kw))


class MotionLog:
    """The keyframes one step passed through: the pose it began in, then one per primitive
    (bounded: a body driven outside environment steps keeps its last few)."""

    LIMIT = 64

    def __init__(self, start: Keyframe):
        self.frames = [start]

    def add(self, frame: Keyframe) -> None:
        if len(self.frames) >= self.LIMIT:
            del self.frames[1]
        self.frames.append(frame)

    def at(self, t: float) -> tuple[Keyframe, float, float]:
        """The pose a share ``t`` (0-1) of the way through the step, each primitive taking
        an equal share: (keyframe, turning shuffle 0-1, reach share 0-1)."""
        frames = self.frames
        if len(frames) < 2 or t >= 1.0:
            return frames[-1], 0.0, 1.0
        spans = len(frames) - 1
        k = min(int(t * spans), spans - 1)
        u = t * spans - k
        a, b = frames[k], frames[k + 1]
        turn = (b.yaw - a.yaw + 180.0) % 360.0 - 180.0
        frame = replace(b, x=a.x + (b.x - a.x) * u, y=a.y + (b.y - a.y) * u, yaw=(a.yaw + turn * u) % 360.0,
                        pitch=a.pitch + (b.pitch - a.pitch) * u, walked=a.walked + (b.walked - a.walked) * u,
                        carry=b.carry if b.reach is None else a.carry)
        shuffle = u if (abs(turn) > 1e-6 and not b.walking) else 0.0
        return frame, shuffle, min(1.0, 2.0 * u) if b.reach is not None else 1.0

"""People: the articulated, kinematic humanoid that the agent and the user are drawn as.

A person is a tree of MuJoCo bodies under the avatar's mocap root (``agent`` or ``user``,
placed at the floor and turned to the heading by the environment)::

    <who>/pelvis
        <who>/torso
            <who>/head                      hinge  <who>/neck (pitch)
            <who>/<side>_upper_arm          hinges <who>/<side>_shoulder_flex, _abduct, _twist
                <who>/<side>_lower_arm      hinge  <who>/<side>_elbow
                    <who>/<side>_hand       site   <who>/<side>_hand
        <who>/<side>_upper_leg              hinge  <who>/<side>_hip
            <who>/<side>_lower_leg          hinge  <who>/<side>_knee
                <who>/<side>_foot

(``<side>`` is ``right`` or ``left``.) The parts of each body (low-poly tapered cylinders,
ellipsoids and boxes) are merged into one palette-coloured mesh (:func:`person_links`,
drawn by the builder); the feet are drawn with the lower legs, and the user's hands with
its forearms, so that a renderer draws the user in 10 small draw calls and the agent in 12
(its hands apart, see below). The avatar is visual only: its geoms collide with nothing and view rays pass
through them; the body that collides is still the swept disc of
:mod:`legent_gym.agent.body`. Joints are limited hinges; their bodies have gravity
compensation, so physics (an object settling after ``put``) never moves a limb: only the
environment poses them (:mod:`legent_gym.agent.motion`).

Proportions follow the body's height. The user is one of :data:`USER_LOOKS` people
(girth, a small height change, skin, hair and clothing colours, a silhouette), chosen by the
scene's seed (:func:`appearance_for`), so the same scene always shows the same person. The
agent has a robot-like look (grey shell, blue top, dark visor) and is never mistaken for
the user.

Geom groups: every part of the user, and every part of the agent but its hands, is in
the person's own group (``GROUP_AGENT`` or ``GROUP_USER``), which that person's head
camera hides; the agent's hands are in the group every camera shows (``GROUP_HANDS``), so
the agent sees its own hands and what it holds.
"""

from __future__ import annotations

import math
import zlib
from collections.abc import Callable
from dataclasses import dataclass
from functools import lru_cache
from typing import Any

import mujoco
import numpy as np

from legent_gym.world.assets.model import Link, Part, box_part, cylinder_part, sphere_part

SIDES = ("right", "left")
#: The limbs' parts, per side: (part, parent part).
PARTS = ("pelvis", "torso", "head",
         *(f"{s}_{p}" for s in SIDES for p in ("upper_arm", "lower_arm", "hand", "upper_leg", "lower_leg", "foot")))


@dataclass(frozen=True)
class Joint:
    """One hinge of the skeleton: its body, its axis in that body's frame and its range in
    degrees (positive angles: the arm and the thigh swing forward, the elbow and the knee
    bend, the head looks down, the arm lifts away from the body)."""

    name: str
    part: str
    axis: tuple[float, float, float]
    range_deg: tuple[float, float]


def _side_joints(side: str) -> tuple[Joint, ...]:
    out = 1.0 if side == "left" else -1.0  # +x lifts the left arm outwards, -x the right
    return (
        Joint(f"{side}_shoulder_flex", f"{side}_upper_arm", (0.0, -1.0, 0.0), (-60.0, 170.0)),
        Joint(f"{side}_shoulder_abduct", f"{side}_upper_arm", (out, 0.0, 0.0), (-15.0, 160.0)),
        Joint(f"{side}_shoulder_twist", f"{side}_upper_arm", (0.0, 0.0, out), (-80.0, 90.0)),
        Joint(f"{side}_elbow", f"{side}_lower_arm", (0.0, -1.0, 0.0), (0.0, 150.0)),
        Joint(f"{side}_hip", f"{side}_upper_leg", (0.0, -1.0, 0.0), (-40.0, 100.0)),
        Joint(f"{side}_knee", f"{side}_lower_leg", (0.0, 1.0, 0.0), (0.0, 140.0)),
    )


#: Every joint of a person, in the order of :class:`Pose` vectors.
JOINTS: tuple[Joint, ...] = (Joint("neck", "head", (0.0, 1.0, 0.0), (-40.0, 50.0)),
                             *_side_joints("right"), *_side_joints("left"))
JOINT_INDEX = {j.name: i for i, j in enumerate(JOINTS)}
JOINT_LOW = np.radians([j.range_deg[0] for j in JOINTS])
JOINT_HIGH = np.radians([j.range_deg[1] for j in JOINTS])
#: The idle pose: arms loose at the sides, elbows a little bent (radians, JOINTS order).
IDLE_POSE = np.zeros(len(JOINTS))
for _name, _deg in (("right_elbow", 12.0), ("left_elbow", 12.0), ("right_shoulder_abduct", 5.0),
                    ("left_shoulder_abduct", 5.0)):
    IDLE_POSE[JOINT_INDEX[_name]] = math.radians(_deg)
IDLE_POSE.flags.writeable = False
#: The arm joints the reach IK moves, per side (shoulder flex, abduct, twist, elbow).
ARM_JOINTS = {s: tuple(JOINT_INDEX[f"{s}_{n}"] for n in ("shoulder_flex", "shoulder_abduct", "shoulder_twist", "elbow"))
              for s in SIDES}


@dataclass(frozen=True)
class Appearance:
    """How one person looks: colours (RGBA), a girth factor, a height factor and a
    silhouette (``"trousers"``, ``"skirt"``, ``"long_hair"``, ``"robot"``)."""

    skin: tuple[float, float, float, float]
    hair: tuple[float, float, float, float]
    top: tuple[float, float, float, float]
    bottom: tuple[float, float, float, float]
    shoes: tuple[float, float, float, float]
    girth: float = 1.0
    height_scale: float = 1.0
    silhouette: str = "trousers"


SKIN = ((0.96, 0.80, 0.69), (0.88, 0.68, 0.53), (0.76, 0.57, 0.42), (0.55, 0.38, 0.26), (0.36, 0.24, 0.16))
HAIR = ((0.1, 0.07, 0.05), (0.35, 0.22, 0.1), (0.72, 0.55, 0.3), (0.55, 0.55, 0.55), (0.45, 0.15, 0.08))
CLOTHES = ((0.75, 0.2, 0.2), (0.2, 0.45, 0.75), (0.25, 0.6, 0.35), (0.9, 0.75, 0.3), (0.55, 0.35, 0.65),
           (0.92, 0.92, 0.9), (0.25, 0.25, 0.3), (0.85, 0.45, 0.2))
TROUSERS = ((0.15, 0.2, 0.35), (0.3, 0.3, 0.32), (0.45, 0.35, 0.25), (0.12, 0.12, 0.12), (0.6, 0.55, 0.45))
#: The agent's look: a grey shell with blue accents and a dark visor.
ROBOT = Appearance(skin=(0.78, 0.8, 0.84, 1.0), hair=(0.08, 0.1, 0.14, 1.0), top=(0.25, 0.35, 0.6, 1.0),
                   bottom=(0.55, 0.58, 0.62, 1.0), shoes=(0.2, 0.22, 0.26, 1.0), silhouette="robot")


def _opaque(rgb) -> tuple[float, float, float, float]:
    return (float(rgb[0]), float(rgb[1]), float(rgb[2]), 1.0)


#: How many different users the scenes' seeds choose among.
USER_LOOKS = 32


def appearance_for(who: str, seed: int | None) -> Appearance:
    """The look of ``who`` (``"agent"`` or ``"user"``) in a scene with ``seed``: the agent
    is always the robot; the user is one of :data:`USER_LOOKS` people (colours, build and
    silhouette), chosen by the seed. Deterministic. A fixed set of people (as LEGENT has a
    fixed set of characters) lets a process build each person's meshes once."""
    if who == "agent":
        return ROBOT
    index = zlib.crc32(str(0 if seed is None else int(seed)).encode()) % USER_LOOKS
    return _user_look(index)


@lru_cache(maxsize=USER_LOOKS)
def _user_look(index: int) -> Appearance:
    rng = np.random.default_rng([index, 1])
    return Appearance(
        skin=_opaque(SKIN[int(rng.integers(len(SKIN)))]),
        hair=_opaque(HAIR[int(rng.integers(len(HAIR)))]),
        top=_opaque(CLOTHES[int(rng.integers(len(CLOTHES)))]),
        bottom=_opaque(TROUSERS[int(rng.integers(len(TROUSERS)))]),
        shoes=_opaque((0.15, 0.12, 0.1) if rng.random() < 0.6 else (0.85, 0.85, 0.85)),
        girth=round(float(rng.uniform(0.9, 1.15)), 2),
        height_scale=round(float(rng.uniform(0.96, 1.04)), 2),
        silhouette=("trousers", "skirt", "long_hair")[int(rng.integers(3))],
    )


@dataclass(frozen=True)
class Proportions:
    """Where a person's joints are, in metres, for a visual height (see :func:`proportions`)."""

    height: float
    girth: float
    hip_z: float          # hip joints above the floor
    hip_y: float          # hip joints either side of the middle
    waist_z: float        # torso above the pelvis
    shoulder_z: float     # shoulders above the waist
    shoulder_y: float
    neck_z: float         # neck above the waist
    upper_arm: float
    lower_arm: float
    hand: float           # wrist to the hand site
    upper_leg: float
    lower_leg: float      # knee to ankle
    head_radius: float

    @property
    def arm_length(self) -> float:
        """Shoulder to hand site, arm straight."""
        return self.upper_arm + self.lower_arm + self.hand

    def shoulder(self, side: str) -> np.ndarray:
        """The shoulder joint in the person's frame (x forward, y left, z up, origin on the
        floor between the feet)."""
        sign = 1.0 if side == "left" else -1.0
        return np.array([0.0, sign * self.shoulder_y, self.hip_z + self.waist_z + self.shoulder_z])


def proportions(height: float, girth: float = 1.0) -> Proportions:
    """A person's joint layout for a body ``height`` metres tall (adult proportions)."""
    h = height
    return Proportions(height=h, girth=girth, hip_z=0.52 * h, hip_y=0.055 * h * girth, waist_z=0.06 * h,
                       shoulder_z=0.24 * h, shoulder_y=0.115 * h * girth, neck_z=0.31 * h,
                       upper_arm=0.17 * h, lower_arm=0.145 * h, hand=0.04 * h, upper_leg=0.245 * h,
                       lower_leg=0.235 * h, head_radius=0.06 * h)


#: The hand sites' group: one MuJoCo's default visual options leave out.
HIDDEN_SITE_GROUP = 5

#: A body's visual, one merged mesh per body: ``add_visual(body, link, group, name)`` (the
#: builder turns the link's parts into one palette-coloured mesh geom: one draw call).
AddVisual = Callable[[Any, Link, int, str], None]


@lru_cache(maxsize=2 * USER_LOOKS + 8)
def person_links(height: float, look: Appearance, separate_hands: bool = True) -> dict[str, Link]:
    """The visual of each part of a person (a :class:`Link` of low-poly parts per body that
    carries geometry), in that body's frame. The feet are drawn with the lower legs (they
    have no joint of their own); the hands too unless ``separate_hands`` (the agent's hands
    are apart so that its own camera can show them and nothing else of it). Cached: the
    builder's merged meshes of the same links are made once per process."""
    p = proportions(height * look.height_scale, look.girth)
    h, g = p.height, p.girth
    robot = look.silhouette == "robot"

    def ellipsoid(centre, radii, rgba, subdivisions: int = 1) -> Part:
        # 80 triangles (20 for small parts): a renderer on a CPU pays per triangle too.
        r = max(radii)
        return sphere_part(centre, r, rgba, scale=tuple(x / r for x in radii), collision="none",
                           subdivisions=subdivisions)

    def limb(length: float, radius: float, rgba) -> list[Part]:
        # A tapered, closed cylinder hanging from the joint (6 sides: 24 triangles).
        return [cylinder_part((0, 0, -length / 2), radius * 0.9, length, rgba, segments=6, collision="none",
                              radius_top=radius)]

    lower = look.top if look.silhouette == "skirt" else look.bottom
    # The torso body sits at the waist; the pelvis is drawn with it (no joint between them).
    torso = [ellipsoid((0, 0, 0.025 * h - p.waist_z), (0.07 * h * g, 0.1 * h * g, 0.065 * h), lower)]
    if look.silhouette == "skirt":
        torso.append(ellipsoid((0, 0, -0.06 * h - p.waist_z), (0.09 * h * g, 0.115 * h * g, 0.11 * h), look.top))
    if robot:
        torso.append(box_part((0, 0, 0.14 * h), (0.14 * h, 0.22 * h, 0.26 * h), look.top, collision="none"))
    else:
        torso.append(ellipsoid((0, 0, 0.13 * h), (0.075 * h * g, 0.12 * h * g, 0.16 * h), look.top))
    hr, hz = p.head_radius, p.head_radius * 0.75
    if robot:
        head = [box_part((0, 0, hz), (2 * hr, 1.8 * hr, 2.1 * hr), look.skin, collision="none"),
                box_part((hr, 0, hz + 0.1 * hr), (0.02 * h, 1.5 * hr, 0.7 * hr), look.hair, collision="none")]
    else:
        long_hair = look.silhouette == "long_hair"
        head = [ellipsoid((0.01 * h, 0, hz), (hr * 0.95, hr * 0.85, hr * 1.1), look.skin),
                ellipsoid((-0.012 * h, 0, hz + (-0.02 * h if long_hair else 0.025 * h)),
                          (hr, hr * 0.92, hr * (1.2 if long_hair else 0.8)), look.hair)]
    links = {"torso": Link("torso", torso), "head": Link("head", head)}
    ankle_z = p.hip_z - p.upper_leg - p.lower_leg
    for side in SIDES:
        hand = ellipsoid((0, 0, -0.03 * h), (0.014 * h, 0.028 * h, 0.045 * h), look.skin, subdivisions=0)
        fore = limb(p.lower_arm, 0.021 * h * g, look.bottom if robot else look.skin)
        links[f"{side}_upper_arm"] = Link("upper_arm", limb(p.upper_arm, 0.026 * h * g, look.top))
        if separate_hands:
            links[f"{side}_lower_arm"] = Link("lower_arm", fore)
            links[f"{side}_hand"] = Link("hand", [hand])
        else:  # the hand in the forearm's frame: the wrist is at the forearm's end
            links[f"{side}_lower_arm"] = Link("lower_arm", [*fore, _moved(hand, -p.lower_arm)])
        links[f"{side}_upper_leg"] = Link("upper_leg", limb(p.upper_leg, 0.037 * h * g, look.bottom))
        foot = box_part((0.035 * h, 0, -p.lower_leg - ankle_z / 2), (0.13 * h, 0.056 * h, ankle_z), look.shoes,
                        collision="none")
        shin = limb(p.lower_leg, 0.028 * h * g, look.skin if look.silhouette == "skirt" else look.bottom)
        links[f"{side}_lower_leg"] = Link("lower_leg", [*shin, foot])
    return links


def _moved(part: Part, dz: float) -> Part:
    """``part`` moved ``dz`` metres along z."""
    matrix = np.eye(4)
    matrix[2, 3] = dz
    return part.transformed(matrix)


def add_humanoid(root, who: str, height: float, look: Appearance, *, body_group: int, hand_group: int,
                 add_visual: AddVisual | None = None, separate_hands: bool = True,
                 articulated: bool = True) -> None:
    """Add a person's parts, joints and hand sites under ``root`` (an ``MjsBody``: the
    avatar's root at the floor, facing +x). ``height`` is the body's nominal height;
    ``look.height_scale`` and ``look.girth`` vary it. ``add_visual`` draws each part (see
    :data:`AddVisual`); without it the skeleton has no geometry. ``separate_hands``: see
    :func:`person_links`. ``articulated=False`` (a person who never moves a limb: the user
    of the single-agent envs) draws the whole person as one mesh in the idle pose on the
    root (:func:`statue_link`): the same picture in one draw call; the skeleton is built
    all the same, without geometry."""
    p = proportions(height * look.height_scale, look.girth)
    links = person_links(height, look, separate_hands) if articulated else {}
    if not articulated and add_visual is not None:
        add_visual(root, statue_link(height, look), body_group, f"{who}/body")

    def child(parent, part: str, pos):
        body = parent.add_body(name=f"{who}/{part}", pos=list(pos), gravcomp=1.0)
        # Joints need a mass to move; a visual-only part has none of its own.
        body.mass, body.inertia, body.explicitinertial = 1.0, [0.01, 0.01, 0.01], True
        for j in JOINTS:
            if j.part == part:
                body.add_joint(name=f"{who}/{j.name}", type=mujoco.mjtJoint.mjJNT_HINGE, axis=list(j.axis),
                               range=[math.radians(j.range_deg[0]), math.radians(j.range_deg[1])],
                               limited=mujoco.mjtLimited.mjLIMITED_TRUE, armature=0.01, damping=1.0)
        if add_visual is not None and part in links:
            add_visual(body, links[part], hand_group if part.endswith("_hand") else body_group, f"{who}/{part}")
        return body

    pelvis = child(root, "pelvis", (0, 0, p.hip_z))
    torso = child(pelvis, "torso", (0, 0, p.waist_z))
    child(torso, "head", (0, 0, p.neck_z))
    for side in SIDES:
        sign = 1.0 if side == "left" else -1.0
        upper = child(torso, f"{side}_upper_arm", (0, sign * p.shoulder_y, p.shoulder_z))
        fore = child(upper, f"{side}_lower_arm", (0, 0, -p.upper_arm))
        hand = child(fore, f"{side}_hand", (0, 0, -p.lower_arm))
        # A site group no camera shows (MuJoCo draws sites of groups 0-2 by default).
        hand.add_site(name=f"{who}/{side}_hand", pos=[0, 0, -p.hand], size=[0.01, 0, 0], group=HIDDEN_SITE_GROUP)
        thigh = child(pelvis, f"{side}_upper_leg", (0, sign * p.hip_y, 0))
        shin = child(thigh, f"{side}_lower_leg", (0, 0, -p.upper_leg))
        child(shin, f"{side}_foot", (0, 0, -p.lower_leg))


def skeleton_model(height: float, look: Appearance) -> mujoco.MjModel:
    """A model of one person alone (root fixed at the origin, facing +x): what the reach IK
    runs its forward kinematics on, a few microseconds a pass instead of a whole house's."""
    spec = mujoco.MjSpec()
    spec.compiler.degree = False
    root = spec.worldbody.add_body(name="person")
    add_humanoid(root, "person", height, look, body_group=0, hand_group=0)
    return spec.compile()


@lru_cache(maxsize=2 * USER_LOOKS)
def statue_link(height: float, look: Appearance) -> Link:
    """The whole person (hands with the forearms) as one link in the idle pose, in the root's
    frame: every part moved where the skeleton's forward kinematics puts its body."""
    model = skeleton_model(height, look)
    data = mujoco.MjData(model)
    PoseWriter(model, "person").write(data, IDLE_POSE)
    mujoco.mj_kinematics(model, data)
    parts: list[Part] = []
    for part, link in person_links(height, look, False).items():
        body = model.body(f"person/{part}").id
        matrix = np.eye(4)
        matrix[:3, :3] = data.xmat[body].reshape(3, 3)
        matrix[:3, 3] = data.xpos[body]
        parts += [piece.transformed(matrix) for piece in link.parts]
    return Link("body", parts)


def element_id(model: mujoco.MjModel, kind: mujoco.mjtObj, name: str) -> int:
    """The id of the model's element of ``kind`` named ``name`` (``mj_name2id``, without
    the accessor object ``model.body(name)`` makes); KeyError if there is none."""
    found = mujoco.mj_name2id(model, kind, name)
    if found < 0:
        raise KeyError(f"no {kind.name[6:].lower()} named {name!r} in the model")
    return found


class PoseWriter:
    """Writes joint angles (a vector in :data:`JOINTS` order, radians) into a compiled
    model's ``qpos`` for the person ``who``."""

    def __init__(self, model: mujoco.MjModel, who: str):
        # mj_name2id: every episode makes its bodies' writers, and an accessor object per
        # name (model.joint(name)) costs many times the lookup.
        self.addresses = np.array([model.jnt_qposadr[element_id(model, mujoco.mjtObj.mjOBJ_JOINT, f"{who}/{j.name}")]
                                   for j in JOINTS])
        self.hand_sites = {s: element_id(model, mujoco.mjtObj.mjOBJ_SITE, f"{who}/{s}_hand") for s in SIDES}

    def write(self, data: mujoco.MjData, angles: np.ndarray) -> None:
        data.qpos[self.addresses] = angles

"""What a task is: it picks a goal in a house, words an instruction, and judges success.

Tasks know the world (scene, built world, navigation grid, the agent's and user's bodies)
through :class:`TaskContext`; they know nothing of Gymnasium.
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np

from legent_gym.agent.body import Body
from legent_gym.world.builder import World
from legent_gym.world.navigation import NavGrid
from legent_gym.world.rays import RayHit, cast_ray
from legent_gym.world.scene import Scene

#: The paper's evaluation cap on the agent's actions in an episode: the registered ids'
#: ``max_episode_steps``, the multi-agent envs' ``max_cycles``, and what the task samplers
#: budget a goal's expert plan against.
MAX_ACTIONS = 25
#: Distance fields a TaskContext keeps (least recently used dropped first).
FIELD_CACHE_SIZE = 16


@dataclass
class TaskContext:
    """Everything a task may read: privileged state, never shown to the agent directly."""

    scene: Scene
    world: World
    agent: Body
    user: Body
    nav: NavGrid
    speech: list[str] = field(default_factory=list)  # what the agent said this episode
    finished: bool = False
    # Distance fields to goal points, and standing points of objects: goals stay put
    # within an episode, so each costs one Dijkstra, and every later query is a lookup.
    _fields: dict = field(default_factory=dict, repr=False)
    _stands: dict = field(default_factory=dict, repr=False)

    def geodesic_to(self, point) -> float:
        """Geodesic metres from the agent to a floor point (inf if unreachable)."""
        # Keyed by grid cell (every point of a cell snaps to the same goal), and bounded: a
        # goal that moves (the user walking, in the multi-agent env) adds a field per cell.
        nav = self.nav
        key = nav.to_cell(point)
        fields = self._fields
        grid = fields.get(key)
        if grid is None:
            grid = nav.distance_field(point)
            if len(fields) >= FIELD_CACHE_SIZE:
                del fields[next(iter(fields))]
            fields[key] = grid
        elif next(reversed(fields)) != key:
            fields[key] = fields.pop(key)  # most recently used last
        here = nav.nearest_walkable_cell(self.agent.xy)
        return math.inf if here is None else float(grid[here])

    def cached_distances(self) -> dict[str, dict]:
        """The distance fields and standing points found so far (a copy), for
        :meth:`add_cached_distances` of a context of the same house and episode."""
        return {"fields": dict(self._fields), "stands": dict(self._stands)}

    def add_cached_distances(self, cached: dict[str, dict]) -> None:
        """Take what :meth:`cached_distances` of another context of this house and
        episode found (the same answers, without searching again)."""
        self._fields.update(cached["fields"])
        self._stands.update(cached["stands"])

    def distance_to_object(self, object_id: int) -> float:
        """Geodesic metres from the agent to where it could reach the object."""
        if self.agent.state.held == object_id:
            return 0.0
        pos = self.world.object_position(object_id)
        key = (object_id, round(float(pos[0]), 1), round(float(pos[1]), 1))
        if key not in self._stands:
            self._stands[key] = self.nav.standing_point(object_id,
                                                        reach=self.agent.reach * 0.8,
                                                        start=tuple(self.agent.position))
        stand = self._stands[key]
        return self.geodesic_to(stand) if stand is not None else math.inf

    def name_of(self, object_id: int) -> str:
        return self.world.assets[object_id].names[0]

    def names_of(self, object_id: int) -> list[str]:
        return [n.lower() for n in self.world.assets[object_id].names]

    def category_count(self, category: str) -> int:
        return sum(1 for o in self.scene.objects if self.world.assets[o.id].category == category)

    def unique_objects(self, *, interactable: bool | None = None) -> list[int]:
        """Objects whose category appears once in the house, so "the apple" is unambiguous."""
        out = []
        for obj in self.scene.objects:
            if interactable is not None and (obj.kind == "interactable") != interactable:
                continue
            if self.category_count(self.world.assets[obj.id].category) == 1:
                out.append(obj.id)
        return out

    def object_centre(self, object_id: int) -> np.ndarray:
        """The centre of the object's bounds where it is now."""
        return self.world.object_centre(object_id)

    def footprint(self, object_id: int) -> np.ndarray:
        """World (x, y) corners (4, 2) of the object's bounds where it is now."""
        world = self.world
        lo, hi = world.assets[object_id].bounds()
        body = world.object_body[object_id]
        rot = world.data.xmat[body].reshape(3, 3)[:2, :2]
        local = np.array([(lo[0], lo[1]), (hi[0], lo[1]), (hi[0], hi[1]), (lo[0], hi[1])])
        return world.data.xpos[body][:2] + local @ rot.T

    def reach_distance(self, xy, object_id: int) -> float:
        """Horizontal metres from ``xy`` to the nearest point of the object's footprint (0
        inside it): what "within reach of A" measures, so that a large bed counts as
        reached from its side."""
        corners = self.footprint(object_id)
        origin, u, v = corners[0], corners[1] - corners[0], corners[3] - corners[0]
        rel = np.asarray(xy, dtype=float)[:2] - origin
        a = float(np.clip(rel @ u / max(u @ u, 1e-12), 0.0, 1.0))
        b = float(np.clip(rel @ v / max(v @ v, 1e-12), 0.0, 1.0))
        return float(np.linalg.norm(rel - a * u - b * v))

    def is_visible(self, body: Body, object_id: int, max_fov_deg: float | None = None) -> bool:
        """The object's centre is in the camera's view and a ray to it hits the object first."""
        ray = self._view_ray(body, self.object_centre(object_id), max_fov_deg, target=object_id)
        if ray is None:
            return False
        hit, dist = ray
        return dist < 1e-6 or (hit is not None and hit.object_id == object_id)

    def sees_point(self, body: Body, point: np.ndarray) -> bool:
        """``point`` is in the camera's view and no house or object geometry (the held
        object aside) is in front of it: the test for what is in neither group, such as an
        avatar."""
        ray = self._view_ray(body, np.asarray(point, dtype=float))
        if ray is None:
            return False
        hit, dist = ray
        return hit is None or hit.distance >= dist - 1e-3

    def _view_ray(self, body: Body, point: np.ndarray, max_fov_deg: float | None = None,
                  target: int | None = None) -> tuple[RayHit | None, float] | None:
        """None when ``point`` is outside the field of view of ``body``'s camera; else the
        ray from the camera towards it: (the first house or object surface it meets, None
        for none; distance to the point), (None, 0) for a point at the eye. The held object
        is no obstacle unless it is ``target``."""
        eye = body.camera_position
        to = point - eye
        dist = float(np.linalg.norm(to))
        if dist < 1e-6:
            return None, 0.0
        fov = max_fov_deg if max_fov_deg is not None else body.options.fovy
        if math.degrees(math.acos(float(np.clip(to @ body.view_direction() / dist, -1, 1)))) > fov / 2:
            return None
        held = body.state.held
        return cast_ray(self.world, eye, to / dist, held if held != target else None), dist


@dataclass
class Evaluation:
    success: bool
    ends: bool  # the episode is over (success, or a terminal failure such as a wrong answer)
    info: dict[str, Any] = field(default_factory=dict)


class TaskInstance(ABC):
    """One sampled goal in one house: subclasses are dataclasses with ``instruction`` and,
    where the task has them, ``target`` and ``receptacle`` object ids."""

    instruction: str

    @abstractmethod
    def evaluate(self, ctx: TaskContext) -> Evaluation:
        """Success and the end of the episode: cheap, asked after every action."""

    @abstractmethod
    def distance_left(self, ctx: TaskContext) -> float:
        """Geodesic metres left to the current sub-goal (``inf`` if unreachable), for shaped
        rewards and ``info``. Apart from :meth:`evaluate` because it is dearer: a goal that
        moves (the user, in the multi-agent env) costs a search of the house each step, so
        envs ask only when a reward or the caller needs it."""

    def describe(self) -> dict[str, Any]:
        """The goal's object ids (None where the task has none) and the answers it accepts
        (WhereIs; else empty): the same keys for every task."""
        return {"target": getattr(self, "target", None), "receptacle": getattr(self, "receptacle", None),
                "answers": list(getattr(self, "answers", ()))}


#: The intermediate code that fetches the target: goes to it, aims at it and grabs it. A
#: task's :attr:`Task.code` that starts with it picks its target up, so the target must be
#: interactable, and an expert taking over with the target in hand skips it.
FETCH_CODE = "goto({a}) target({a}) interact()"
#: The fields of :attr:`Task.code`: the goal's target and receptacle ids, the receptacle's name.
CODE_FIELDS = ("a", "b", "b_name")


class Task(ABC):
    """A task family: ComeHere, GoTo, PickUp, BringMe, WhereIs, PutOn, each in its own file.

    A task class carries everything about the task: the instructions (:attr:`templates`),
    goal sampling (:meth:`sample`, with :meth:`house_conditions`), success (the goal's
    :meth:`TaskInstance.evaluate`), the expert's intermediate code (:attr:`code`), and the
    kinds of a tasks file it judges with their lines for the LLM task generator
    (:attr:`kinds`, :meth:`goal_for`, :meth:`spec_problem`). It is registered with
    :func:`legent_gym.tasks.registry.register_task`; docs/adding-a-task.md walks through one.
    """

    name: str = "task"
    #: Instruction paraphrases; ``{a}`` and ``{b}`` stand for object names. The first is the
    #: paper's wording (:func:`~legent_gym.tasks.registry.paper_instruction`).
    templates: tuple[str, ...] = ()
    #: The paper's intermediate code that completes a goal (Table 2), which the experts
    #: plan: ``{a}`` and ``{b}`` stand for the goal's target and receptacle ids, ``{b_name}``
    #: for the receptacle's name. Code starting with :data:`FETCH_CODE` picks the target up.
    code: str = ""
    #: The object fields of the goal, in order (``"target"``, ``"receptacle"``): what a
    #: tasks file's line of one of :attr:`kinds` must give.
    roles: tuple[str, ...] = ()
    #: The kinds of task in a tasks file (:mod:`legent_gym.tasks.custom`) this task judges,
    #: each with its description in the LLM task generator's prompt.
    kinds: ClassVar[dict[str, str]] = {}
    #: The goal's class: made from an instruction and the ids of :attr:`roles`, in order,
    #: by the default :meth:`goal_for`.
    goal_type: ClassVar[type[TaskInstance] | None] = None

    @classmethod
    def fetches_target(cls) -> bool:
        """The task's code picks the target up first (:data:`FETCH_CODE`)."""
        return cls.code.startswith(FETCH_CODE)

    @classmethod
    def goal_for(cls, ctx: TaskContext, instruction: str, target: int | None = None,
                 receptacle: int | None = None) -> TaskInstance:
        """The goal of a tasks file's line of one of :attr:`kinds` in ``ctx``'s scene (the
        ids of :attr:`roles` are given and in the scene): :attr:`goal_type` of the
        instruction and those ids."""
        if cls.goal_type is None:
            raise NotImplementedError(f"{cls.name} has no goal_type to make a tasks file's goal of")
        ids = {"target": target, "receptacle": receptacle}
        return cls.goal_type(instruction, *(ids[role] for role in cls.roles))  # type: ignore[call-arg]

    @classmethod
    def spec_problem(cls, ctx: TaskContext, target: int | None, receptacle: int | None) -> str | None:
        """Why a tasks file's line of one of :attr:`kinds` with these objects cannot be a
        goal in ``ctx``'s scene (None: it can). The objects exist; that a fetched target
        can be picked up is checked for every task."""
        return None

    def house_conditions(self, house_seed: int) -> dict[str, Any]:
        """Generation conditions this task needs of the house of ``house_seed`` (e.g. a
        minimum start distance). A condition drawn at random draws from the house seed, so
        the same seed still gives the same house."""
        return {}

    @abstractmethod
    def sample(self, ctx: TaskContext, rng: np.random.Generator) -> TaskInstance | None:
        """A goal in this house, or None if the house offers none (a new house is drawn)."""

    def goal_task(self, goal: TaskInstance) -> str:
        """The name of the template task whose expert plan completes ``goal`` (this task's
        own name; a task that plays the templates' goals says which)."""
        return self.name

    def word(self, rng: np.random.Generator, **names: str) -> str:
        template = self.templates[int(rng.integers(len(self.templates)))]
        return template.format(**names)

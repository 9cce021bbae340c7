"""The episode engine: one house and one goal at a time, without Gymnasium.

:class:`Episode` is what every front end of the household tasks drives: the single-agent
Gymnasium env (:class:`~legent_gym.envs.household.HouseholdEnv`), the PettingZoo envs
(through it), their single-agent view (:class:`~legent_gym.multiagent.SingleAgentEnv`), the
experts' :class:`~legent_gym.experts.Oracle`, and any interactive server. It does five
things, each one public method:

1. **draw a house** (:class:`HouseSource`: a fixed scene, a fixed seed, a pool of seeds, or a
   new seed of a layout each time) and **set it up** (build the MuJoCo world, place the
   agent's and the user's bodies, make the navigation grid) and **sample the task's goal**
   in it: :meth:`Episode.begin`;
2. **run a body's primitives** (the agent's or the user's): :meth:`Episode.run` and
   :meth:`Episode.execute`;
3. **judge the task**: :meth:`Episode.judge` and :meth:`Episode.distance_left`;
4. **observe**: :meth:`Episode.views` (RGB, and depth and segmentation when asked, from a
   body's head camera);
5. hold the state the others read: :attr:`Episode.ctx` (scene, world, bodies, navigation
   grid, speech: see :class:`~legent_gym.tasks.base.TaskContext`), :attr:`Episode.goal`,
   :attr:`Episode.world`, :attr:`Episode.house_seed`.

Rewards, observation dictionaries, info dictionaries, step counting and spaces are the
front end's business; the engine knows nothing of them.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from legent_gym.agent.actions import (
    Action,
    ActionLimits,
    Close,
    Finish,
    Grab,
    Interact,
    MoveForward,
    Open,
    Put,
    RotateDown,
    RotateRight,
    Speak,
    clip_action,
)
from legent_gym.agent.body import Body, Outcome
from legent_gym.tasks.base import Evaluation, Task, TaskContext, TaskInstance
from legent_gym.world.builder import BuildOptions, World, build_world
from legent_gym.world.generation import GenerationError, generate_house
from legent_gym.world.navigation import NavGrid
from legent_gym.world.render import Renderer
from legent_gym.world.scene import Scene

#: Houses drawn before :meth:`Episode.begin` gives up on finding one with a goal.
HOUSE_RETRIES = 20
#: The body method behind each interaction primitive (each takes an optional target).
BODY_METHOD = {Interact: "interact", Grab: "grab", Put: "put", Open: "open", Close: "close"}


class HouseSource:
    """Where each episode's house comes from, in this order of precedence: a fixed
    ``scene``, a ``house_pool`` of generation seeds cycled through, a fixed ``house_seed``,
    else a new seed of ``layout`` drawn from the episode's generator."""

    def __init__(self, layout: str, *, scene: Scene | None = None, house_seed: int | None = None,
                 house_pool: list[int] | None = None):
        self.layout = layout
        self.scene = scene
        self.house_seed = house_seed
        self.house_pool = list(house_pool) if house_pool else None
        self.pool_index = 0

    @property
    def seed_fixed(self) -> bool:
        """A generation failure is the caller's to see (a fixed seed or a pool), not a
        reason to draw another house."""
        return self.house_seed is not None or bool(self.house_pool)

    @property
    def house_fixed(self) -> bool:
        """Every episode is in the same house: a house with no goal is an error."""
        return self.scene is not None or (self.house_seed is not None and not self.house_pool)

    def draw(self, rng: np.random.Generator, task: Task) -> tuple[Scene, int | None]:
        """The next house and its generation seed (None for a fixed scene); raises
        :class:`~legent_gym.world.generation.GenerationError` when generation fails."""
        if self.scene is not None:
            return self.scene, None
        if self.house_pool:
            seed = self.house_pool[self.pool_index % len(self.house_pool)]
            self.pool_index += 1
        elif self.house_seed is not None:
            seed = self.house_seed
        else:
            seed = int(rng.integers(2**31 - 1))
        return generate_house(seed, self.layout, **task.house_conditions(seed)), seed


@dataclass(frozen=True)
class Observing:
    """What :meth:`Episode.views` renders: image size and the extra images."""

    width: int
    height: int
    depth: bool = False
    segmentation: bool = False


class Episode:
    """One house and one goal at a time (see the module docstring).

    Args:
        task: the task family that samples goals and judges them.
        houses: where houses come from.
        build_options: the bodies' sizes and cameras, and how the world is built.
        observing: image size and extra images of :meth:`views`.
        reach: the agent's interaction distance (metres).
        limits: the action limits primitives are clipped to.
    """

    def __init__(self, task: Task, houses: HouseSource, build_options: BuildOptions, observing: Observing, *,
                 reach: float, limits: ActionLimits):
        self.task = task
        self.houses = houses
        self.build_options = build_options
        self.observing = observing
        self.reach = reach
        self.limits = limits
        #: The current house, goal and their context; None before the first :meth:`begin`.
        self.ctx: TaskContext | None = None
        self.goal: TaskInstance | None = None
        #: The generation seed of the current house (None for a fixed scene).
        self.house_seed: int | None = None
        self._renderer: Renderer | None = None

    @property
    def world(self) -> World | None:
        """The built world of the current house (None before the first :meth:`begin`)."""
        return None if self.ctx is None else self.ctx.world

    def require(self) -> TaskContext:
        """The current context; raises RuntimeError before the first :meth:`begin`."""
        if self.ctx is None:
            raise RuntimeError("no episode has begun: call reset() first")
        return self.ctx

    # -- 1. house draw, set-up and goal --------------------------------------------------------
    def begin(self, rng: np.random.Generator, scene: Scene | None = None) -> int:
        """Start an episode: draw a house (``scene`` if given, else from :attr:`houses`), set
        it up and sample a goal, drawing another house while one offers none. Returns the
        number of houses tried. Every draw comes from ``rng``."""
        failure = None
        for attempt in range(HOUSE_RETRIES):
            if scene is not None:
                house, house_seed = scene, None
            else:
                try:
                    house, house_seed = self.houses.draw(rng, self.task)
                except GenerationError as err:
                    # A task's condition this layout cannot meet (a kitchen counter asked of a
                    # bedroom): draw another house, unless the seed is fixed.
                    if self.houses.seed_fixed:
                        raise
                    failure = err
                    continue
            self.set_up(house)
            self.goal = self.task.sample(self.ctx, rng)
            if self.goal is not None:
                self.house_seed = house_seed
                return attempt + 1
            if scene is not None or self.houses.house_fixed:
                raise ValueError(f"task {self.task.name} has no valid goal in house {house.name!r}")
        raise RuntimeError(f"no house in {HOUSE_RETRIES} tries offered a {self.task.name} goal"
                           + (f" (the last generation failed: {failure})" if failure else ""))

    def set_up(self, scene: Scene) -> TaskContext:
        """Build ``scene`` and put the agent and the user at its spawns (no goal yet)."""
        self.close()
        world = build_world(scene, self.build_options)
        agent = Body(world, "agent", reach=self.reach, other="user" if scene.user else None)
        user = Body(world, "user", other="agent")
        nav = NavGrid.from_scene(scene, agent_radius=self.build_options.agent.radius)
        self.ctx = TaskContext(scene, world, agent, user, nav)
        return self.ctx

    # -- 2. running primitives -------------------------------------------------------------------
    def run(self, primitives: tuple[Action, ...] | list[Action], body: Body | None = None) -> list[Outcome]:
        """Run a step's primitives in order by the agent (or ``body``), with one update of
        the world for its moves and turns (see :meth:`~legent_gym.agent.body.Body.batched`)."""
        ctx = self.require()
        actor = ctx.agent if body is None else body
        with actor.batched():
            return [self.execute(p, body) for p in primitives]

    def execute(self, primitive: Action, body: Body | None = None) -> Outcome:
        """Run one primitive by the agent, or by ``body`` (the multi-agent env's user moves
        and interacts through here; it handles the user's speech and finish itself). The
        primitive is clipped to :attr:`limits` first; the outcome's reason says so."""
        ctx = self.require()
        primitive, note = clip_action(primitive, self.limits)
        actor = ctx.agent if body is None else body
        match primitive:
            case MoveForward(distance=d):
                outcome = actor.move_forward(d)
            case RotateRight(degrees=d):
                outcome = actor.rotate_right(d)
            case RotateDown(degrees=d):
                outcome = actor.rotate_down(d)
            case Speak(text=text):
                ctx.speech.append(text)
                outcome = Outcome(True)
            case Finish():
                ctx.finished = True
                outcome = Outcome(True)
            case Interact() | Grab() | Put() | Open() | Close():
                outcome = getattr(actor, BODY_METHOD[type(primitive)])(primitive.target)
            case _:
                outcome = Outcome(False, f"unsupported action {primitive!r}")
        if note:
            outcome.reason = f"{note}; {outcome.reason}" if outcome.reason else note
        return outcome

    # -- 3. judging ------------------------------------------------------------------------------
    def judge(self) -> Evaluation:
        """Success and the end of the episode, as the task judges them now (cheap)."""
        return self.goal.evaluate(self.require())

    def distance_left(self) -> float:
        """Geodesic metres to the current sub-goal (dearer than :meth:`judge`: a goal that
        moves costs a search of the house)."""
        return self.goal.distance_left(self.require())

    @property
    def ended(self) -> bool:
        """The agent said ``finish()`` in this episode."""
        return self.require().finished

    # -- 4. observing ----------------------------------------------------------------------------
    @property
    def renderer(self) -> Renderer:
        """The head cameras' renderer of the current house, made on the first frame (no
        OpenGL context exists before it, so a process may fork until then)."""
        if self._renderer is None:
            o = self.observing
            self._renderer = Renderer(self.require().world, o.width, o.height, "fast")
        return self._renderer

    def views(self, who: str = "agent") -> dict[str, np.ndarray]:
        """What ``who`` (``"agent"`` or ``"user"``) sees: ``rgb``, and ``depth`` and
        ``segmentation`` when :attr:`observing` asks for them."""
        renderer = self.renderer
        out = {"rgb": renderer.rgb(who)}
        if self.observing.depth:
            out["depth"] = renderer.depth(who)
        if self.observing.segmentation:
            out["segmentation"] = renderer.segmentation(who)
        return out

    def close(self) -> None:
        """Free the renderer (a new one is made for the next frame)."""
        if self._renderer is not None:
            self._renderer.close()
            self._renderer = None

    # Pickling: the house is set up again at the next begin().
    def __getstate__(self) -> dict[str, Any]:
        state = self.__dict__.copy()
        state.update(ctx=None, goal=None, _renderer=None)
        return state

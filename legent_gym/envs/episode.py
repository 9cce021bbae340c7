"""The episode engine: one house and one goal at a time, without Gymnasium.

:class:`Episode` is what every front end of the household tasks drives: the single-agent
Gymnasium env (:class:`~legent_gym.envs.household.HouseholdEnv`), the PettingZoo envs
(through it), their single-agent view (:class:`~legent_gym.multiagent.SingleAgentEnv`), the
experts' :class:`~legent_gym.experts.Oracle`, and any interactive server. It does five
things, each one public method:

1. **draw a house** (:class:`HouseSource`: a fixed scene, a fixed seed, a pool of seeds, a
   folder of scene files, or a new seed of a layout each time) and **set it up** (build
   the MuJoCo world, place the agent's and the user's bodies, make the navigation grid)
   and **sample the task's goal** in it: :meth:`Episode.begin`;
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

**Houses are kept.** Building a house costs tens of milliseconds, an episode step well
under one, and training resets every twenty-odd steps. So a built house (:class:`House`)
is kept with a copy of its state as built, and an episode in a house built before starts
by restoring that copy (:mod:`legent_gym.world.state`): small objects back where the house
has them, doors and drawers as built, nothing held, nothing said. A house is reused

* for ``episodes_per_house`` consecutive episodes (default 1): the first in a house starts
  at the scene's spawns; each later one draws new spawns for the agent and the user (the
  task's conditions, e.g. ComeHere's 3 m apart, hold) and a new goal;
* whenever the house source gives a house it gave before (a fixed ``scene`` or
  ``house_seed``, an entry of ``house_pool``, a file of a ``houses`` folder): the last
  ``houses_kept`` such houses are kept (:data:`HOUSE_CACHE_SIZE` by default; with
  ``episodes_per_house`` 1, a house of a new random seed is not). A kept house costs a few
  megabytes (about 3 a OneRoom house, 4 a TwoRoom one): a ``houses`` folder of N houses
  with ``houses_kept`` >= N builds each house once.

**Every episode is the episode of a seed.** :meth:`Episode.play` begins the episode of a
seed, which depends on the seed alone: seeds ``s`` with one ``s // K`` (``K`` =
``episodes_per_house``) share a house, and spawns and goal come from a generator seeded
with ``s``. A reset with a seed plays that seed; a reset without one plays the next seed
of the current block while the block has episodes left, else the first seed ``b * K`` of
a block ``b`` drawn from the env's generator (one draw per block, whatever the episodes
did). So ``reset(seed=Episode.episode_seed)`` plays any episode again, and the seeds of
the coming episodes are known before they begin (:meth:`Episode.upcoming`), which is what
lets them be prepared elsewhere:

* **in helper processes** (``helpers`` > 0; :mod:`legent_gym.envs.factory`), which play
  the coming seeds while the env steps and ship each episode ready to use; what is left
  to do here (loading a new house's model, putting the bodies at their spawns, uploading
  its meshes for the renderer) is done a piece at a time after the steps before it
  (:meth:`Episode.stage`, about a millisecond a step), so that a reset only swaps the
  next episode in and draws its first frame;
* **or, for the house alone, in a thread** (``prepare_ahead``): once an episode has begun
  in the last episode of its house, the next block's house is generated and built in a
  background thread at the lowest CPU priority, in time the process would spend waiting
  (a vector env's worker waits for the slowest worker at every step). One build runs at
  a time.

Either way the next ``begin`` takes what was prepared only if it is the seed (or house)
drawn, and plays it itself otherwise, so the episodes are the same with or without them.

A house from a ``houses`` folder is written without a task in mind, so its every episode
draws spawns under the task's conditions.
"""

from __future__ import annotations

import threading
from collections import OrderedDict
from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any

import mujoco
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
from legent_gym.envs.factory import EpisodeFactory, HelperDied, PreparedEpisode
from legent_gym.envs.house_store import HouseStore
from legent_gym.envs.houses import House, HouseAhead, HouseDraw, HouseSource
from legent_gym.tasks.base import Evaluation, Task, TaskContext, TaskInstance
from legent_gym.utils import heap
from legent_gym.world.builder import BuildOptions, World, build_world
from legent_gym.world.generation import GenerationError
from legent_gym.world.generation.conditions import HouseSpec
from legent_gym.world.generation.house import AttemptFailed, SpawnSampler
from legent_gym.world.navigation import NavGrid
from legent_gym.world.render import Renderer
from legent_gym.world.scene import Scene, Spawn
from legent_gym.world.state import capture, restore

#: Houses drawn before :meth:`Episode.begin` gives up on finding one with a goal.
HOUSE_RETRIES = 20
#: Built houses kept for reuse by default (a house is a few megabytes).
HOUSE_CACHE_SIZE = 8
#: New spawns tried in a kept house before a house with no goal for them is left.
SPAWN_RETRIES = 3
#: Mixed into the seed of the generator that draws a block of seeded episodes' house, so
#: that it is not the stream of any episode's own seed.
HOUSE_STREAM = 0x4E05E
#: An episode begun without a seed starts a new block at a seed ``b * K`` with ``b`` drawn
#: below this from the env's generator (``K`` = ``episodes_per_house``).
SEED_BLOCKS = 2**31 - 1
#: The body method behind each interaction primitive (each takes an optional target).
BODY_METHOD = {Interact: "interact", Grab: "grab", Put: "put", Open: "open", Close: "close"}


@dataclass
class _Staged:
    """The next episode, taken from a helper and made ready here a piece at a time
    (:meth:`Episode.stage`)."""

    seed: int
    prepared: PreparedEpisode
    #: What is left to do (None: nothing).
    work: Iterator[None] | None = None
    #: Its new house, loaded, with the bodies at their spawns and its renderer (None for a
    #: house held here, which the current episode may be using).
    house: House | None = None
    ctx: TaskContext | None = None
    renderer: Renderer | None = None
    #: The agent's first views in it (what :meth:`Episode.views` gives first).
    first_views: dict[str, np.ndarray] | None = None

    def finish(self) -> None:
        if self.work is not None:
            for _ in self.work:
                pass
            self.work = None

    def drop(self) -> None:
        """Give up on it (its renderer's GL context is kept for the next renderer)."""
        self.work = None
        if self.renderer is not None:
            self.renderer.close()
            self.renderer = None


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
        episodes_per_house: consecutive episodes in one built house.
        prepare_ahead: make the next house in a background thread (module docstring; not
            with helpers).
        houses_kept: the most built houses kept for reuse (module docstring).
        helpers: processes that prepare the coming episodes (module docstring).
        house_store: a folder of built houses that houses given again are loaded from
            and stored in (:mod:`legent_gym.envs.house_store`).
    """

    def __init__(self, task: Task, houses: HouseSource, build_options: BuildOptions, observing: Observing, *,
                 reach: float, limits: ActionLimits, episodes_per_house: int = 1, prepare_ahead: bool = False,
                 houses_kept: int = HOUSE_CACHE_SIZE, helpers: int = 0, house_store: HouseStore | None = None):
        if isinstance(episodes_per_house, bool) or not isinstance(episodes_per_house, int | np.integer) \
                or episodes_per_house < 1:
            raise ValueError(f"episodes_per_house must be a positive integer, got {episodes_per_house!r}")
        self.episodes_per_house = int(episodes_per_house)
        if isinstance(houses_kept, bool) or not isinstance(houses_kept, int | np.integer) or houses_kept < 1:
            raise ValueError(f"houses_kept must be a positive integer, got {houses_kept!r}")
        self.houses_kept = int(houses_kept)
        #: Where houses given again are stored once built (None: nowhere).
        self.house_store = house_store
        self.task = task
        self.houses = houses
        self.build_options = build_options
        self.observing = observing
        self.reach = reach
        self.limits = limits
        #: The current house, goal and their context; None before the first :meth:`begin`.
        self.ctx: TaskContext | None = None
        self.goal: TaskInstance | None = None
        #: The house of the current episode.
        self.house: House | None = None
        self._kept: OrderedDict[tuple, House] = OrderedDict()
        self._renderer: Renderer | None = None
        self._renderer_world: World | None = None
        self.prepare_ahead = bool(prepare_ahead)
        self._ahead: HouseAhead | None = None
        #: The seed of the current episode (given or drawn; None for a scene given to begin).
        self.episode_seed: int | None = None
        if isinstance(helpers, bool) or not isinstance(helpers, int | np.integer) or helpers < 0:
            raise ValueError(f"helpers must be a non-negative integer, got {helpers!r}")
        #: Helper processes that prepare the coming episodes (0: none; see the module docstring).
        self.helpers = int(helpers)
        self._factory: EpisodeFactory | None = None
        #: With helpers: the seed the next begin() without a seed plays, and that episode
        #: as far as :meth:`stage` has made it ready.
        self._next_seed: int | None = None
        self._staged: _Staged | None = None
        #: The agent's views drawn ahead for the episode just begun, given by the first
        #: views("agent") unless the world moved first.
        self._first_views: dict[str, np.ndarray] | None = None
        #: The renderer and house the last staged begin() left: freed by the next stage(),
        #: off the reset.
        self._retired: tuple[Renderer | None, House | None] | None = None
        #: Of those, episodes begun in a new house that :meth:`stage` had loaded and entered.
        self.episodes_staged = 0
        #: Episodes begun from one a helper prepared (the rest were played here).
        self.episodes_from_helpers = 0
        #: Keep each built house's compiled model as MuJoCo's binary (what helpers ship).
        self.keep_binaries = False
        #: Houses made ahead that a begin() took (the rest were not the house drawn).
        self.houses_taken_ahead = 0
        # Houses are made one at a time (the asset caches are shared by all builds).
        self._build_lock = threading.Lock()
        #: Whether the bodies keep the poses each step passes through (what
        #: :meth:`in_between` shows; an env with ``frames_per_step`` > 1 sets it).
        self.record_motion = False

    @property
    def house_seed(self) -> int | None:
        """The generation seed of the current house (None for a scene given as it is)."""
        return None if self.house is None else self.house.seed

    @property
    def kept_houses(self) -> int:
        """How many built houses are kept for reuse now."""
        return len(self._kept)

    @property
    def world(self) -> World | None:
        """The built world of the current house (None before the first :meth:`begin`)."""
        return None if self.ctx is None else self.ctx.world

    def require(self) -> TaskContext:
        """The current context; raises RuntimeError before the first :meth:`begin`."""
        if self.ctx is None:
            raise RuntimeError("no episode has begun: call reset() first")
        return self.ctx

    def require_goal(self) -> TaskInstance:
        """The current goal; raises RuntimeError before the first :meth:`begin`."""
        if self.goal is None:
            raise RuntimeError("no episode has begun: call reset() first")
        return self.goal

    # -- 1. house draw, set-up and goal --------------------------------------------------------
    def begin(self, rng: np.random.Generator, scene: Scene | None = None, *, seed: int | None = None) -> int:
        """Start an episode and return the number of houses tried. With ``scene``: that house,
        set up as it is, and a goal drawn from ``rng``. Otherwise the episode of a seed (see
        :meth:`play`): ``seed`` if given, else :meth:`next_seed` of ``rng`` (the next seed
        of the current block of ``episodes_per_house`` seeds, or the first of a new block
        drawn from ``rng``). With helpers the episode is taken ready-made from them when it
        is one they were asked to prepare (:mod:`legent_gym.envs.factory`): the same episode."""
        self._first_views = None
        if scene is not None:
            self.episode_seed = None
            return self._begin(rng, rng, 0, scene)
        if seed is None:
            seed = self.next_seed(rng)
        elif isinstance(seed, bool) or not isinstance(seed, int | np.integer) or seed < 0:
            raise ValueError(f"seed must be a non-negative integer, got {seed!r}")
        seed = int(seed)
        factory = self._start_factory()
        if factory is None:
            attempts = self.play(seed)
            if self.prepare_ahead:
                self._make_next_ahead(rng)
            return attempts
        staged, self._staged = self._staged, None
        if staged is not None and staged.seed != seed:
            staged.drop()
            staged = None
        if staged is not None:
            staged.finish()
        prepared = staged.prepared if staged is not None else factory.take(seed)
        adopted = self._adopt(prepared, staged) if prepared is not None else None
        if adopted is None:
            attempts = self.play(seed)
        else:
            attempts = adopted
            self.episodes_from_helpers += 1
        upcoming = self.upcoming(rng, factory.lookahead)
        factory.want(upcoming, self._held_keys())
        self._next_seed = upcoming[0] if upcoming else None
        return attempts

    def stage(self) -> bool:
        """Do one piece (about a millisecond) of setting up the episode the next
        :meth:`begin` without a seed plays, once its helper has sent it: load its new house's
        model, put the bodies at their spawns, then upload the house's textures and meshes
        for its renderer and draw its first frame, a piece per call; True if it did one,
        False if there is nothing to do now. Front ends call it after each step (our vector
        env's workers while they wait for the next step instead); the next begin does
        whatever is left, or drops it if it plays another seed. Without helpers it does
        nothing. The episode is the same either way: staging changes only when the work is
        done."""
        if self._retired is not None:
            self._release_retired()
            return True
        if self._factory is None or self._next_seed is None:
            return False
        staged = self._staged
        if staged is None:
            try:
                prepared = self._factory.take_ready(self._next_seed)
            except HelperDied:  # raised by the next reset, which waits for that episode
                self._next_seed = None
                return False
            if prepared is None:
                return False
            staged = self._staged = _Staged(self._next_seed, prepared)
            staged.work = self._staging(staged)
            return True
        if staged.work is None:
            return False
        if next(staged.work, True):
            staged.work = None
        return True

    @property
    def staged(self) -> bool:
        """Whether :meth:`stage` has done all there is to do ahead for the next episode."""
        return self._staged is not None and self._staged.work is None

    def _staging(self, staged: _Staged) -> Iterator[None]:
        """The pieces of :meth:`stage`'s work for ``staged``."""
        prepared = staged.prepared
        if prepared.house is None or prepared.key in self._held_keys():
            return  # a house held here: entered at the reset (the current episode may be in it)
        assert self._factory is not None
        house = prepared.house.to_house(self._factory.library)
        staged.house = house
        yield
        house.episodes = prepared.episodes
        staged.ctx = self._placed(house, prepared.agent, prepared.user)
        staged.ctx.add_cached_distances(prepared.distances)
        o = self.observing
        staged.renderer = Renderer(house.world, o.width, o.height, "fast")
        yield
        while not staged.renderer.prepare_step():
            yield
        yield
        staged.first_views = self._draw_views(staged.renderer, "agent")

    def _release_retired(self) -> None:
        renderer, _house = self._retired or (None, None)
        self._retired = None
        if renderer is not None:
            renderer.close()

    def play(self, seed: int) -> int:
        """Start the episode of ``seed``, which depends on the seed alone: seeds ``s`` with
        one ``s // K`` (``K`` = ``episodes_per_house``) share a house, drawn from a generator
        of that block (a kept one is taken as it is), and ``s`` is episode ``s % K`` in it (0:
        at the house's own spawns); spawns and goal come from a generator seeded with ``s``
        (the one ``Env.reset(seed=s)`` seeds). Returns the number of houses tried."""
        self.episode_seed = seed = int(seed)
        return self._begin(*self._generators(seed))

    def _generators(self, seed: int) -> tuple[np.random.Generator, np.random.Generator, int]:
        """The episode's generator, its house's, and its index in the house (:meth:`play`)."""
        rng = np.random.default_rng(seed)
        block, index_in_house = divmod(seed, self.episodes_per_house)
        house_rng = rng
        if self.episodes_per_house > 1:
            house_rng = np.random.default_rng([block, self.episodes_per_house, HOUSE_STREAM])
        return rng, house_rng, index_in_house

    def next_seed(self, rng: np.random.Generator) -> int:
        """The seed of the next episode begun without one: the next seed of the current
        block while it has episodes left, else the first seed of a block drawn from ``rng``
        (one draw, whatever the episodes did)."""
        return self._following(self.episode_seed, rng)

    def upcoming(self, rng: np.random.Generator, count: int) -> list[int]:
        """The seeds of the next ``count`` episodes begun without a seed, if nothing else
        draws from ``rng`` in between (``rng`` is not moved: its bit generator's state is
        put back, a tenth of the cost of drawing from a deep copy)."""
        state = rng.bit_generator.state
        seeds: list[int] = []
        last = self.episode_seed
        try:
            for _ in range(count):
                last = self._following(last, rng)
                seeds.append(last)
        finally:
            rng.bit_generator.state = state
        return seeds

    def _following(self, last: int | None, rng: np.random.Generator) -> int:
        k = self.episodes_per_house
        if last is not None and last % k != k - 1:
            return last + 1
        return int(rng.integers(SEED_BLOCKS)) * k

    def _begin(self, rng: np.random.Generator, house_rng: np.random.Generator, index_in_house: int,
               scene: Scene | None = None) -> int:
        """A house (``scene``, else drawn from ``house_rng``), set up or restored, and a goal
        in it from ``rng``, drawing another house while one offers none."""
        failure = None
        previous = self.house
        for attempt in range(HOUSE_RETRIES):
            if scene is not None:
                house = self._build(HouseDraw(("given", id(scene)), None, lambda: (scene, None)), keep=False)
            else:
                try:
                    draw = self.houses.draw(house_rng, self.task)
                    house = self._kept_or_built(draw)
                except GenerationError as err:
                    # A task's condition this layout cannot meet (a kitchen counter asked of a
                    # bedroom): draw another house, unless the seed is fixed.
                    if self.houses.seed_fixed:
                        raise
                    failure = err
                    continue
                house.episodes = index_in_house if attempt == 0 else 0
            drawn_spawns = bool(house.episodes) or house.draw.spawns_drawn
            for agent, user in self._spawns(house, rng):
                ctx = self._enter(house, agent, user)
                self.goal = self.task.sample(ctx, rng)
                if self.goal is not None:
                    house.episodes += 1
                    if previous is not None and previous is not house and previous.draw.key not in self._kept:
                        previous = None  # the last reference to a house not kept: its memory is free
                        heap.trim(heap.TRIM_GROWTH)  # its pages go back to the system (legent_gym.utils.heap)
                    return attempt + 1
            if not drawn_spawns and (scene is not None or self.houses.house_fixed):
                raise ValueError(f"task {self.task.name} has no valid goal in house {house.scene.name!r}")
        raise RuntimeError(f"no house in {HOUSE_RETRIES} tries offered a {self.task.name} goal"
                           + (f" (the last generation failed: {failure})" if failure else ""))

    def _start_factory(self) -> EpisodeFactory | None:
        """The helpers, started on first use; None without helpers or where episodes are
        not the seed's alone (a fixed scene, a pool of seeds)."""
        if not self.helpers or self.houses.scene is not None or self.houses.house_pool:
            return None
        if self._factory is None:
            self._factory = EpisodeFactory(self, self.helpers)
        return self._factory

    def _held_keys(self) -> set[tuple]:
        """The keys of the houses this engine holds built."""
        held = set(self._kept)
        if self.house is not None:
            held.add(self.house.draw.key)
        return held

    def _adopt(self, prepared: PreparedEpisode, staged: _Staged | None = None) -> int | None:
        """Begin the episode a helper prepared (and :meth:`stage` set up, if ``staged``);
        None when its house is neither held here nor shipped (then the caller plays it)."""
        key = prepared.key
        if staged is not None and staged.ctx is not None:
            house = staged.house
            assert house is not None and staged.renderer is not None
            if house.draw.repeats or self.episodes_per_house > 1:
                self._keep(house)
            # The last house and its renderer are let go by the next stage(), not here.
            self._release_retired()
            self._retired = (self._renderer, self.house)
            self._renderer, self._renderer_world = staged.renderer, house.world
            self.house, self.ctx = house, staged.ctx
            self._first_views = staged.first_views
            self.episode_seed = prepared.seed
            self.goal = prepared.goal
            self.episodes_staged += 1
            return prepared.attempts
        house = self._kept.get(key)
        if house is not None:
            self._kept.move_to_end(key)
        elif self.house is not None and self.house.draw.key == key:
            house = self.house
        elif prepared.house is not None:
            assert self._factory is not None
            house = prepared.house.to_house(self._factory.library)
            if house.draw.repeats or self.episodes_per_house > 1:
                self._keep(house)
        else:
            return None
        self.episode_seed = prepared.seed
        house.episodes = prepared.episodes
        ctx = self._enter(house, prepared.agent, prepared.user)
        ctx.add_cached_distances(prepared.distances)
        self.goal = prepared.goal
        return prepared.attempts

    def _kept_or_built(self, draw: HouseDraw) -> House:
        house = self._kept.get(draw.key)
        if house is not None:
            self._kept.move_to_end(draw.key)
            return house
        # With several episodes per house, seeded resets of one block draw the same house again.
        keep = draw.repeats or self.episodes_per_house > 1
        ahead, self._ahead = self._ahead, None
        if ahead is not None and ahead.draw.key == draw.key:
            house = ahead.take()
            self.houses_taken_ahead += 1
            if keep:
                self._keep(house)
            return house
        return self._build(draw, keep=keep)

    def _make_next_ahead(self, rng: np.random.Generator) -> None:
        """Start making the house the next unseeded :meth:`begin` draws, if it begins a new
        block of seeds, draws a house that is not kept, and no other house is being made."""
        if self._ahead is not None:
            return
        _, house_rng, index = self._generators(self.upcoming(rng, 1)[0])
        if index:
            return
        draw = self.houses.peek(house_rng, self.task)
        if draw.key not in self._kept:
            self._ahead = HouseAhead(draw, self._make_house)

    def _make_house(self, draw: HouseDraw) -> House:
        with self._build_lock:
            store = self.house_store
            if store is not None:
                stored = store.load(draw, with_binary=self.keep_binaries)
                if stored is not None:
                    return stored
            scene, nav = draw.load()
            world = build_world(scene, self.build_options)
            if nav is None or nav.agent_radius != self.build_options.agent.radius:
                nav = NavGrid.from_scene(scene, agent_radius=self.build_options.agent.radius)
            seed = scene.seed if draw.spawns_drawn else draw.seed
            binary = None
            storing = store is not None and draw.recipe is not None
            if self.keep_binaries or storing:  # as built, before any episode touches the model
                binary = np.empty(mujoco.mj_sizeModel(world.model), np.uint8)
                mujoco.mj_saveModel(world.model, None, binary)
            house = House(draw, scene, world, nav, capture(world), seed,
                          binary=binary if self.keep_binaries else None)
            if storing:
                assert store is not None and binary is not None
                store.save(house, binary)
            return house

    def _build(self, draw: HouseDraw, keep: bool) -> House:
        house = self._make_house(draw)
        if keep:
            self._keep(house)
        return house

    def _keep(self, house: House) -> None:
        self._kept[house.draw.key] = house
        if len(self._kept) > self.houses_kept:
            self._kept.popitem(last=False)

    def _spawns(self, house: House, rng: np.random.Generator):
        """(agent, user) spawn pairs to try: the scene's for a house's first episode (unless
        its spawns are drawn), else up to :data:`SPAWN_RETRIES` new pairs drawn under the
        task's conditions."""
        scene = house.scene
        if not house.episodes and not house.draw.spawns_drawn:
            yield scene.agent, scene.user
            return
        conditions = self.task.house_conditions(house.draw.seed if house.draw.seed is not None else 0)
        min_distance = float(conditions.get("min_user_distance", HouseSpec.model_fields["min_user_distance"].default))
        if house.spawns is None:
            house.spawns = SpawnSampler(house.nav, house.nav.component(scene.agent.position))
        for _ in range(SPAWN_RETRIES):
            try:
                yield house.spawns.draw(rng, user=scene.user is not None, min_distance=min_distance)
            except AttemptFailed:
                return

    def _enter(self, house: House, agent: Spawn, user: Spawn | None) -> TaskContext:
        """Restore ``house`` as built and put the bodies at these spawns."""
        if self._renderer is not None and self._renderer_world is not house.world:
            self._close_renderer()
        ctx = self._placed(house, agent, user)
        self.house, self.ctx = house, ctx
        return ctx

    def _placed(self, house: House, agent: Spawn, user: Spawn | None) -> TaskContext:
        """``house`` restored as built with the bodies at these spawns, and its context (not
        made the current one)."""
        world = house.world
        restore(world, house.built)
        scene = house.scene
        if agent != scene.agent or user != scene.user:
            scene = scene.model_copy(update={"agent": agent, "user": user})
        world.set_body_pose("agent", *agent.position, agent.yaw)
        if user is not None:
            world.set_body_pose("user", *user.position, user.yaw)
        mujoco.mj_forward(world.model, world.data)
        return self._context(scene, world, house.nav)

    def set_up(self, scene: Scene, world: World | None = None, nav: NavGrid | None = None) -> TaskContext:
        """Build ``scene`` (or take its built ``world`` and ``nav``) and put the agent and the
        user at the scene's spawns (no goal yet)."""
        if world is None:
            self._close_renderer()
            with self._build_lock:
                world = build_world(scene, self.build_options)
        if nav is None:
            nav = NavGrid.from_scene(scene, agent_radius=self.build_options.agent.radius)
        self.ctx = self._context(scene, world, nav)
        return self.ctx

    def _context(self, scene: Scene, world: World, nav: NavGrid) -> TaskContext:
        agent = Body(world, "agent", reach=self.reach, other="user" if scene.user else None, spawn=scene.agent,
                     record_motion=self.record_motion)
        user = Body(world, "user", other="agent", spawn=scene.user or scene.agent, record_motion=self.record_motion)
        return TaskContext(scene, world, agent, user, nav)

    # -- 2. running primitives -------------------------------------------------------------------
    def run(self, primitives: tuple[Action, ...] | list[Action], body: Body | None = None) -> list[Outcome]:
        """Run a step's primitives in order by the agent (or ``body``), with one update of
        the world for its moves and turns (see :meth:`~legent_gym.agent.body.Body.batched`)."""
        ctx = self.require()
        self._first_views = None
        actor = ctx.agent if body is None else body
        with actor.batched():
            return [self.execute(p, body) for p in primitives]

    def execute(self, primitive: Action, body: Body | None = None) -> Outcome:
        """Run one primitive by the agent, or by ``body`` (the multi-agent env's user moves
        and interacts through here; it handles the user's speech and finish itself). The
        primitive is clipped to :attr:`limits` first; the outcome's reason says so."""
        ctx = self.require()
        self._first_views = None
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
        return self.require_goal().evaluate(self.require())

    def distance_left(self) -> float:
        """Geodesic metres to the current sub-goal (dearer than :meth:`judge`: a goal that
        moves costs a search of the house)."""
        return self.require_goal().distance_left(self.require())

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
            self._renderer_world = self.require().world
            self._renderer = Renderer(self._renderer_world, o.width, o.height, "fast")
        return self._renderer

    def views(self, who: str = "agent") -> dict[str, np.ndarray]:
        """What ``who`` (``"agent"`` or ``"user"``) sees: ``rgb``, and ``depth`` and
        ``segmentation`` when :attr:`observing` asks for them."""
        first, self._first_views = self._first_views, None
        if first is not None and who == "agent":
            return first
        return self._draw_views(self.renderer, who)

    def _draw_views(self, renderer: Renderer, who: str) -> dict[str, np.ndarray]:
        out = {"rgb": renderer.rgb(who)}
        if self.observing.depth:
            out["depth"] = renderer.depth(who)
        if self.observing.segmentation:
            out["segmentation"] = renderer.segmentation(who)
        return out

    def in_between(self, frames: int) -> Iterator[float]:
        """Pose the people as they were at each of the ``frames - 1`` moments between the
        last observation and now (the walk along the swept path, the reach), yielding the
        share of the step each shows; the world is put back as the step left it at the end,
        also when the caller stops early. Only the people and what they carry move: the
        rest of the world shows the step's outcome."""
        ctx = self.require()
        bodies = (ctx.agent, ctx.user)
        try:
            for i in range(1, frames):
                t = i / frames
                for body in bodies:
                    body.show_motion(t)
                yield t
        finally:
            for body in bodies:
                body.show_motion(1.0)

    def close(self) -> None:
        """Free the renderer (a new one is made for the next frame), wait for a house
        being made ahead (it is dropped) and stop the helper processes (started again by
        the next :meth:`begin`)."""
        self._close_renderer()
        self._release_retired()
        staged, self._staged, self._next_seed = self._staged, None, None
        if staged is not None:
            staged.drop()
        ahead, self._ahead = self._ahead, None
        if ahead is not None:
            ahead.wait()
        factory, self._factory = self._factory, None
        if factory is not None:
            factory.close()

    def _close_renderer(self) -> None:
        self._first_views = None
        if self._renderer is not None:
            self._renderer.close()
        self._renderer = self._renderer_world = None

    # Pickling: the house is set up again at the next begin().
    def __getstate__(self) -> dict[str, Any]:
        state = self.__dict__.copy()
        state.update(ctx=None, goal=None, house=None, _kept=OrderedDict(), _renderer=None, _renderer_world=None,
                     _ahead=None, _build_lock=None, _factory=None, _staged=None, _next_seed=None, _first_views=None, _retired=None)
        return state

    def __setstate__(self, state: dict[str, Any]) -> None:
        self.__dict__.update(state)
        self._build_lock = threading.Lock()

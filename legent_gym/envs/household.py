"""The household environments: an agent in a house, an instruction from the user, six tasks.

The Gymnasium side only: spaces, rewards, observation and info dictionaries. The house, the
bodies, the task and the views are the episode engine's (:mod:`legent_gym.envs.episode`).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from legent_gym.agent.actions import ActionLimits, ActionParseError, format_action
from legent_gym.agent.body import DEFAULT_REACH, Outcome
from legent_gym.envs.action_spaces import (
    continuous_action_space,
    parse_step,
    speech_space,
    text_action_space,
)
from legent_gym.envs.episode import HOUSE_CACHE_SIZE, Episode, Observing
from legent_gym.envs.house_store import HouseStore
from legent_gym.envs.houses import HouseSource
from legent_gym.envs.vector import settle_worker
from legent_gym.tasks import make_task
from legent_gym.tasks.base import Evaluation
from legent_gym.utils import gl_backend  # noqa: F401  (before mujoco)
from legent_gym.world.builder import PERSON_SEGMENTATION_ID, BodyOptions, BuildOptions, World
from legent_gym.world.render import FreeCamera, Renderer
from legent_gym.world.scene import Scene, load_scene

#: Camera presets: ``"default"`` (90 degrees vertical field of view, head at 1.5 m) and
#: ``"paper"`` (LEGENT's evaluation camera: 448 x 448 pixels, 120 degrees).
CAMERA_PRESETS = {
    "default": {"width": 96, "height": 96, "fovy": 90.0},
    "paper": {"width": 448, "height": 448, "fovy": 120.0},
}
#: The longest instruction or message an observation holds (characters).
MAX_TEXT = 500
#: ``info`` ids (``held``, ``house_seed``, the task's ``target`` and ``receptacle``) where there is none.
NO_ID = -1
#: ``info["distance_to_goal"]`` where nothing measures it (``distance_info=False``): a number,
#: as recorders of infos need, and not nan, which equals nothing (determinism checks compare infos).
NOT_MEASURED = -1.0


def info_values(values: dict[str, Any]) -> dict[str, Any]:
    """A task's description or evaluation as ``info`` holds it: one type per key in every
    episode (what Minari's recorder needs): -1 for an id the goal has not (None), a list
    of names (WhereIs's ``answers``) as one string joined by "|"."""
    return {k: NO_ID if v is None else "|".join(v) if isinstance(v, list | tuple) else v for k, v in values.items()}


def action_info(texts: list[str], results: list[Outcome], error: str) -> dict[str, Any]:
    """The ``info`` fields of a step's primitives (``texts``, their ``results``) or of an
    action that did not parse (``error``); with nothing given, those of a reset."""
    return {
        "action_text": ", ".join(texts),
        "action_ok": not error and all(r.ok for r in results),
        "action_results": "; ".join(f"{t}: {'ok' if r.ok else 'failed'}" + (f" ({r.reason})" if r.reason else "")
                                    for t, r in zip(texts, results)),
        "action_error": error,
    }


class HouseholdEnv(gym.Env):
    """## Description
    An embodied agent in a house, as in LEGENT: it sees through a camera on its head, hears
    an instruction from a user who stands in the same house, and acts with the paper's
    actions: speak, move forward a continuous distance, rotate by continuous degrees, and
    interact with what is at the centre of its view (grab, put, open, close). Each reset
    draws a new procedurally generated house (or the house you fix) and a new goal.

    The task is chosen with ``task``, the name of a registered task
    (:data:`legent_gym.tasks.TASKS`): ``ComeHere`` (go to the user), ``GoTo`` (go to an
    object), ``PickUp`` (hold an object), ``BringMe`` (hold an object near the user),
    ``WhereIs`` (say what the object lies on), ``PutOn`` (put an object on a receptacle).
    Instructions come from paraphrase templates ("Bring me the apple.").

    ## Action Space
    ``action_type="text"`` (default): a ``Text`` space holding LEGENT's action code, one or
    more primitives joined by ", ": ``speak("It's on the sofa.")``, ``move_forward(1.2)``
    (metres, at most 2), ``rotate_right(-35)`` (degrees, at most 90 either way; negative
    turns left), ``rotate_down(10)`` (pitch, clamped to [-60, 60] degrees), ``interact()``,
    ``grab()``, ``put()``, ``open()``, ``close()`` (also addressed: ``grab(12)``,
    ``open("inner")``), ``release()`` (= ``put()``), ``finish()``. Primitives run in order.
    An action that does not parse is a no-op step with ``info["action_error"]`` saying what
    is wrong (``strict=True`` raises instead). See ``docs/actions.md``.

    ``action_type="continuous"``: a ``Dict`` with ``move_forward`` Box(0, 2),
    ``rotate_right`` Box(-90, 90), ``rotate_down`` Box(-90, 90), ``interact`` Discrete(6)
    (none, interact, grab, put, open, close), ``speak`` Text (empty: silent) and ``finish``
    Discrete(2), executed in that order. It converts losslessly to and from text.

    ## Observation Space
    A ``Dict``: ``rgb`` Box(0, 255, (H, W, 3), uint8), the egocentric view; ``instruction``
    Text, the user's instruction; ``message`` Text, the user's latest words (the instruction
    at reset). With ``depth=True``: ``depth`` Box((H, W), float32) metres; with
    ``segmentation=True``: ``segmentation`` Box((H, W), int32) scene object ids; the user's
    pixels -2, the agent's own hands -3; -1 elsewhere.

    Privileged state is in ``info`` (for rewards, experts and analysis, not for policies;
    the whole episode, for experts and servers, is ``env.unwrapped.episode``, an
    :class:`~legent_gym.envs.episode.Episode`). It has the same keys at reset and after
    every step, and each key one type in every episode of an env (no None), so Minari's
    ``DataCollector(env, record_infos=True)`` records it (``docs/datasets.md``):

    * ``agent_pose``, ``user_pose``: (x, y, yaw, pitch); ``held``: the agent's object id
      (-1: nothing);
    * ``task``: ``name``, the goal's ``target`` and ``receptacle`` object ids (-1 where the
      task has none) and ``answers``, the names WhereIs's success accepts joined by "|" (""
      for the other tasks): the same keys for every task, so ``Legent/Custom-v0`` too;
    * ``success``; ``distance_to_goal``: geodesic metres to the current sub-goal (-1 with
      ``distance_info=False``); ``distance_to_user``: horizontal metres from the agent to
      the user (ComeHere's success: under 2);
    * ``action_text``: the step as action code; ``action_ok``: it parsed and every
      primitive succeeded; ``action_results``: one ``code: ok`` or ``code: failed
      (reason)`` per primitive, joined by "; "; ``action_error``: why it did not parse,
      else "" (at reset: "", True, "", "");
    * ``attempts``: spawn draws the reset needed; ``house_seed`` (-1: a scene given as it
      is), ``scene_name``, ``n_actions``;
    * with ``frames_per_step`` F > 1, ``frames``: (F - 1, H, W, 3) uint8 (see Arguments;
      at reset F - 1 copies of the first view).

    ## Rewards
    ``reward="sparse"`` (default): 1 on success, else 0. ``reward="dense"``: the decrease of
    the geodesic distance to the current sub-goal each step, -0.01 per step, and +10 on
    success.

    ## Starting State
    The agent and user stand at the house's spawns (at least 3 m apart for ComeHere, as in
    LEGENT's evaluation), the agent looking level. Each reset draws a new house unless
    ``episodes_per_house`` > 1 keeps one for several episodes (later ones at new spawns)
    or the house is fixed; a kept house starts every episode as built: small objects where
    the house has them, doors and drawers as built, nothing held. A reset with a seed
    draws the house of its block of ``episodes_per_house`` seeds (seeds ``s`` with the same
    ``s // K`` share one house, a kept one if it was built before), so each episode depends
    on its seed and ``K`` alone; resets without a seed go on in the current house.

    ## Episode End
    Terminates on success, on ``finish()``, and (WhereIs) on any speech. Truncates after
    ``max_episode_steps`` actions (25 by default, the paper's evaluation cap).

    ## Arguments
    * ``task``: a registered task (ComeHere, GoTo, PickUp, BringMe, WhereIs, PutOn, ...); or
      Custom (``Legent/Custom-v0``).
    * ``tasks``: for Custom, a tasks file of the house given as ``scene`` (``legent-gym tasks generate``).
    * ``layout``: the generation preset of new houses: OneRoom, TwoRoom, FourRoom or
      Apartment.
    * ``action_type``: ``"text"`` (default) or ``"continuous"``.
    * ``width``, ``height``: observation size in pixels (default: the camera preset's).
    * ``fovy``: the head camera's vertical field of view in degrees (default: the preset's).
    * ``camera``: ``"default"`` (96 x 96, 90 degrees) or ``"paper"`` (448 x 448, 120 degrees).
    * ``reward``: ``"sparse"`` (default) or ``"dense"``.
    * ``scene``: a scene JSON path or a ``Scene``: every episode in this house.
    * ``house_seed``: every episode in the house of this generation seed.
    * ``house_pool``: a list of generation seeds, cycled through episode by episode.
    * ``houses``: a folder of scene files (``legent-gym generate --count N --out-dir DIR``),
      one drawn at random for each new house; each episode in one draws its spawns.
    * ``episodes_per_house``: consecutive episodes in one built house (default 1: a new
      house every episode); later ones draw new spawns and a new goal, with the house
      restored as built (see :mod:`legent_gym.envs.episode`).
    * ``houses_kept``: the most built houses kept for reuse (default 8; a few megabytes
      each): a ``houses`` folder of N houses with ``houses_kept`` >= N builds each once.
    * ``house_cache``: a folder where the houses of ``houses``, ``house_seed`` and
      ``house_pool`` are stored once built (about 2 MB each), for every process and run
      that uses the same folder to load instead of building them (default None: not
      stored; see :mod:`legent_gym.envs.house_store`).
    * ``pin_worker``: in a vector env's worker process, pin it to one core and render in one
      thread (default True; see :mod:`legent_gym.envs.vector`).
    * ``prepare_ahead``: make the next house in a background thread at the lowest CPU
      priority, in time the process would spend waiting (same episodes; see
      :mod:`legent_gym.envs.episode`). Default None: on in a vector env's pinned worker
      process, where the lock-step of the vector env leaves such time, off elsewhere
      (and off with ``helpers``).
    * ``helpers``: child processes that prepare the coming episodes (house, spawns, goal)
      while this env steps, so that a reset only loads one (default 0: none; the same
      episodes either way; stopped by ``close()``; not used with ``scene`` or
      ``house_pool``; see :mod:`legent_gym.envs.factory`). An episode of a new house costs
      a helper more CPU than the env spends stepping through it (generation and compile),
      so give one or two per env where cores are free.
    * ``depth``, ``segmentation``: add these images to the observation.
    * ``strict``: raise on an invalid action instead of a no-op step.
    * ``reach``: interaction distance in metres (1.5).
    * ``agent_radius``, ``agent_height``, ``camera_height``: the agent's body (metres).
    * ``distance_info``: ``info["distance_to_goal"]`` every step (default True; the dense
      reward computes it anyway).
    * ``render_mode``: ``"rgb_array"`` (a third-person view over the agent),
      ``"rgb_array_list"`` (the same view at every frame since the last ``render()``:
      ``frames_per_step`` of them a step) or ``"depth_array"``.
    * ``render_size``: the ``render()`` image's side in pixels (256).
    * ``frames_per_step``: frames a step is shown in (default 1). With F > 1 each step also
      poses the people at the F - 1 moments between the last observation and this one (the
      walk cycle along the swept path, the reach, the handover) and returns those views of
      the agent's camera in ``info["frames"]`` (RGB, the observation's size; one step is
      still one observation); ``render_mode="rgb_array_list"`` collects the third-person
      view of each, and ``legent-gym collect --format video`` puts them in the video.
    * ``user_moves``: whether the user moves its limbs (default False: here the user stands
      still, and is drawn as one mesh in its idle pose, the same picture for less rendering;
      the PettingZoo envs, where the user acts, set it).
    * ``task_options``: the task's own arguments: WhereIs takes ``objects`` and
      ``receptacles``, the categories it asks about (``legent_gym.tasks.PAPER_WHERE_IS``
      is LEGENT's four objects on its five receptacle kinds); Custom takes ``order``,
      ``"random"`` (default: a task drawn per episode) or ``"sequential"``.

    ## Version History
    * v0: initial release; ``task_options``, ``houses``, ``episodes_per_house`` and
      ``tasks`` (``Legent/Custom-v0``) added later without changing any default episode.
    """

    metadata = {"render_modes": ["rgb_array", "rgb_array_list", "depth_array"], "render_fps": 4}

    def __init__(self, task: str = "ComeHere", layout: str = "OneRoom", action_type: str = "text", *,
                 width: int | None = None, height: int | None = None, fovy: float | None = None,
                 camera: str = "default", reward: str = "sparse", scene: str | Path | Scene | None = None,
                 house_seed: int | None = None, house_pool: list[int] | None = None, depth: bool = False,
                 segmentation: bool = False, strict: bool = False, reach: float = DEFAULT_REACH,
                 agent_radius: float = 0.25, agent_height: float = 1.6, camera_height: float = 1.5,
                 distance_info: bool = True, render_mode: str | None = None, render_size: int = 256,
                 task_options: dict[str, Any] | None = None, houses: str | Path | None = None,
                 episodes_per_house: int = 1, houses_kept: int = HOUSE_CACHE_SIZE, pin_worker: bool = True,
                 prepare_ahead: bool | None = None, helpers: int = 0, tasks: str | Path | list | None = None,
                 frames_per_step: int = 1, user_moves: bool = False, house_cache: str | Path | None = None):
        if camera not in CAMERA_PRESETS:
            raise ValueError(f"unknown camera preset {camera!r}; known: {', '.join(CAMERA_PRESETS)}")
        if action_type not in ("text", "continuous"):
            raise ValueError(f"action_type must be 'text' or 'continuous', got {action_type!r}")
        if reward not in ("sparse", "dense"):
            raise ValueError(f"reward must be 'sparse' or 'dense', got {reward!r}")
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise ValueError(f"render_mode must be one of {self.metadata['render_modes']}, got {render_mode!r}")
        if not isinstance(frames_per_step, int) or isinstance(frames_per_step, bool) or frames_per_step < 1:
            raise ValueError(f"frames_per_step must be a positive integer, got {frames_per_step!r}")
        self.frames_per_step = frames_per_step
        #: The core this env's process was pinned to as a vector env's worker (None: not pinned).
        self.worker_core = settle_worker() if pin_worker else None
        preset = CAMERA_PRESETS[camera]
        self.width = int(width or preset["width"])
        self.height = int(height or preset["height"])
        self.task_name, self.layout, self.action_type = task, layout, action_type
        self.reward_type, self.strict = reward, strict
        # The geodesic to the goal is measured only when something reads it.
        self.measure_distance = bool(distance_info) or reward == "dense"
        self.render_mode, self.render_size = render_mode, render_size
        build_options = BuildOptions(agent=BodyOptions(agent_radius, agent_height, camera_height,
                                                       float(fovy or preset["fovy"])),
                                     user_articulated=bool(user_moves))
        source = HouseSource(layout, scene=load_scene(scene) if isinstance(scene, str | Path) else scene,
                             house_seed=house_seed, house_pool=house_pool, houses=houses)
        #: The episode engine: house, bodies, goal, views (see :mod:`legent_gym.envs.episode`).
        if task == "Custom" and scene is None:
            raise ValueError("the Custom task plays tasks written for one house: give scene= (its scene file)")
        if tasks is not None:
            task_options = {**(task_options or {}), "tasks": tasks}
        self.episode = Episode(make_task(task, **(task_options or {})), source, build_options,
                               Observing(self.width, self.height, depth, segmentation), reach=reach,
                               limits=ActionLimits(), episodes_per_house=episodes_per_house,
                               houses_kept=houses_kept, helpers=helpers,
                               house_store=None if house_cache is None else HouseStore(house_cache, build_options),
                               prepare_ahead=(self.worker_core is not None and not helpers) if prepare_ahead is None
                               else prepare_ahead)

        self.episode.record_motion = frames_per_step > 1
        self.action_space = text_action_space() if action_type == "text" else continuous_action_space(
            self.episode.limits)
        obs = {
            "rgb": spaces.Box(0, 255, (self.height, self.width, 3), np.uint8),
            "instruction": speech_space(MAX_TEXT),
            "message": speech_space(MAX_TEXT),
        }
        if depth:
            obs["depth"] = spaces.Box(0.0, np.inf, (self.height, self.width), np.float32)
        if segmentation:
            obs["segmentation"] = spaces.Box(min(PERSON_SEGMENTATION_ID.values()), np.iinfo(np.int32).max,
                                                 (self.height, self.width), np.int32)
        self.observation_space = spaces.Dict(obs)

        self._n_actions = 0
        self._attempts = 0
        self._last_distance: float | None = None
        self._message = ""
        # The third-person view of render(), made on its first frame, for one world.
        self._view_renderer: Renderer | None = None
        self._view_world: World | None = None
        #: render_mode "rgb_array_list": the views of the moments within steps since the last render().
        self._frames_since_render: list[np.ndarray] = []
        #: With helpers, whether step() does a piece of the next episode's set-up
        #: (Episode.stage); our vector env's workers call stage_ahead() while they wait instead.
        self.stage_after_step = True

    # -- Gymnasium API -----------------------------------------------------------------------
    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None):
        """Start an episode. ``options``: ``{"scene": path or Scene}`` plays this house once."""
        super().reset(seed=seed)
        options = options or {}
        scene = options.get("scene")
        if scene is not None and not isinstance(scene, Scene):
            scene = load_scene(scene)
        # The same seed, the same episode, whatever came before (see Episode.begin).
        self._attempts = self.episode.begin(self.np_random, scene, seed=seed)
        self._n_actions = 0
        self._frames_since_render = []
        evaluation = self.episode.judge()
        self._last_distance = distance = self.distance_left()
        self._message = self.episode.require_goal().instruction
        info = self._info(evaluation, distance)
        obs = self._observation()
        if self.frames_per_step > 1:  # the agent stood still before its first observation
            info["frames"] = np.stack([obs["rgb"]] * (self.frames_per_step - 1))
        return obs, info

    def step(self, action):
        if self.episode.ctx is None:
            raise RuntimeError("call reset() before step()")
        error = ""
        try:
            primitives = parse_step(action, self.action_type)
        except (ActionParseError, ValueError) as err:
            if self.strict:
                raise
            primitives = ()
            error = str(err)
        self._n_actions += 1
        results = self.episode.run(primitives)
        evaluation = self.episode.judge()
        terminated = evaluation.success or evaluation.ends or self.episode.ended
        distance = self.distance_left()
        reward = self._reward(evaluation, distance)
        info = self._info(evaluation, distance)
        texts = [format_action(p) for p in primitives]  # each primitive printed once
        info.update(action_info(texts, results, error))
        if self.frames_per_step > 1:
            info["frames"] = np.stack(self._frames_within_step())
        obs = self._observation()
        if self.stage_after_step:  # a piece of the next episode's set-up, now that this step's frame is drawn
            self.episode.stage()
        return obs, reward, bool(terminated), False, info

    def _frames_within_step(self) -> list[np.ndarray]:
        """The agent's views at the moments between the last observation and this one (and,
        with render_mode "rgb_array_list", the third-person views of them)."""
        views = []
        for _ in self.episode.in_between(self.frames_per_step):
            views.append(self.episode.views("agent")["rgb"])
            if self.render_mode == "rgb_array_list":
                self._frames_since_render.append(self._third_person())
        return views

    def stage_ahead(self) -> bool:
        """One piece of the next episode's set-up (:meth:`Episode.stage`); False if none is
        to be done now."""
        return self.episode.stage()

    def distance_left(self) -> float | None:
        """Geodesic metres to the current sub-goal, or None when nothing measures it."""
        return self.episode.distance_left() if self.measure_distance else None

    def _reward(self, evaluation: Evaluation, distance: float | None) -> float:
        if self.reward_type == "sparse":
            return 1.0 if evaluation.success else 0.0
        progress = 0.0
        if distance is not None and self._last_distance is not None and \
                np.isfinite(distance) and np.isfinite(self._last_distance):
            progress = self._last_distance - distance
        self._last_distance = distance
        return float(progress - 0.01 + (10.0 if evaluation.success else 0.0))

    # -- observations and info ----------------------------------------------------------------
    def _observation(self) -> dict[str, Any]:
        views = self.episode.views("agent")
        obs = {"rgb": views.pop("rgb"), "instruction": self.episode.require_goal().instruction, "message": self._message}
        obs.update(views)
        return obs

    def _info(self, evaluation: Evaluation, distance: float | None) -> dict[str, Any]:
        ctx = self.episode.require()
        a, u = ctx.agent.state, ctx.user.state
        house_seed = self.episode.house_seed
        return {
            "agent_pose": (a.x, a.y, a.yaw, a.pitch),
            "user_pose": (u.x, u.y, u.yaw, u.pitch),
            "held": NO_ID if a.held is None else a.held,
            "task": {"name": self.task_name, **info_values(self.episode.require_goal().describe())},
            "success": bool(evaluation.success),
            "distance_to_goal": NOT_MEASURED if distance is None else float(distance),
            "house_seed": NO_ID if house_seed is None else house_seed,
            "scene_name": ctx.scene.name,
            "n_actions": self._n_actions,
            "attempts": self._attempts,
            "distance_to_user": float(ctx.agent.horizontal_distance(ctx.user.xy)),
            **action_info([], [], ""),
            **info_values(evaluation.info),
        }

    def render(self):
        world = self.episode.world
        if self.render_mode is None or world is None:
            return None
        if self.render_mode == "rgb_array_list":
            frames, self._frames_since_render = self._frames_since_render, []
            return [*frames, self._third_person()]
        return self._third_person(depth=self.render_mode == "depth_array")

    def _third_person(self, depth: bool = False) -> np.ndarray:
        world = self.episode.require().world
        renderer = self._view_renderer
        if renderer is None or self._view_world is not world:  # a new house since the last frame
            self._close_view()
            renderer = self._view_renderer = Renderer(world, self.render_size, self.render_size, "fast")
            self._view_world = world
        a = self.episode.require().agent.state
        camera = FreeCamera((a.x, a.y, 0.8), 4.0, azimuth=a.yaw + 180.0, elevation=-50.0)
        return renderer.depth(camera) if depth else renderer.rgb(camera)

    def _close_view(self) -> None:
        if self._view_renderer is not None:
            self._view_renderer.close()
        self._view_renderer = self._view_world = None

    def close(self):
        self._close_view()
        self.episode.close()

    # Pickling: the world and renderers are made again at the next reset.
    def __getstate__(self):
        state = self.__dict__.copy()
        state.update(_view_renderer=None, _view_world=None)
        return state

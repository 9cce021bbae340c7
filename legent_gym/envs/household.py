"""The household environments: an agent in a house, an instruction from the user, six tasks."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from legent_gym import gl_backend  # noqa: F401  (before mujoco)
from legent_gym.agent.actions import (
    ActionLimits,
    ActionParseError,
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
    format_action,
    parse_actions,
)
from legent_gym.agent.body import DEFAULT_REACH, Body, Outcome
from legent_gym.envs.action_spaces import (
    continuous_action_space,
    dict_to_actions,
    speech_space,
    text_action_space,
)
from legent_gym.tasks.base import TaskContext, TaskInstance
from legent_gym.tasks.household import make_task
from legent_gym.world.builder import BodyOptions, BuildOptions, build_world
from legent_gym.world.generation import GenerationError, generate_house
from legent_gym.world.navigation import NavGrid
from legent_gym.world.render import Renderer
from legent_gym.world.scene import Scene, load_scene

#: Camera presets: ``"default"`` (90 degrees vertical field of view, head at 1.5 m) and
#: ``"paper"`` (LEGENT's evaluation camera: 448 x 448 pixels, 120 degrees).
CAMERA_PRESETS = {
    "default": {"width": 96, "height": 96, "fovy": 90.0},
    "paper": {"width": 448, "height": 448, "fovy": 120.0},
}
MAX_TEXT = 500
HOUSE_RETRIES = 20
#: The body method behind each interaction primitive (each takes an optional target).
_BODY_METHOD = {Interact: "interact", Grab: "grab", Put: "put", Open: "open", Close: "close"}


class HouseholdEnv(gym.Env):
    """## Description
    An embodied agent in a house, as in LEGENT: it sees through a camera on its head, hears
    an instruction from a user who stands in the same house, and acts with the paper's
    actions: speak, move forward a continuous distance, rotate by continuous degrees, and
    interact with what is at the centre of its view (grab, put, open, close). Each reset
    draws a new procedurally generated house (or the house you fix) and a new goal.

    The task is chosen with ``task``: ``ComeHere`` (go to the user), ``GoTo`` (go to an
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
    ``segmentation=True``: ``segmentation`` Box((H, W), int32) scene object ids, -1 elsewhere.

    Privileged state is in ``info`` (for rewards, experts and analysis, not for policies):
    ``agent_pose`` (x, y, yaw, pitch), ``user_pose``, ``held`` (object id or None),
    ``task`` (goal ids), ``success``, ``distance_to_goal`` (geodesic metres to the current
    sub-goal; None with ``distance_info=False``), ``action_text`` (the step as action code),
    ``action_results`` (one entry per primitive: ``ok`` and ``reason``), ``action_error`` (only on unparsable actions),
    ``house_seed``, ``scene_name``, ``n_actions``.

    ## Rewards
    ``reward="sparse"`` (default): 1 on success, else 0. ``reward="dense"``: the decrease of
    the geodesic distance to the current sub-goal each step, -0.01 per step, and +10 on
    success.

    ## Starting State
    The agent and user stand at the house's spawns (at least 3 m apart for ComeHere, as in
    LEGENT's evaluation), the agent looking level.

    ## Episode End
    Terminates on success, on ``finish()``, and (WhereIs) on any speech. Truncates after
    ``max_episode_steps`` actions (25 by default, the paper's evaluation cap).

    ## Arguments
    ``task`` (ComeHere, GoTo, PickUp, BringMe, WhereIs, PutOn); ``layout`` (a generation
    preset: OneRoom, TwoRoom, FourRoom, Apartment); ``action_type`` ("text" or
    "continuous"); ``width``, ``height``, ``fovy``, ``camera`` ("default" or "paper");
    ``reward`` ("sparse" or "dense"); ``scene`` (a scene JSON path or a Scene: always this
    house); ``house_seed`` (always the house of this seed); ``house_pool`` (a list of seeds
    cycled through); ``depth``, ``segmentation`` (extra observations); ``strict``
    (raise on invalid actions); ``reach`` (interaction distance, 1.5 m);
    ``agent_radius``, ``agent_height``, ``camera_height`` (the body); ``distance_info``
    (``info["distance_to_goal"]`` every step, default True; the dense reward computes it
    anyway); ``render_mode``
    ("rgb_array": a 256 px third-person view over the agent, or "depth_array");
    ``task_options`` (the task's own arguments: WhereIs takes ``objects`` and
    ``receptacles``, the categories it asks about; ``legent_gym.tasks.PAPER_WHERE_IS`` is
    LEGENT's four objects on its five receptacle kinds).

    ## Version History
    * v0: initial release; ``task_options`` added later without changing any default episode.
    """

    metadata = {"render_modes": ["rgb_array", "depth_array"], "render_fps": 4}

    def __init__(self, task: str = "ComeHere", layout: str = "OneRoom", action_type: str = "text", *,
                 width: int | None = None, height: int | None = None, fovy: float | None = None,
                 camera: str = "default", reward: str = "sparse", scene: str | Path | Scene | None = None,
                 house_seed: int | None = None, house_pool: list[int] | None = None, depth: bool = False,
                 segmentation: bool = False, strict: bool = False, reach: float = DEFAULT_REACH,
                 agent_radius: float = 0.25, agent_height: float = 1.6, camera_height: float = 1.5,
                 distance_info: bool = True, render_mode: str | None = None, render_size: int = 256,
                 task_options: dict[str, Any] | None = None):
        if camera not in CAMERA_PRESETS:
            raise ValueError(f"unknown camera preset {camera!r}; known: {', '.join(CAMERA_PRESETS)}")
        if action_type not in ("text", "continuous"):
            raise ValueError(f"action_type must be 'text' or 'continuous', got {action_type!r}")
        if reward not in ("sparse", "dense"):
            raise ValueError(f"reward must be 'sparse' or 'dense', got {reward!r}")
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise ValueError(f"render_mode must be one of {self.metadata['render_modes']}, got {render_mode!r}")
        preset = CAMERA_PRESETS[camera]
        self.width = int(width or preset["width"])
        self.height = int(height or preset["height"])
        self.task_name, self.layout, self.action_type = task, layout, action_type
        self.task = make_task(task, **(task_options or {}))
        self.reward_type, self.strict, self.reach = reward, strict, reach
        # The geodesic to the goal is measured only when something reads it.
        self.measure_distance = bool(distance_info) or reward == "dense"
        self.render_mode, self.render_size = render_mode, render_size
        self.limits = ActionLimits()
        self.observe_depth, self.observe_segmentation = depth, segmentation
        self.build_options = BuildOptions(agent=BodyOptions(agent_radius, agent_height, camera_height,
                                                            float(fovy or preset["fovy"])))
        self._fixed_scene = load_scene(scene) if isinstance(scene, str | Path) else scene
        self.house_seed, self.house_pool = house_seed, list(house_pool) if house_pool else None
        self._pool_index = 0

        self.action_space = text_action_space() if action_type == "text" else continuous_action_space(self.limits)
        obs = {
            "rgb": spaces.Box(0, 255, (self.height, self.width, 3), np.uint8),
            "instruction": speech_space(MAX_TEXT),
            "message": speech_space(MAX_TEXT),
        }
        if depth:
            obs["depth"] = spaces.Box(0.0, np.inf, (self.height, self.width), np.float32)
        if segmentation:
            obs["segmentation"] = spaces.Box(-1, np.iinfo(np.int32).max, (self.height, self.width), np.int32)
        self.observation_space = spaces.Dict(obs)

        # Made at reset; the renderer only on the first frame (no OpenGL before a fork).
        self.world = None
        self.ctx: TaskContext | None = None
        self.goal: TaskInstance | None = None
        self._renderer: Renderer | None = None
        self._view_renderer: Renderer | None = None
        self._n_actions = 0
        self._last_distance: float | None = None
        self._house_seed_used: int | None = None

    # -- houses ----------------------------------------------------------------------------
    def _next_house(self, rng: np.random.Generator) -> tuple[Scene, int | None]:
        if self._fixed_scene is not None:
            return self._fixed_scene, None
        if self.house_pool:
            seed = self.house_pool[self._pool_index % len(self.house_pool)]
            self._pool_index += 1
        elif self.house_seed is not None:
            seed = self.house_seed
        else:
            seed = int(rng.integers(2**31 - 1))
        return generate_house(seed, self.layout, **self.task.house_conditions(seed)), seed

    def _set_up(self, scene: Scene) -> None:
        if self._renderer is not None:
            self._renderer.close()
            self._renderer = None
        if self._view_renderer is not None:
            self._view_renderer.close()
            self._view_renderer = None
        self.world = build_world(scene, self.build_options)
        agent = Body(self.world, "agent", reach=self.reach, other="user" if scene.user else None)
        user = Body(self.world, "user", other="agent")
        nav = NavGrid.from_scene(scene, agent_radius=self.build_options.agent.radius)
        self.ctx = TaskContext(scene, self.world, agent, user, nav)

    # -- Gymnasium API -----------------------------------------------------------------------
    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None):
        super().reset(seed=seed)
        options = options or {}
        rng = self.np_random
        failure = None
        for attempt in range(HOUSE_RETRIES):
            tries = attempt + 1
            if "scene" in options:
                scene = options["scene"] if isinstance(options["scene"], Scene) else load_scene(options["scene"])
                house_seed = None
            else:
                try:
                    scene, house_seed = self._next_house(rng)
                except GenerationError as err:
                    # A task's condition this layout cannot meet (a kitchen counter asked of a
                    # bedroom): draw another house, unless the house is fixed.
                    if self.house_seed is not None or self.house_pool:
                        raise
                    failure = err
                    continue
            self._set_up(scene)
            self.goal = self.task.sample(self.ctx, rng)
            if self.goal is not None:
                break
            if self._fixed_scene is not None or "scene" in options or (self.house_seed is not None and not self.house_pool):
                raise ValueError(f"task {self.task_name} has no valid goal in house {scene.name!r}")
        else:
            raise RuntimeError(f"no house in {HOUSE_RETRIES} tries offered a {self.task_name} goal"
                               + (f" (the last generation failed: {failure})" if failure else ""))
        self._house_seed_used = house_seed
        self._n_actions = 0
        evaluation = self.goal.evaluate(self.ctx)
        self._last_distance = distance = self.distance_left()
        self._message = self.goal.instruction
        info = self._info(evaluation, distance)
        info["attempts"] = tries
        return self._observation(), info

    def step(self, action):
        if self.ctx is None:
            raise RuntimeError("call reset() before step()")
        info_extra: dict[str, Any] = {}
        try:
            primitives = self._to_primitives(action)
        except (ActionParseError, ValueError) as err:
            if self.strict:
                raise
            primitives = ()
            info_extra["action_error"] = str(err)
        self._n_actions += 1
        with self.ctx.agent.batched():  # one world update for the step's moves and turns
            results = [self._execute(p) for p in primitives]
        evaluation = self.goal.evaluate(self.ctx)
        terminated = evaluation.success or evaluation.ends or self.ctx.finished
        distance = self.distance_left()
        reward = self._reward(evaluation, distance)
        info = self._info(evaluation, distance)
        info.update(info_extra)
        texts = [format_action(p) for p in primitives]  # each primitive printed once
        info["action_text"] = ", ".join(texts)
        info["action_results"] = [{"action": t, "ok": r.ok, "reason": r.reason} for t, r in zip(texts, results)]
        return self._observation(), reward, bool(terminated), False, info

    def _to_primitives(self, action) -> tuple:
        if self.action_type == "text":
            if not isinstance(action, str):
                raise ActionParseError(str(action), 0, f"expected action code as a string, got {type(action).__name__}")
            return parse_actions(action)
        if isinstance(action, str):
            return parse_actions(action)
        return dict_to_actions(action)

    def _execute(self, primitive, body: Body | None = None) -> Outcome:
        """Run one primitive by the agent, or by ``body`` (the multi-agent env's user moves
        and interacts through here; it handles the user's speech and finish itself)."""
        primitive, note = clip_action(primitive, self.limits)
        agent = self.ctx.agent if body is None else body
        match primitive:
            case MoveForward(distance=d):
                outcome = agent.move_forward(d)
            case RotateRight(degrees=d):
                outcome = agent.rotate_right(d)
            case RotateDown(degrees=d):
                outcome = agent.rotate_down(d)
            case Speak(text=text):
                self.ctx.speech.append(text)
                outcome = Outcome(True)
            case Finish():
                self.ctx.finished = True
                outcome = Outcome(True)
            case Interact() | Grab() | Put() | Open() | Close():
                outcome = getattr(agent, _BODY_METHOD[type(primitive)])(primitive.target)
            case _:
                outcome = Outcome(False, f"unsupported action {primitive!r}")
        if note:
            outcome.reason = f"{note}; {outcome.reason}" if outcome.reason else note
        return outcome

    def distance_left(self) -> float | None:
        """Geodesic metres to the current sub-goal, or None when nothing measures it."""
        return self.goal.distance_left(self.ctx) if self.measure_distance else None

    def _reward(self, evaluation, distance: float | None) -> float:
        if self.reward_type == "sparse":
            return 1.0 if evaluation.success else 0.0
        progress = 0.0
        if distance is not None and self._last_distance is not None and \
                np.isfinite(distance) and np.isfinite(self._last_distance):
            progress = self._last_distance - distance
        self._last_distance = distance
        return float(progress - 0.01 + (10.0 if evaluation.success else 0.0))

    # -- observations and info ----------------------------------------------------------------
    def _ensure_renderer(self) -> Renderer:
        if self._renderer is None:
            self._renderer = Renderer(self.world, self.width, self.height, "fast")
        return self._renderer

    def _observation(self) -> dict[str, Any]:
        renderer = self._ensure_renderer()
        obs = {"rgb": renderer.rgb("agent"), "instruction": self.goal.instruction, "message": self._message}
        if self.observe_depth:
            obs["depth"] = renderer.depth("agent")
        if self.observe_segmentation:
            obs["segmentation"] = renderer.segmentation("agent")
        return obs

    def _info(self, evaluation, distance: float | None) -> dict[str, Any]:
        a, u = self.ctx.agent.state, self.ctx.user.state
        return {
            "agent_pose": (a.x, a.y, a.yaw, a.pitch),
            "user_pose": (u.x, u.y, u.yaw, u.pitch),
            "held": a.held,
            "task": {"name": self.task_name, **self.goal.describe()},
            "success": bool(evaluation.success),
            "distance_to_goal": distance,
            "house_seed": self._house_seed_used,
            "scene_name": self.ctx.scene.name,
            "n_actions": self._n_actions,
            **evaluation.info,
        }

    def render(self):
        if self.render_mode is None or self.world is None:
            return None
        from legent_gym.world.render import FreeCamera

        if self._view_renderer is None:
            self._view_renderer = Renderer(self.world, self.render_size, self.render_size, "fast")
        a = self.ctx.agent.state
        camera = FreeCamera((a.x, a.y, 0.8), 4.0, azimuth=a.yaw + 180.0, elevation=-50.0)
        if self.render_mode == "depth_array":
            return self._view_renderer.depth(camera)
        return self._view_renderer.rgb(camera)

    def close(self):
        for r in (self._renderer, self._view_renderer):
            if r is not None:
                r.close()
        self._renderer = self._view_renderer = None

    # Pickling: the world and renderers are rebuilt at the next reset.
    def __getstate__(self):
        state = self.__dict__.copy()
        for key in ("world", "ctx", "goal", "_renderer", "_view_renderer"):
            state[key] = None
        return state

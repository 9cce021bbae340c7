"""The user and the agent, both learnable: a PettingZoo ``ParallelEnv`` over the household tasks.

The single-agent :class:`~legent_gym.envs.household.HouseholdEnv` does all the work of the
agent's step, reward and observation, through its episode engine
(:class:`~legent_gym.envs.episode.Episode`: the house, the bodies, the task, the views);
this env owns one and adds the user's turn before it, on the same engine. Each parallel step:

1. the user's action runs on the user's body (moves, turns, interactions) through the same
   code path as the agent's (:meth:`Episode.execute <legent_gym.envs.episode.Episode.execute>`); the user's speech becomes the agent's ``message`` (and, with
   ``instruction_from_user=True``, its first words become the agent's ``instruction``);
2. the agent's action runs through ``HouseholdEnv.step``, which judges the task after both
   have acted; the agent's speech becomes the user's ``message``;
3. both egocentric views are rendered (the agent's inside ``HouseholdEnv.step``).

So, with a user that never acts, the agent's observations, rewards and infos are exactly
those of the single-agent env under the same seed (``tests/multiagent/test_multiagent.py`` checks it).

Module functions, as PettingZoo envs have them: :func:`parallel_env`, :func:`raw_env` (the
AEC form) and :func:`env` (the AEC form with order enforcement); :func:`env_module` gives
the three bound to one registered id (for ``pettingzoo.test.max_cycles_test``).
"""

from __future__ import annotations

import copy
import functools
import math
from dataclasses import replace
from types import SimpleNamespace
from typing import Any

import numpy as np
from pettingzoo import ParallelEnv
from pettingzoo.utils.conversions import parallel_to_aec_wrapper
from pettingzoo.utils.wrappers import OrderEnforcingWrapper

from legent_gym.agent.actions import (
    ActionLimits,
    ActionParseError,
    Finish,
    Grab,
    Interact,
    Speak,
    clip_action,
    format_action,
)
from legent_gym.agent.body import Body, Outcome
from legent_gym.envs.action_spaces import SPEECH_CHARSET, parse_step
from legent_gym.envs.episode import Episode
from legent_gym.envs.household import MAX_TEXT, NO_ID, HouseholdEnv, action_info
from legent_gym.multiagent.registration import id_kwargs
from legent_gym.multiagent.window import Window
from legent_gym.tasks.base import MAX_ACTIONS
from legent_gym.world.builder import GROUP_COLLISION, World
from legent_gym.world.render import FreeCamera, Renderer

USER, AGENT = "user", "agent"
REWARD_MODES = ("team", "per_agent")
_SPEECH_CHARS = frozenset(SPEECH_CHARSET)


def to_speech(text: str) -> str:
    """Words as the listener's observation holds them: characters outside the speech
    charset become spaces (tabs, newlines, backslashes can be spoken in action code but a
    ``Text`` observation space cannot hold them), at most ``MAX_TEXT`` characters."""
    return "".join(c if c in _SPEECH_CHARS else " " for c in text[:MAX_TEXT])


class HouseholdParallelEnv(ParallelEnv):
    """## Description
    LEGENT's household tasks with both sides embodied and acting: the ``"user"`` and the
    ``"agent"`` share a house, each sees through its own head camera and acts with the same
    action language (``speak``, ``move_forward``, ``rotate_right``, ``rotate_down``,
    ``interact``/``grab``/``put``/``open``/``close``, ``finish``). What the user says
    reaches the agent; what the agent says reaches the user. The task (ComeHere, GoTo,
    PickUp, BringMe, WhereIs, PutOn) is the agent's, judged after both have acted.

    ## Agents
    ``possible_agents == ["user", "agent"]``; the AEC form lets the user act first.

    ## Action Space (each agent)
    The single-agent env's: ``Text`` action code (``action_type="text"``) or the ``Dict``
    form (``"continuous"``). The user may also pass ``None``: it does nothing this step.
    The user's ``finish()`` does nothing (only the agent ends the episode); the user's
    speech goes to the agent, never into the task's judgement (WhereIs hears the agent).
    Either side may take an object out of the other's hands with ``grab``/``interact``.

    ## Observation Space (each agent)
    A ``Dict``: ``rgb`` (H, W, 3) uint8 from the agent's own head camera; ``instruction``
    Text; ``message`` Text; with ``depth=True`` / ``segmentation=True`` also those images.
    The agent: ``instruction`` is the task's instruction, ``message`` the user's latest
    words (the instruction at reset). With ``instruction_from_user=True`` both start empty
    and the user's first words become the agent's instruction. The user: ``instruction``
    is what it wants done (the task's instruction), ``message`` the agent's latest words.
    Speech is cut to 500 characters; characters a Text observation cannot hold become spaces.

    ## Rewards
    ``rewards="team"`` (default): both get the task's reward (``reward="sparse"``: 1 on
    success; ``"dense"``: geodesic progress to the sub-goal, -0.01 per step, +10 on
    success). ``rewards="per_agent"``: with dense rewards each is credited with the progress
    its own actions made (the user's turn is judged before the agent's), and both share the
    step cost and the success bonus; with sparse rewards both get the success reward.

    ## Episode End
    Both terminate when the task ends (success, the agent's ``finish()``, the agent's
    speech in WhereIs); both truncate after ``max_cycles`` steps (25).

    ## Info
    The agent's info is the single-agent env's. The user's has the same keys and types
    (poses, task, success, distances) with its own ``held``, ``n_actions``,
    ``action_text``, ``action_ok``, ``action_results`` and ``action_error`` (a user that
    passes None: "", True, "", ""). ``distance_to_goal`` is -1 unless
    ``distance_info=True`` or ``reward="dense"``: where the goal is the user (ComeHere,
    BringMe), a user who moves makes it a shortest-path search over the whole house every
    step, dearer than the step itself.

    ## Arguments
    * ``task``: ComeHere, GoTo, PickUp, BringMe, WhereIs or PutOn.
    * ``layout``: the generation preset of new houses: OneRoom, TwoRoom, FourRoom or
      Apartment.
    * ``action_type``: ``"text"`` (default) or ``"continuous"``, for both sides.
    * ``max_cycles``: parallel steps before both truncate (25).
    * ``rewards``: ``"team"`` (default) or ``"per_agent"`` (see Rewards).
    * ``instruction_from_user``: the user's first words become the agent's instruction.
    * ``distance_info``: ``info["distance_to_goal"]`` every step (default False, see Info).
    * ``render_mode``: ``"rgb_array"``, a third-person view of both; ``"human"``, the same
      view shown in a pygame window at every reset and step (without a display it opens on
      SDL's dummy driver, with a warning, and shows nothing).
    * ``render_size``: the ``render()`` image's side in pixels (256).
    * every other keyword goes to ``HouseholdEnv`` (``width``, ``height``, ``fovy``,
      ``camera``, ``reward``, ``scene``, ``house_seed``, ``house_pool``, ``depth``,
      ``segmentation``, ``strict``, ``reach``, ...). The user's camera takes the agent's
      field of view.
    """

    metadata: dict[str, Any] = {"name": "legent_household_v0", "render_modes": ["human", "rgb_array"], "render_fps": 4,
                "is_parallelizable": True}

    def __init__(self, task: str = "ComeHere", layout: str = "OneRoom", action_type: str = "text", *,
                 max_cycles: int = MAX_ACTIONS, rewards: str = "team", instruction_from_user: bool = False,
                 distance_info: bool = False, render_mode: str | None = None, render_size: int = 256,
                 **household_kwargs: Any):
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise ValueError(f"render_mode must be one of {self.metadata['render_modes']} or None, "
                             f"got {render_mode!r}")
        if rewards not in REWARD_MODES:
            raise ValueError(f"rewards must be one of {REWARD_MODES}, got {rewards!r}")
        if isinstance(max_cycles, bool) or not isinstance(max_cycles, int | np.integer) or max_cycles < 1:
            raise ValueError(f"max_cycles must be a positive integer, got {max_cycles!r}")
        # The user acts here: its body is articulated (walks, looks, reaches), unless the
        # caller knows it never moves a limb (make_single_agent with a still user).
        household_kwargs.setdefault("user_moves", True)
        self.core = HouseholdEnv(task, layout, action_type, distance_info=distance_info, **household_kwargs)
        # The user's eyes get the agent's field of view (the builder's default user is 90 degrees).
        episode = self.core.episode
        episode.build_options = replace(episode.build_options,
                                        user=replace(episode.build_options.user, fovy=episode.build_options.agent.fovy))
        self.task_name, self.layout, self.action_type = task, layout, action_type
        self.max_cycles = int(max_cycles)
        self.rewards_mode = rewards
        self.instruction_from_user = bool(instruction_from_user)
        self.render_mode, self.render_size = render_mode, int(render_size)

        self.possible_agents = [USER, AGENT]
        self.agents: list[str] = []
        # One space object per agent (PettingZoo seeds each agent's space separately).
        self.observation_spaces = {USER: copy.deepcopy(self.core.observation_space),
                                   AGENT: self.core.observation_space}
        self.action_spaces = {USER: copy.deepcopy(self.core.action_space), AGENT: self.core.action_space}

        self.cycles = 0
        self._agent_instruction = ""
        self._agent_hears = ""
        self._user_hears = ""
        self._last_distance: float | None = None
        self._view_renderer: Renderer | None = None
        self._view_world: World | None = None
        self._window = Window(f"legent_gym {task}-{layout}", self.metadata["render_fps"]) \
            if render_mode == "human" else None

    # -- spaces --------------------------------------------------------------------------
    def observation_space(self, agent: str):
        return self.observation_spaces[agent]

    def action_space(self, agent: str):
        return self.action_spaces[agent]

    # -- privileged state, for scripted user policies, experts and analysis ----------------
    @property
    def episode(self) -> Episode:
        """The episode engine both sides act in (the single-agent env's)."""
        return self.core.episode

    @property
    def limits(self) -> ActionLimits:
        """The most either side's one action may move, turn, tilt and say (metres, degrees)."""
        return self.core.episode.limits

    # -- PettingZoo API ------------------------------------------------------------------
    def reset(self, seed: int | None = None, options: dict | None = None):
        agent_obs, agent_info = self.core.reset(seed=seed, options=options)
        scene = self.episode.require().scene
        if scene.user is None:
            raise ValueError(f"house {scene.name!r} has no user: a multi-agent env needs "
                             "a 'user' spawn in the scene")
        self.agents = list(self.possible_agents)
        self.cycles = 0
        instruction = self.episode.require_goal().instruction
        self._agent_instruction = "" if self.instruction_from_user else instruction
        self._agent_hears = self._agent_instruction
        self._user_hears = ""
        self._last_distance = agent_info["distance_to_goal"]
        observations = {USER: self._user_observation(), AGENT: self._agent_observation(agent_obs)}
        user_info = self._user_info(agent_info, [], [], "")
        if self._window is not None:
            self.render()
        return observations, {USER: user_info, AGENT: agent_info}

    def step(self, actions: dict[str, Any]):
        if not self.agents:
            raise RuntimeError("the episode is over (or never began): call reset() before step()")
        unknown = set(actions) - set(self.possible_agents)
        if unknown:
            raise ValueError(f"actions for unknown agents {sorted(unknown)}; agents are {self.possible_agents}")
        missing = [a for a in self.agents if a not in actions]
        if missing:
            raise ValueError(f"actions must hold one entry per live agent: missing {missing} "
                             "(the user may pass None to do nothing)")
        episode = self.episode
        ctx = episode.require()
        user_texts, user_results, user_error = self._user_turn(actions[USER])
        distance_after_user = None
        if self.rewards_mode == "per_agent" and self.core.reward_type == "dense":
            distance_after_user = self.core.distance_left()

        said_before = len(ctx.speech)
        carried = ctx.user.state.held
        carried_at = ctx.world.object_position(carried) if carried is not None else None
        agent_obs, reward, terminated, _, agent_info = self.core.step(actions[AGENT])
        if carried is not None and carried_at is not None:  # (both or neither)
            if ctx.agent.state.held == carried or _collides(ctx.world, carried):
                ctx.user.state.held = None  # the agent took it out of the user's hands (and maybe put it down)
            elif not np.array_equal(carried_at, ctx.world.object_position(carried)):
                # Physics the agent's turn ran (settling a put object, a drawer) moved what the
                # user carries: back into the user's hands, and the agent's view drawn again.
                self._restore_carried(ctx.user)
                agent_obs.update(episode.views(AGENT))
        if len(ctx.speech) > said_before:
            self._user_hears = to_speech(ctx.speech[-1])

        self.cycles += 1
        truncated = self.cycles >= self.max_cycles
        observations = {USER: self._user_observation(), AGENT: self._agent_observation(agent_obs)}
        rewards = self._rewards(float(reward), distance_after_user, agent_info["distance_to_goal"])
        user_info = self._user_info(agent_info, user_texts, user_results, user_error)
        terminations = {USER: bool(terminated), AGENT: bool(terminated)}
        truncations = {USER: truncated, AGENT: truncated}
        if terminated or truncated:
            self.agents = []
        if self._window is not None:
            self.render()
        return observations, rewards, terminations, truncations, {USER: user_info, AGENT: agent_info}

    # -- the user's turn -----------------------------------------------------------------
    def _user_turn(self, action) -> tuple[list[str], list[Outcome], str]:
        """The user's primitives as code, their outcomes, and why the action did not parse ("")."""
        if action is None:
            return [], [], ""
        try:
            primitives = parse_step(action, self.action_type)
        except (ActionParseError, ValueError) as err:
            if self.core.strict:
                raise
            return [], [], str(err)
        ctx = self.episode.require()
        results: list[Outcome] = []
        with ctx.user.batched():  # as for the agent: one world update for the step's moves and turns
            for primitive in primitives:
                results.append(self._user_execute(primitive))
                if ctx.agent.state.held is not None and ctx.agent.state.held == ctx.user.state.held:
                    ctx.agent.state.held = None  # the user took it out of the agent's hands
        return [format_action(p) for p in primitives], results, ""

    def _user_execute(self, primitive) -> Outcome:
        episode = self.episode
        ctx = episode.require()
        match primitive:
            case Speak():
                spoken, note = clip_action(primitive, episode.limits)
                words = to_speech(spoken.text)
                self._agent_hears = words
                if self.instruction_from_user and not self._agent_instruction:
                    self._agent_instruction = words
                return Outcome(True, note)
            case Finish():
                return Outcome(False, "the user cannot finish the episode: only the agent's finish() ends it")
        held = ctx.agent.state.held
        before = ctx.world.object_position(held) if held is not None else None
        outcome = episode.execute(primitive, body=ctx.user)
        if held is not None and before is not None and ctx.agent.state.held == held and \
                not np.array_equal(before, ctx.world.object_position(held)):
            self._restore_carried(ctx.agent)  # physics of the user's put or drawer moved it
        if held is not None and isinstance(primitive, Grab | Interact) and outcome.ok and outcome.target == held:
            outcome.reason = "taken from the agent's hands"
        return outcome

    @staticmethod
    def _restore_carried(body: Body) -> None:
        s = body.state
        body.place(s.x, s.y, s.yaw, s.pitch)  # re-syncs the held object into the hand

    # -- observations, rewards, infos -------------------------------------------------------
    def _user_observation(self) -> dict[str, Any]:
        views = self.episode.views(USER)
        obs = {"rgb": views.pop("rgb"), "instruction": self.episode.require_goal().instruction,
               "message": self._user_hears}
        obs.update(views)
        return obs

    def _agent_observation(self, core_obs: dict[str, Any]) -> dict[str, Any]:
        core_obs["instruction"] = self._agent_instruction
        core_obs["message"] = self._agent_hears
        return core_obs

    def _rewards(self, team: float, after_user: float | None, after_agent: float | None) -> dict[str, float]:
        before, self._last_distance = self._last_distance, after_agent
        if self.rewards_mode == "team" or after_user is None:
            return {USER: team, AGENT: team}

        def progress(a, b) -> float:
            return a - b if a is not None and b is not None and math.isfinite(a) and math.isfinite(b) else 0.0

        # The team's reward counts both turns' progress; each side gives back the other's.
        return {USER: team - progress(after_user, after_agent), AGENT: team - progress(before, after_user)}

    def _user_info(self, agent_info: dict[str, Any], texts: list[str], results: list[Outcome],
                   error: str) -> dict[str, Any]:
        """The agent's info with the user's own ``held``, ``n_actions`` and action fields (the
        same keys and types as the agent's, at reset and every step)."""
        info = dict(agent_info)
        info["task"] = dict(agent_info["task"])
        held = self.episode.require().user.state.held
        info["held"] = NO_ID if held is None else held
        info["n_actions"] = self.cycles
        info.update(action_info(texts, results, error))
        return info

    # -- rendering and closing -------------------------------------------------------------
    def render(self):
        world = self.episode.world
        if self.render_mode is None or world is None:
            return None
        renderer = self._view_renderer
        if renderer is None or self._view_world is not world:  # the first frame, or a new house
            if renderer is not None:
                renderer.close()
            renderer = self._view_renderer = Renderer(world, self.render_size, self.render_size, "fast")
            self._view_world = world
        ctx = self.episode.require()
        a, u = ctx.agent.state, ctx.user.state
        gap = math.hypot(u.x - a.x, u.y - a.y)
        side = math.degrees(math.atan2(u.y - a.y, u.x - a.x)) - 90.0  # look across the line joining them
        camera = FreeCamera(((a.x + u.x) / 2, (a.y + u.y) / 2, 0.8), max(4.0, 0.9 * gap + 2.5),
                            azimuth=side, elevation=-55.0)
        frame = renderer.rgb(camera)
        if self._window is not None:
            self._window.show(frame)
            return None
        return frame

    def close(self):
        if self._window is not None:
            self._window.close()
        if self._view_renderer is not None:
            self._view_renderer.close()
        self._view_renderer = self._view_world = None
        self.core.close()


def _collides(world, object_id: int) -> bool:
    """Whether the object's collision geoms are on: off exactly while someone holds it."""
    model = world.model
    body = world.object_body[object_id]
    first = model.body_geomadr[body]
    return any(model.geom_contype[g] for g in range(first, first + model.body_geomnum[body])
               if model.geom_group[g] == GROUP_COLLISION)


def parallel_env(**kwargs: Any) -> HouseholdParallelEnv:
    """The parallel form (``task=``, ``layout=``, and every :class:`HouseholdParallelEnv` argument)."""
    return HouseholdParallelEnv(**kwargs)


def raw_env(**kwargs: Any) -> parallel_to_aec_wrapper:
    """The AEC form, unwrapped: the user acts, then the agent; a cycle is one parallel step."""
    return parallel_to_aec_wrapper(parallel_env(**kwargs))


def env(**kwargs: Any) -> OrderEnforcingWrapper:
    """The AEC form with PettingZoo's order enforcement (what ``pettingzoo.make("aec", id)`` gives)."""
    return OrderEnforcingWrapper(raw_env(**kwargs))


def env_module(env_id: str) -> SimpleNamespace:
    """``env``, ``parallel_env`` and ``raw_env`` bound to a registered id's task and layout,
    shaped like a PettingZoo environment module (``max_cycles_test`` takes one)."""
    bound = id_kwargs(env_id)
    return SimpleNamespace(env=functools.partial(env, **bound), parallel_env=functools.partial(parallel_env, **bound),
                           raw_env=functools.partial(raw_env, **bound), __name__=env_id)

"""Scripted users (and the interface every fixed partner policy follows).

A policy is reset at the start of each episode with the env and a random generator of its
own (so that a user's randomness never shifts the houses an env draws), then asked for one
action per step. Scripted users read privileged state (``env.episode.ctx``: both bodies and the
navigation grid) the way a person in the house would know where things are::

    StandStill()                  stands where it is (the single-agent env's passive user)
    Wander(speed=0.5)             walks between random points of the house, pausing now and then
    WalkAway(speed=0.5)           heads for the reachable spot farthest from the agent
    ComeTowards(speed=0.5)        walks to the agent and stops about a metre away, facing it

Each of these turns to look at the agent, for a step, when the agent says something (as a
person does when spoken to), then goes on.
    RepeatInstruction(every=5)    says the instruction at the start and every few steps
                                  (``then=`` another policy for the walking)

Actions are LEGENT's action code: ``"rotate_right(-35), move_forward(0.5)"``. Any object
with ``reset(env, rng)`` and ``act(env, observation)`` works as a policy; a plain function
``observation -> action`` (e.g. a trained model's predict) is wrapped by
:func:`make_policy`.
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from legent_gym.agent.actions import Action, MoveForward, RotateRight, Speak, format_actions

ARRIVED = 0.3  # metres: a goal this close counts as reached


class UserPolicy(ABC):
    """A fixed policy for one side of :class:`~legent_gym.multiagent.HouseholdParallelEnv`."""

    rng: np.random.Generator

    def reset(self, env, rng: np.random.Generator) -> None:
        """Called after each env reset, before the first ``act``."""
        self.rng = rng
        self._speech_heard = 0

    def spoken_to(self, env) -> bool:
        """Whether the agent has said something since this policy last asked."""
        said = len(env.episode.ctx.speech)
        new = said > getattr(self, "_speech_heard", 0)
        self._speech_heard = said
        return new

    def look_at_speaker(self, env) -> str | None:
        """A turn towards the agent if it has just spoken and the user is not facing it."""
        if not self.spoken_to(env):
            return None
        ctx = env.episode.ctx
        return face(ctx.user, ctx.agent.position)

    @abstractmethod
    def act(self, env, observation: dict[str, Any]) -> Any:
        """The action for this step (action code, a Dict action, or None to do nothing)."""


def walk_along(body, path: Sequence[tuple[float, float]], max_move: float) -> str | None:
    """One step of action code that follows ``path`` (corner points, from the body's position):
    turn towards the next corner (at most 90 degrees) and, once facing it, walk up to
    ``max_move`` metres towards it in the same step. None when the path is walked."""
    s = body.state
    for cx, cy in path[1:]:
        distance = math.hypot(cx - s.x, cy - s.y)
        if distance > 0.05:
            break
    else:
        return None
    error = (math.degrees(math.atan2(cy - s.y, cx - s.x)) - s.yaw + 180.0) % 360.0 - 180.0  # + is to the left
    step: list[Action] = []
    if abs(error) > 1.0:
        step.append(RotateRight(round(-max(-90.0, min(90.0, error)), 1)))
    move = round(min(distance, max_move), 2)
    if abs(error) <= 90.0 and move > 0:
        step.append(MoveForward(move))
    return format_actions(step) if step else None


def face(body, point, tolerance: float = 15.0) -> str | None:
    """Turn towards a point (None when already facing it within ``tolerance`` degrees)."""
    s = body.state
    error = (math.degrees(math.atan2(point[1] - s.y, point[0] - s.x)) - s.yaw + 180.0) % 360.0 - 180.0
    if abs(error) <= tolerance:
        return None
    return format_actions((RotateRight(round(-max(-90.0, min(90.0, error)), 1)),))


class StandStill(UserPolicy):
    """Stands where it is (the user of the single-agent env, which never asks it); turns to
    the agent when spoken to."""

    def act(self, env, observation):
        return self.look_at_speaker(env)


class _Walker(UserPolicy):
    """Walks to a goal it chooses; a new goal when it arrives or is blocked."""

    def __init__(self, speed: float = 0.5):
        if not speed > 0:
            raise ValueError(f"speed must be positive (metres per step), got {speed!r}")
        self.speed = float(speed)

    def reset(self, env, rng):
        super().reset(env, rng)
        self.goal: tuple[float, float] | None = None
        self._asked_from: np.ndarray | None = None  # where the user stood when it last walked

    def _blocked(self, body) -> bool:
        return self._asked_from is not None and float(np.hypot(*(body.position - self._asked_from))) < 0.01

    def _walk(self, env, body) -> str | None:
        path = env.episode.ctx.nav.path(tuple(body.position), self.goal)
        action = walk_along(body, path, self.speed) if path else None
        self._asked_from = body.position if action is not None and "move_forward" in action else None
        return action


class Wander(_Walker):
    """Walks between random reachable points of the house at ``speed`` metres per step,
    standing still for a step with probability ``pause``."""

    def __init__(self, speed: float = 0.5, pause: float = 0.25):
        super().__init__(speed)
        if not 0 <= pause < 1:
            raise ValueError(f"pause must be a probability in [0, 1), got {pause!r}")
        self.pause = float(pause)

    def act(self, env, observation):
        turn = self.look_at_speaker(env)
        if turn is not None:
            self._asked_from = None
            return turn
        user, nav = env.episode.ctx.user, env.episode.ctx.nav
        if self.goal is None or self._blocked(user) or math.dist(user.position, self.goal) < ARRIVED:
            cells = np.argwhere(nav.labels == nav.component(tuple(user.position)))
            if len(cells) == 0:
                return None
            self.goal = nav.to_world(cells[int(self.rng.integers(len(cells)))])
        if self.rng.random() < self.pause:
            self._asked_from = None
            return None
        return self._walk(env, user)


class WalkAway(_Walker):
    """Heads for the reachable spot farthest (by walking distance) from the agent,
    re-choosing it when the agent has moved half a metre."""

    def reset(self, env, rng):
        super().reset(env, rng)
        self._agent_seen_at: np.ndarray | None = None

    def act(self, env, observation):
        turn = self.look_at_speaker(env)
        if turn is not None:
            self._asked_from = None
            return turn
        user, agent, nav = env.episode.ctx.user, env.episode.ctx.agent, env.episode.ctx.nav
        if self.goal is None or self._blocked(user) or \
                float(np.hypot(*(agent.position - self._agent_seen_at))) > 0.5:
            field = nav.distance_field(tuple(agent.position))
            field[(nav.labels != nav.component(tuple(user.position))) | ~np.isfinite(field)] = -1.0
            self.goal = nav.to_world(np.unravel_index(int(np.argmax(field)), field.shape))
            self._agent_seen_at = agent.position
        if math.dist(user.position, self.goal) < ARRIVED:
            return None
        return self._walk(env, user)


class ComeTowards(_Walker):
    """Walks to the agent and stops ``stop_distance`` metres from it, turning to face it."""

    def __init__(self, speed: float = 0.5, stop_distance: float = 1.0):
        super().__init__(speed)
        self.stop_distance = float(stop_distance)

    def act(self, env, observation):
        turn = self.look_at_speaker(env)
        if turn is not None:
            return turn
        user, agent = env.episode.ctx.user, env.episode.ctx.agent
        gap = user.horizontal_distance(agent.position)
        if gap <= self.stop_distance:
            return face(user, agent.position)
        self.goal = tuple(agent.position)
        path = env.episode.ctx.nav.path(tuple(user.position), self.goal)
        return walk_along(user, path, min(self.speed, gap - self.stop_distance)) if path else None


class RepeatInstruction(UserPolicy):
    """Says the instruction at the first step and every ``every`` steps after; walks as
    ``then`` does (stands still by default)."""

    def __init__(self, every: int = 5, then: UserPolicy | str | None = None):
        if every < 1:
            raise ValueError(f"every must be a positive number of steps, got {every!r}")
        self.every = int(every)
        self.then = make_policy(then) if then is not None else StandStill()

    def reset(self, env, rng):
        super().reset(env, rng)
        self.then.reset(env, rng)
        self._steps = 0

    def act(self, env, observation):
        move = self.then.act(env, observation)
        due = self._steps % self.every == 0
        self._steps += 1
        if not due:
            return move
        speech = format_actions((Speak(observation["instruction"]),))
        return speech if move is None else f"{speech}, {move}"


class CallablePolicy(UserPolicy):
    """A function ``observation -> action`` (a trained model, a keyboard, ...) as a policy."""

    def __init__(self, fn: Callable[[dict[str, Any]], Any]):
        self.fn = fn

    def act(self, env, observation):
        return self.fn(observation)


USER_POLICIES: dict[str, type[UserPolicy]] = {
    "still": StandStill,
    "wander": Wander,
    "walk_away": WalkAway,
    "come_towards": ComeTowards,
    "repeat_instruction": RepeatInstruction,
}


def make_policy(spec: UserPolicy | str | Callable) -> UserPolicy:
    """A policy from a name in :data:`USER_POLICIES` (default settings), a policy object,
    or a function ``observation -> action``."""
    if isinstance(spec, UserPolicy):
        return spec
    if isinstance(spec, str):
        try:
            return USER_POLICIES[spec]()
        except KeyError:
            raise ValueError(f"unknown user policy {spec!r}; known: {', '.join(USER_POLICIES)}") from None
    if callable(spec):
        return CallablePolicy(spec)
    raise TypeError(f"a policy is a name, a UserPolicy or a function observation -> action, got {spec!r}")

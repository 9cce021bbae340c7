"""One person's game: the env, the partner policy, the person's view, the map, the recorder.

A :class:`PlaySession` is driven from one thread (the server runs every session's calls on
one worker thread, which owns the OpenGL context). It knows nothing of the network: the
server turns its :meth:`PlaySession.state` into messages.

* ``role="user"``: the person is the user of the multi-agent env
  (:class:`~legent_gym.multiagent.HouseholdParallelEnv`, with ``instruction_from_user=True``:
  the person's first words are the agent's instruction). Every action of the person is
  one parallel step; the partner policy chooses the agent's action of that step once the
  agent has an instruction, and :meth:`PlaySession.tick` lets the agent act alone while
  the person waits.
* ``role="agent"``: the person is the agent of the single-agent env (the user stands
  still), wrapped in :class:`~legent_gym.wrappers.expert.ExpertInfo` as ``legent-gym
  collect`` wraps it; with ``record`` every episode that ends is written in the LEGENT
  and Minari formats (:mod:`legent_gym.play.recorder`).
"""

from __future__ import annotations

import base64
import importlib
import json
import math
import re
import urllib.request
from pathlib import Path
from typing import Any

import cv2
import numpy as np

from legent_gym.agent import Speak, format_action
from legent_gym.data.rollout import make_env
from legent_gym.experts.expert import Expert
from legent_gym.play.recorder import Recorder
from legent_gym.tasks import MAX_ACTIONS
from legent_gym.world.render import Renderer
from legent_gym.world.scene import Scene
from legent_gym.world.topdown_map import draw_topdown_map

ROLES = ("user", "agent")
PARTNERS = ("expert", "random", "llm")
#: A partner given as a trained policy: ``module:function`` (a function of no arguments that
#: returns a policy with ``reset(instruction)`` and ``act(observation) -> action code``) or
#: ``module:function:ARGUMENT`` (the function is given the text ARGUMENT, e.g. a checkpoint:
#: ``baselines.vla.policy:partner:model.pt``, the repository's compact VLA).
PLUGIN = re.compile(r"(?P<module>[\w.]+):(?P<function>\w+)(?::(?P<argument>.+))?")
#: The longest text (speech or action code) a person may send.
MAX_TEXT = 500
#: Pixels of the map's longer side.
MAP_SIZE = 360
#: Parallel steps before a user-mode episode truncates (a person walks in small steps).
USER_MAX_CYCLES = 200
#: The map's margin in pixels (``draw_topdown_map`` draws with this margin).
MAP_PAD = 16

#: Keyboard commands -> action code (the page shows the keys).
KEY_ACTIONS = {
    "forward": "move_forward(0.5)",
    "forward_far": "move_forward(1.5)",
    "left": "rotate_right(-30)",
    "right": "rotate_right(30)",
    "around": "rotate_right(180)",
    "look_up": "rotate_down(-15)",
    "look_down": "rotate_down(15)",
    "interact": "interact()",
    "finish": "finish()",
}


class PartnerError(RuntimeError):
    """The partner policy could not choose an action (shown on the page; the agent waits)."""


# -- partner policies (they drive the agent while the person plays the user) ------------------
class ExpertPartner:
    """The task expert's next action (privileged: reads the episode through the Oracle)."""

    name = "expert"

    def __init__(self, env: Any):
        self.expert = Expert(env)

    def act(self, observation: dict[str, Any]) -> str:
        action = self.expert.action()
        if not isinstance(action, str):
            raise PartnerError(f"the expert returned {type(action).__name__}, not action code")
        return action


class RandomPartner:
    """A random move, turn or head tilt."""

    name = "random"

    def __init__(self, seed: int = 0):
        self.rng = np.random.default_rng(seed)

    def act(self, observation: dict[str, Any]) -> str:
        kind = int(self.rng.integers(3))
        if kind == 0:
            return f"move_forward({float(self.rng.uniform(0.2, 1.5)):.2f})"
        if kind == 1:
            return f"rotate_right({float(self.rng.uniform(-90, 90)):.1f})"
        return f"rotate_down({float(self.rng.uniform(-20, 20)):.1f})"


LLM_PROMPT = (
    "You are a household robot. You see nothing but the words below. Reply with one line of "
    "action code in this language: move_forward(metres), rotate_right(degrees), "
    "rotate_down(degrees), interact(), speak(\"text\"), finish(). Several actions may be "
    "joined by commas.")


class LLMPartner:
    """An OpenAI-compatible chat endpoint (``POST {base_url}/chat/completions``) that answers
    with action code. Any failure (endpoint down, bad reply) raises :class:`PartnerError`."""

    name = "llm"

    def __init__(self, base_url: str, model: str, api_key: str = "", timeout: float = 20.0):
        self.base_url, self.model, self.api_key, self.timeout = base_url.rstrip("/"), model, api_key, timeout
        self.history: list[str] = []

    def act(self, observation: dict[str, Any]) -> str:
        user_text = (f"Instruction: {observation.get('instruction', '')}\n"
                     f"The user's latest words: {observation.get('message', '')}\n"
                     f"Your previous actions: {'; '.join(self.history[-8:]) or 'none'}")
        body = json.dumps({"model": self.model, "messages": [{"role": "system", "content": LLM_PROMPT},
                                                             {"role": "user", "content": user_text}]}).encode()
        headers = {"Content-Type": "application/json"}
        if self.api_key:
            headers["Authorization"] = f"Bearer {self.api_key}"
        request = urllib.request.Request(f"{self.base_url}/chat/completions", data=body, headers=headers)
        try:
            with urllib.request.urlopen(request, timeout=self.timeout) as response:  # noqa: S310 (a URL the person gave)
                reply = json.loads(response.read())
            text = str(reply["choices"][0]["message"]["content"]).strip().splitlines()[0]
        except Exception as err:  # any failure of the endpoint is the partner's, reported on the page
            raise PartnerError(f"LLM endpoint {self.base_url}: {err}") from err
        self.history.append(text)
        return text[:MAX_TEXT]


class PolicyPartner:
    """A trained policy (the baselines' protocol: ``reset(instruction)``, then
    ``act(observation) -> action code``) as the partner; it is reset whenever the agent's
    instruction changes (a new episode, or the person's first words)."""

    def __init__(self, policy: Any, name: str):
        if not callable(getattr(policy, "act", None)):
            raise ValueError(f"partner {name!r} gave {type(policy).__name__}, which has no act(observation)")
        self.policy, self.name = policy, name
        self.instruction: str | None = None

    @property
    def env_kwargs(self) -> dict[str, Any]:
        """What the env must be made with for this policy (a VLA's view size)."""
        return dict(getattr(self.policy, "env_kwargs", {}) or {})

    def act(self, observation: dict[str, Any]) -> str:
        instruction = str(observation.get("instruction", ""))
        if instruction != self.instruction:
            self.instruction = instruction
            if callable(getattr(self.policy, "reset", None)):
                self.policy.reset(instruction)
        action = self.policy.act(observation)
        if not isinstance(action, str):
            raise PartnerError(f"{self.name} returned {type(action).__name__}, not action code")
        return action


def is_partner(name: str) -> bool:
    """A known partner name, ``module:function`` or ``module:function:ARGUMENT``."""
    return name in PARTNERS or PLUGIN.fullmatch(name) is not None


def load_policy_partner(spec: str) -> PolicyPartner:
    """The partner of a ``module:function[:ARGUMENT]`` spec (see :data:`PLUGIN`); ValueError
    naming what is missing or what the function refused."""
    match = PLUGIN.fullmatch(spec)
    if match is None:
        raise ValueError(f"--partner {spec}: not module:function or module:function:ARGUMENT")
    module_name, function, argument = match.group("module", "function", "argument")
    try:
        factory = getattr(importlib.import_module(module_name), function)
    except (ImportError, AttributeError) as err:
        raise ValueError(f"--partner {spec}: cannot import {function!r} from {module_name!r} ({err})") from None
    try:
        policy = factory() if argument is None else factory(argument)
    except ValueError as err:
        raise ValueError(f"--partner {spec}: {err}") from None
    return PolicyPartner(policy, spec)


def make_partner(name: str, env: Any, *, seed: int = 0, llm_url: str = "", llm_model: str = "",
                 llm_key: str = "") -> ExpertPartner | RandomPartner | LLMPartner:
    if name == "expert":
        return ExpertPartner(env)
    if name == "random":
        return RandomPartner(seed)
    if name == "llm":
        if not llm_url:
            raise ValueError("the llm partner needs an endpoint: --llm-url (or OPENAI_BASE_URL)")
        return LLMPartner(llm_url, llm_model or "gpt-4o-mini", llm_key)
    raise ValueError(f"unknown partner {name!r}; known: {', '.join(PARTNERS)}")


def speech_code(text: str) -> str:
    """``speak("...")`` for ``text`` (quoted as the action language reads it)."""
    return format_action(Speak(text))


def map_transform(scene: Scene, size: int) -> dict[str, float]:
    """How :func:`~legent_gym.world.topdown_map.draw_topdown_map` (``size``, its margin of
    ``MAP_PAD`` pixels) puts world metres on pixels: ``u = (x - x0) * scale + pad``,
    ``v = (y1 - y) * scale + pad``."""
    (x0, y0), (x1, y1) = scene.bounds()
    span = max(x1 - x0, y1 - y0, 1e-6)
    return {"x0": float(x0), "y1": float(y1), "scale": (size - 2 * MAP_PAD) / span, "pad": float(MAP_PAD)}


def _pose(value: Any) -> list[float] | None:
    if value is None:
        return None
    pose = [float(v) for v in value]
    return None if any(math.isnan(v) for v in pose) else pose


class PlaySession:
    """The env a person plays, as ``role`` (``"user"`` or ``"agent"``)."""

    def __init__(self, env_id: str, *, role: str = "user", partner: str = "expert",
                 size: tuple[int, int] = (640, 480), record: str | Path | None = None, seed: int = 0,
                 max_cycles: int = USER_MAX_CYCLES, env_kwargs: dict[str, Any] | None = None,
                 llm_url: str = "", llm_model: str = "", llm_key: str = "", jpeg_quality: int = 80):
        if role not in ROLES:
            raise ValueError(f"role must be one of {ROLES}, got {role!r}")
        if not is_partner(partner):
            raise ValueError(f"partner must be one of {PARTNERS} or module:function[:ARGUMENT], got {partner!r}")
        if record is not None and role != "agent":
            raise ValueError("recording needs role='agent' (the person's actions are the agent's)")
        self.env_id, self.role, self.partner_name = env_id, role, partner
        self.width, self.height = int(size[0]), int(size[1])
        self.seed = int(seed)
        self.jpeg_quality = int(jpeg_quality)
        kwargs = dict(env_kwargs or {})
        self.env: Any
        if role == "user":
            # pettingzoo (the multiagent extra) only for the person as the user.
            import pettingzoo

            import legent_gym.multiagent  # noqa: F401  (registers the ids)

            policy = None if partner in PARTNERS else load_policy_partner(partner)
            if policy is not None:
                kwargs.update(policy.env_kwargs)  # e.g. the view size a VLA was trained on
            self.env = pettingzoo.make("parallel", env_id, instruction_from_user=True, max_cycles=max_cycles,
                                       **kwargs)
            self.partner: Any = policy if policy is not None else make_partner(
                partner, self.env.unwrapped, seed=seed, llm_url=llm_url, llm_model=llm_model, llm_key=llm_key)
        else:
            self.env = make_env(env_id, kwargs, expert=True)
            self.partner = None
        self.recorder = None
        if record is not None:
            self.recorder = Recorder(record, env_id, self.env)
        self._renderer: Renderer | None = None
        self._renderer_world: Any = None
        self.transcript: list[dict[str, str]] = []
        self.version = 0
        self.map: dict[str, Any] = {}
        self.reset(new_house=False)

    # -- the episode ----------------------------------------------------------------------------
    @property
    def engine(self) -> Any:
        """The episode engine (house, bodies, goal) both front ends drive."""
        return self.env.unwrapped.episode

    def reset(self, new_house: bool = True) -> None:
        """A new episode: in a new house (the next seed) or the same house and task again."""
        if new_house and getattr(self, "obs", None) is not None:
            self.seed += 1
        self.transcript = []
        self.partner_error = ""
        self.result = ""  # info["action_results"] of the person's last action
        self.error = ""
        self.done = False
        self.recorded = ""
        self.steps = 0
        if self.role == "user":
            observations, infos = self.env.reset(seed=self.seed)
            self.obs, self.info = observations, infos
            self.instruction = str(observations["user"]["instruction"])
        else:
            obs, info = self.env.reset(seed=self.seed)
            self.obs, self.info = obs, info
            self.instruction = str(obs["instruction"])
            self.transcript.append({"who": "user", "text": self.instruction})
            if self.recorder is not None:
                self.recorder.begin(obs, info, self.seed)
        self._said = len(self.engine.require().speech)
        self.map = self._map()
        self.version += 1

    def _map(self) -> dict[str, Any]:
        scene = self.engine.require().scene
        bare = scene.model_copy(update={"agent": None, "user": None})
        img = draw_topdown_map(bare, size=MAP_SIZE, labels=True)
        ok, png = cv2.imencode(".png", img[:, :, ::-1])
        if not ok:
            raise RuntimeError("could not encode the map")
        return {"png": "data:image/png;base64," + base64.b64encode(png.tobytes()).decode("ascii"),
                "width": int(img.shape[1]), "height": int(img.shape[0]), **map_transform(scene, MAP_SIZE)}

    @property
    def agent_instructed(self) -> bool:
        return self.role == "user" and bool(str(self.obs["agent"]["instruction"]))

    def act(self, code: str) -> None:
        """The person's action (action code); an action that does not parse is reported."""
        code = str(code)[:MAX_TEXT]
        if self.done:
            self.error = "the episode is over: press a reset button"
            self.version += 1
            return
        if self.role == "user":
            self._user_step(code)
        else:
            self._agent_step(code)
        self.version += 1

    def say(self, text: str) -> None:
        """The person's words: ``speak(...)`` (they reach the other side as its ``message``)."""
        text = " ".join(str(text).split())[:MAX_TEXT]
        if not text:
            self.error = "nothing to say"
            self.version += 1
            return
        if not self.done and self.role == "user":  # (the agent's own speech is heard from the episode)
            self.transcript.append({"who": "you", "text": text})
        self.act(speech_code(text))

    def tick(self) -> bool:
        """User mode: the agent acts alone (the person does nothing this step), once it has
        an instruction and the episode goes on. Returns whether a step was taken."""
        if self.role != "user" or self.done or not self.agent_instructed:
            return False
        self._user_step(None)
        self.version += 1
        return True

    def _partner_action(self) -> str:
        if not self.agent_instructed:
            return ""  # the agent waits for its instruction (an empty action does nothing)
        try:
            action = self.partner.act(self.obs["agent"])
            self.partner_error = ""
            return action
        except Exception as err:  # a failing partner is shown on the page; the person goes on
            self.partner_error = f"{self.partner_name} partner failed: {err}"
            return ""

    def _user_step(self, code: str | None) -> None:
        agent_action = self._partner_action()
        observations, _, terminations, truncations, infos = self.env.step({"user": code, "agent": agent_action})
        self.obs, self.info = observations, infos
        user_info = infos["user"]
        self.result = str(user_info.get("action_results", "")) if code is not None else self.result
        self.error = str(user_info.get("action_error") or "") if code is not None else self.error
        self._hear("agent")
        self.done = bool(terminations["agent"] or truncations["agent"])

    def _agent_step(self, code: str) -> None:
        obs, reward, terminated, truncated, info = self.env.step(code)
        self.steps += 1
        self.obs, self.info = obs, info
        self.result = str(info.get("action_results", ""))
        self.error = str(info.get("action_error") or "")
        self._hear("you")
        self.done = bool(terminated or truncated)
        if self.recorder is not None:
            self.recorder.step(code, obs, float(reward), bool(terminated), bool(truncated), info)
            if self.done:
                self.recorded = self.recorder.end(info)

    def _hear(self, who: str) -> None:
        speech = self.engine.require().speech
        for text in speech[self._said:]:
            self.transcript.append({"who": who, "text": str(text)})
        self._said = len(speech)

    # -- what the page shows ----------------------------------------------------------------------
    @property
    def agent_info(self) -> dict[str, Any]:
        return self.info["agent"] if self.role == "user" else self.info

    def frame(self) -> np.ndarray:
        """The person's egocentric view at the page's size, (H, W, 3) uint8."""
        world = self.engine.require().world
        if self._renderer is None or self._renderer_world is not world:
            if self._renderer is not None:
                self._renderer.close()
            self._renderer = Renderer(world, self.width, self.height, "fast")
            self._renderer_world = world
        return self._renderer.rgb(self.role)

    def jpeg(self) -> bytes:
        ok, data = cv2.imencode(".jpg", self.frame()[:, :, ::-1], [cv2.IMWRITE_JPEG_QUALITY, self.jpeg_quality])
        if not ok:
            raise RuntimeError("could not encode the frame")
        return data.tobytes()

    def state(self) -> dict[str, Any]:
        info = self.agent_info
        task = dict(info.get("task") or {})
        if self.role == "user":
            used, cap = int(self.env.unwrapped.cycles), int(self.env.unwrapped.max_cycles)
        else:
            spec = getattr(self.env, "spec", None)
            used, cap = self.steps, int(getattr(spec, "max_episode_steps", None) or MAX_ACTIONS)
        return {
            "type": "state",
            "version": self.version,
            "role": self.role,
            "partner": self.partner_name if self.role == "user" else "still user",
            "env_id": self.env_id,
            "seed": self.seed,
            "task": str(task.get("name", "")),
            "instruction": self.instruction,
            "agent_instructed": self.agent_instructed if self.role == "user" else True,
            "success": bool(info.get("success", False)),
            "done": self.done,
            "actions_used": used,
            "actions_cap": cap,
            "result": self.result,
            "error": self.error,
            "partner_error": self.partner_error,
            "recorded": self.recorded,
            "agent_pose": _pose(info.get("agent_pose")),
            "user_pose": _pose(info.get("user_pose")),
            "transcript": self.transcript,
        }

    def close(self) -> None:
        if self._renderer is not None:
            self._renderer.close()
            self._renderer = None
        if self.recorder is not None:
            self.recorder.close()
        self.env.close()


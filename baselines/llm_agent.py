"""A zero-shot multimodal LLM agent: the paper's GPT-4V row, over any OpenAI-compatible endpoint.

Each step the agent sends the instruction and its image-text interleaved history (the last
``history`` frames as base64 PNG data URLs, each followed by the action it took, in the
paper's ``Observation: <image> Action: <code>`` form) to a chat completions endpoint, and
parses the reply as action code (:func:`legent_gym.agent.actions.parse_actions`).

It is a :class:`baselines.evaluate.Policy`: ``reset(instruction)``, ``act(obs) -> str``.

What can go wrong, and what happens:

* the endpoint times out, refuses the connection, answers HTTP 429 or 5xx, or answers
  something that is not a chat completion (not JSON, no ``choices``): the request is retried
  up to ``max_retries`` times with exponential backoff (a ``Retry-After`` header is honoured
  up to ``max_backoff``); then :class:`EndpointError` names the URL and the last failure;
* HTTP 4xx other than 408/409/429 (a wrong key, model or URL): :class:`EndpointError` at once;
* the reply is not valid action code: the parse error is fed back to the model and it is
  asked again, up to ``parse_retries`` times; then the agent falls back to
  :data:`NOOP_ACTION` (``rotate_right(0)``: a valid step that changes nothing, as LEGENT's
  GPT-4V client skipped unparsable replies) and records why in ``agent.steps``.

Configuration: ``base_url`` (else ``$OPENAI_BASE_URL``, else OpenAI's), ``api_key`` (else
``$OPENAI_API_KEY``; a local endpoint needs none), ``model``, ``timeout`` (seconds per
request). From the shell::

    python baselines/llm_agent.py --env Legent/ComeHere-OneRoom-v0 \\
        --base-url http://127.0.0.1:8000/v1 --model my-vlm --episodes 10 --seed 0
"""

from __future__ import annotations

import argparse
import base64
import io
import json
import re
import sys
from collections import deque
from collections.abc import Sequence
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

if __package__ in (None, ""):  # run as a file: make the repository root importable
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import numpy as np  # noqa: E402
from PIL import Image  # noqa: E402

from baselines.episodes import run_episodes  # noqa: E402
from legent_gym.agent.actions import ActionLimits, ActionParseError, format_actions, parse_actions  # noqa: E402
from legent_gym.llm import ChatClient, EndpointError  # noqa: E402
from legent_gym.utils.atomic import atomic_write_text  # noqa: E402

NOOP_ACTION = "rotate_right(0)"
"""What the agent does when no reply parses: a valid step that changes nothing."""

SYSTEM_PROMPT = """\
You are an embodied agent in a house, seeing through a camera on your head. A user in the \
same house gives you an instruction. At each step you are shown your trajectory so far as \
"Observation: <image> Action: <code>" and you write the code of your next action.

Actions (one or more per step, joined by ", ", run in order):
- move_forward(metres): walk straight ahead, at most {max_move:g} m; you stop at obstacles.
- rotate_right(degrees): turn, at most {max_turn:g} degrees either way; negative turns left.
- rotate_down(degrees): tilt your head; negative looks up.
- grab(), put(), open(), close(): act on what is at the centre of your view, within reach.
- speak("text"): say something to the user.
- finish(): declare the task done.
Write arguments as plain values: move_forward(1.5), not move_forward(meters=1.5).
Reply with the action code only, for example: move_forward(1.5), rotate_right(-30)

The user's instruction: {instruction}"""

_FEEDBACK = ("That reply is not valid action code ({error}). Reply with the action code only, "
             "for example: move_forward(1.5), rotate_right(-30)")
_FENCE = re.compile(r"^```[A-Za-z]*\s*|\s*```$")
_PREFIX = re.compile(r"^\s*(?:action\s*:\s*)", re.IGNORECASE)


@dataclass
class StepTrace:
    """What happened in one ``act()``: for analysis and for the CLI's ``--trace`` file."""

    episode: int
    step: int
    action: str
    replies: list[str] = field(default_factory=list)
    requests: int = 0  # HTTP requests sent, retries included
    errors: list[str] = field(default_factory=list)  # transport failures that were retried
    fallback: str | None = None  # why NOOP_ACTION was used, when it was


def extract_action(reply: str) -> str:
    """The canonical action code in a model's reply; ``ActionParseError`` if there is none.

    Tolerates what chat models add around code: a code fence, an ``Action:`` prefix, or a
    line of explanation before or after (the first line that parses wins).
    """
    text = _FENCE.sub("", reply.strip()).strip()
    candidates = [text, *(line for line in text.splitlines() if line.strip())]
    first_error: ActionParseError | None = None
    for candidate in candidates:
        code = _PREFIX.sub("", candidate).strip().strip("`").strip()
        try:
            return format_actions(parse_actions(code))
        except ActionParseError as err:
            first_error = first_error or err
    raise first_error  # candidates always holds the whole reply, so this is set


def image_data_url(frame: np.ndarray) -> str:
    """An RGB frame as a ``data:image/png;base64,...`` URL."""
    buffer = io.BytesIO()
    Image.fromarray(np.ascontiguousarray(frame, dtype=np.uint8)).save(buffer, format="PNG")
    return "data:image/png;base64," + base64.b64encode(buffer.getvalue()).decode("ascii")


class ChatEndpoint:
    """One OpenAI-compatible chat completions endpoint: :class:`legent_gym.llm.ChatClient`
    (retries, backoff, errors naming the URL) with the agent's reply length and temperature."""

    def __init__(self, base_url: str | None = None, api_key: str | None = None, *, model: str,
                 timeout: float = 60.0, max_retries: int = 3, backoff: float = 1.0, max_backoff: float = 30.0,
                 max_tokens: int = 64, temperature: float = 0.0):
        self.client = ChatClient(base_url, api_key, model=model, timeout=timeout, max_retries=max_retries,
                                 backoff=backoff, max_backoff=max_backoff)
        self.base_url, self.model = self.client.base_url, model
        self.timeout, self.max_retries = self.client.timeout, max_retries
        self.max_tokens, self.temperature = max_tokens, temperature

    def complete(self, messages: list[dict[str, Any]], trace: StepTrace) -> str:
        """The reply's text (``""`` if the message has none). Retries transient failures;
        raises :class:`EndpointError` naming the URL when they persist or are not transient."""
        return self.client.complete(messages, max_tokens=self.max_tokens, temperature=self.temperature, log=trace)


class LLMAgent:
    """A policy that asks a multimodal chat model for every action (see the module docstring).

    Args:
        endpoint: where to ask (:class:`ChatEndpoint`); or pass its keyword arguments
            (``base_url``, ``api_key``, ``model``, ``timeout``, ``max_retries``, ...).
        history: frames sent per request, newest last (the paper: 6).
        parse_retries: how often an unparsable reply is answered with the parse error.
        limits: the action limits quoted in the prompt.
    """

    def __init__(self, endpoint: ChatEndpoint | None = None, *, history: int = 6, parse_retries: int = 2,
                 limits: ActionLimits | None = None, system_prompt: str = SYSTEM_PROMPT, **endpoint_kwargs: Any):
        if endpoint is None:
            endpoint = ChatEndpoint(**endpoint_kwargs)
        elif endpoint_kwargs:
            raise TypeError(f"pass an endpoint or its arguments, not both: {sorted(endpoint_kwargs)}")
        if history < 1:
            raise ValueError(f"history must be >= 1 frame, got {history}")
        if parse_retries < 0:
            raise ValueError(f"parse_retries must be >= 0, got {parse_retries}")
        self.endpoint, self.history, self.parse_retries = endpoint, history, parse_retries
        self.limits, self.system_prompt = limits or ActionLimits(), system_prompt
        self.instruction: str | None = None
        self.steps: list[StepTrace] = []  # every act() of every episode, in order
        self._episode, self._step = -1, 0
        self._window: deque[list] = deque(maxlen=history)  # [image data URL, action or None]

    def reset(self, instruction: str) -> None:
        self.instruction = instruction
        self._episode += 1
        self._step = 0
        self._window.clear()

    def act(self, observation: dict[str, Any]) -> str:
        if self.instruction is None:
            raise RuntimeError("call reset(instruction) before act()")
        self._window.append([image_data_url(observation["rgb"]), None])
        trace = StepTrace(self._episode, self._step, NOOP_ACTION)
        self._step += 1
        messages = self.messages()
        for attempt in range(1 + self.parse_retries):
            reply = self.endpoint.complete(messages, trace)
            trace.replies.append(reply)
            try:
                trace.action = extract_action(reply)
                break
            except ActionParseError as err:
                if attempt == self.parse_retries:
                    trace.fallback = f"no valid action code in {len(trace.replies)} replies (last error: {err})"
                else:
                    messages = [*messages, {"role": "assistant", "content": reply},
                                {"role": "user", "content": _FEEDBACK.format(error=err)}]
        self._window[-1][1] = trace.action
        self.steps.append(trace)
        return trace.action

    def messages(self) -> list[dict[str, Any]]:
        """The chat request for the current step: the prompt, then the interleaved history."""
        system = self.system_prompt.format(instruction=self.instruction, max_move=self.limits.max_move,
                                           max_turn=self.limits.max_rotate_right)
        content: list[dict[str, Any]] = []
        for url, action in self._window:
            content.append({"type": "text", "text": "Observation:"})
            content.append({"type": "image_url", "image_url": {"url": url}})
            content.append({"type": "text", "text": f"Action: {action}\n" if action else "Action:"})
        return [{"role": "system", "content": system}, {"role": "user", "content": content}]


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description="Evaluate a multimodal LLM agent through an OpenAI-compatible "
                                                 "chat endpoint.")
    parser.add_argument("--env", default="Legent/ComeHere-OneRoom-v0")
    parser.add_argument("--base-url", default=None, help="default: $OPENAI_BASE_URL, else OpenAI's")
    parser.add_argument("--api-key", default=None, help="default: $OPENAI_API_KEY (a local endpoint needs none)")
    parser.add_argument("--model", default="gpt-4o")
    parser.add_argument("--episodes", type=int, default=10)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--camera", choices=["default", "paper"], default="default",
                        help="'paper': LEGENT's 448 x 448, 120 degree evaluation camera")
    parser.add_argument("--history", type=int, default=6, help="frames per request (the paper: 6)")
    parser.add_argument("--timeout", type=float, default=60.0, help="seconds per request")
    parser.add_argument("--retries", type=int, default=3, help="retries of a failed request")
    parser.add_argument("--parse-retries", type=int, default=2, help="re-asks after a reply that does not parse")
    parser.add_argument("--trace", type=Path, default=None, help="write every step (replies, errors) as JSON lines")
    args = parser.parse_args(argv)

    try:
        agent = LLMAgent(base_url=args.base_url, api_key=args.api_key, model=args.model, timeout=args.timeout,
                         max_retries=args.retries, history=args.history, parse_retries=args.parse_retries)
    except ValueError as err:
        print(f"error: {err}", file=sys.stderr)
        return 2
    try:
        results = run_episodes(agent, args.env, args.episodes, args.seed, {"camera": args.camera})
    except (EndpointError, ValueError) as err:
        print(f"error: {err}", file=sys.stderr)
        return 2
    finally:  # the steps taken so far are worth keeping, also after an error
        if args.trace is not None:
            atomic_write_text(args.trace, "".join(json.dumps(asdict(s)) + "\n" for s in agent.steps))
    for r in results:
        print(f"episode seed {r.seed}: {'success' if r.success else 'failure'} in {r.steps} steps ({r.instruction!r})")
    rate = sum(r.success for r in results) / len(results)
    fallbacks = sum(s.fallback is not None for s in agent.steps)
    print(f"{args.model} on {args.env}: success {rate:.3f} over {len(results)} episodes (seed {args.seed}); "
          f"{fallbacks} of {len(agent.steps)} steps fell back to {NOOP_ACTION}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

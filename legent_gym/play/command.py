"""``legent-gym play``: its arguments and what it runs (the server's modules are imported
only when the command runs)."""

from __future__ import annotations

import argparse
import asyncio
import contextlib
import os
import sys
from pathlib import Path
from typing import Any

import gymnasium as gym

from legent_gym.errors import UserError
from legent_gym.play.session import PARTNERS, PlaySession, is_partner


def parse_size(text: str) -> tuple[int, int]:
    """``"640x480"`` -> ``(640, 480)``."""
    width, sep, height = text.lower().partition("x")
    try:
        size = (int(width), int(height))
    except ValueError:
        size = (0, 0)
    if not sep or not (16 <= size[0] <= 4096 and 16 <= size[1] <= 4096):
        raise argparse.ArgumentTypeError(f"--size must be WxH, each 16 to 4096 pixels, got {text!r}")
    return size


def partner_spec(text: str) -> str:
    if not is_partner(text):
        raise argparse.ArgumentTypeError(f"--partner must be one of {', '.join(PARTNERS)} or "
                                         f"module:function[:ARGUMENT], got {text!r}")
    return text


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("env_id", help="e.g. Legent/ComeHere-OneRoom-v0")
    p.add_argument("--as", dest="role", choices=["user", "agent"], default="user",
                   help="whom the person plays (default: the user; the partner drives the agent)")
    p.add_argument("--partner", type=partner_spec, default="expert",
                   help="the policy that drives the agent when the person is the user: expert, random, llm, "
                        "or module:function[:ARGUMENT] (returns a policy with reset(instruction) and act(observation); "
                        "e.g. baselines.vla.policy:partner:CHECKPOINT, a model trained by baselines/vla)")
    p.add_argument("--host", default="127.0.0.1", help="address to listen on (default 127.0.0.1, loopback only)")
    p.add_argument("--allow-remote", action="store_true",
                   help="needed for a --host that is not a loopback address (anyone who can reach it and has the "
                        "URL's token can play)")
    p.add_argument("--port", type=int, default=8765, help="port (0: any free port)")
    p.add_argument("--size", type=parse_size, default=(640, 480), help="the view's size, WxH (default 640x480)")
    p.add_argument("--record", help="as the agent: write every episode to DIR in the LEGENT and Minari formats")
    p.add_argument("--sessions", type=int, default=1, help="sessions (browser tabs) played at once")
    p.add_argument("--seed", type=int, default=0, help="the first episode's seed (a new house: the next seed)")
    p.add_argument("--fps", type=float, default=30.0, help="the most frames per second streamed")
    p.add_argument("--tick", type=float, default=0.6,
                   help="as the user: seconds between the agent's own steps while you wait")
    p.add_argument("--max-cycles", type=int, default=200, help="as the user: steps before the episode truncates")
    p.add_argument("--llm-url", default=os.environ.get("OPENAI_BASE_URL", ""),
                   help="--partner llm: an OpenAI-compatible endpoint (default $OPENAI_BASE_URL)")
    p.add_argument("--llm-model", default="gpt-4o-mini", help="--partner llm: the model name")


def make_server(args: Any) -> Any:
    """The :class:`~legent_gym.play.server.PlayServer` the arguments describe."""
    # websockets (the play extra) is imported only to serve.
    from legent_gym.play.server import PlayServer, is_loopback
    if not is_loopback(args.host) and not args.allow_remote:
        raise UserError(f"--host {args.host} is not a loopback address: add --allow-remote to listen there")
    if args.record and args.role != "agent":
        raise UserError("--record needs --as agent (the recorded actions are the person's)")
    if args.sessions < 1:
        raise UserError(f"--sessions must be >= 1, got {args.sessions}")
    record = Path(args.record) if args.record else None
    llm_key = os.environ.get("OPENAI_API_KEY", "")

    def factory() -> PlaySession:
        return PlaySession(args.env_id, role=args.role, partner=args.partner, size=args.size, record=record,
                           seed=args.seed, max_cycles=args.max_cycles, llm_url=args.llm_url,
                           llm_model=args.llm_model, llm_key=llm_key)

    return PlayServer(factory, host=args.host, port=args.port, sessions=args.sessions, fps=args.fps, tick=args.tick)


def run(args: Any) -> int:
    """Start the server, print the URL, serve until interrupted."""
    if args.env_id not in gym.registry:
        raise UserError(f"unknown env id {args.env_id!r} (legent-gym ids look like Legent/ComeHere-OneRoom-v0)")
    server = make_server(args)
    from legent_gym.play.server import is_loopback  # the play extra, as in make_server

    if not is_loopback(args.host):
        print(f"legent-gym: warning: listening on {args.host}, not loopback: anyone who can reach it "
              "and has the URL's token can play", file=sys.stderr)

    async def main() -> None:
        await server.start()
        print(f"play {args.env_id} as the {args.role} at {server.url}", flush=True)
        try:
            await server.serve_forever()
        finally:
            await server.stop()

    with contextlib.suppress(KeyboardInterrupt):
        asyncio.run(main())
    return 0

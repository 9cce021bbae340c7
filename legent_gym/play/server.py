"""The play server: one HTTP page and one WebSocket per session (``websockets``, asyncio).

Routes (every one but ``/static/`` needs the server's token in the query string, ``?token=``;
a wrong or missing token gets HTTP 403):

* ``GET /``: the page (``static/index.html``);
* ``GET /static/play.js``, ``/static/play.css``: its script and style;
* ``GET /ws`` (WebSocket): the session.

Messages on the WebSocket. Server -> page: binary messages are JPEG frames of the person's
view; text messages are JSON objects with a ``type``: ``hello`` (keys, role, sizes),
``map`` (the top-down map as a PNG data URL and its world -> pixel transform), ``state``
(:meth:`~legent_gym.play.session.PlaySession.state`), ``error`` (``message``; the session
goes on). Page -> server: JSON objects of at most :data:`MAX_MESSAGE` bytes, of the types
``key`` (``key``: a name of :data:`~legent_gym.play.session.KEY_ACTIONS`), ``action``
(``code``: action code), ``say`` (``text``), ``reset`` (``same_house``: bool), ``wait`` (the person does nothing: the agent
acts), ``ack``
(a frame was drawn: the server keeps at most :data:`FRAMES_IN_FLIGHT` frames unacknowledged)
and ``ping``. Anything else (binary data, bad JSON, an unknown type, an oversized
message) is answered with an ``error`` message and otherwise ignored.

All env work (stepping, rendering, encoding) runs on one worker thread, which holds the
process's OpenGL context; a closed connection closes its session's env there.
"""

from __future__ import annotations

import asyncio
import contextlib
import ipaddress
import json
import secrets
import time
import urllib.parse
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from importlib import resources
from typing import Any

from websockets.asyncio.server import Server, ServerConnection, serve
from websockets.datastructures import Headers
from websockets.exceptions import ConnectionClosed
from websockets.http11 import Request, Response

from legent_gym.play.session import KEY_ACTIONS, MAX_TEXT, PlaySession

#: The largest page -> server message the session reads (larger ones get an error).
MAX_MESSAGE = 64 * 1024
#: The largest message the connection accepts at all (larger ones close it, code 1009).
MAX_FRAME = 32 * 1024 * 1024
#: Frames sent and not yet acknowledged by the page.
FRAMES_IN_FLIGHT = 2
#: Seconds a connection waits for a session to free before it is told the server is busy: a
#: reloaded page connects again while its old session is still closing its env.
SESSION_GRACE = 5.0
STATIC_FILES = {"index.html": "text/html; charset=utf-8", "play.js": "text/javascript; charset=utf-8",
                "play.css": "text/css; charset=utf-8"}
CSP = ("default-src 'self'; img-src 'self' data: blob:; connect-src 'self' ws: wss:; "
       "style-src 'self'; script-src 'self'; object-src 'none'; base-uri 'none'; frame-ancestors 'none'")


def is_loopback(host: str) -> bool:
    """Whether ``host`` (an address or ``localhost``) is a loopback address."""
    if host == "localhost":
        return True
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        return False


def static_file(name: str) -> bytes:
    return (resources.files("legent_gym.play") / "static" / name).read_bytes()


def _response(status: int, reason: str, body: bytes, content_type: str = "text/plain; charset=utf-8") -> Response:
    headers = Headers([("Content-Type", content_type), ("Content-Length", str(len(body))),
                       ("Cache-Control", "no-store"), ("X-Content-Type-Options", "nosniff"),
                       ("Referrer-Policy", "no-referrer"), ("Content-Security-Policy", CSP)])
    return Response(status, reason, headers, body)


class PlayServer:
    """Serves sessions made by ``factory`` (at most ``sessions`` at a time) on
    ``host:port`` (port 0: any free port). ``fps``: the most frames per second sent;
    ``tick``: seconds between the agent's own steps while the person waits."""

    def __init__(self, factory: Callable[[], PlaySession], *, host: str = "127.0.0.1", port: int = 0,
                 sessions: int = 1, fps: float = 30.0, tick: float = 0.6, token: str | None = None):
        if sessions < 1:
            raise ValueError(f"sessions must be >= 1, got {sessions}")
        if not fps > 0:
            raise ValueError(f"fps must be > 0, got {fps}")
        self.factory, self.host, self.port = factory, host, int(port)
        self.max_sessions, self.fps, self.tick = int(sessions), float(fps), float(tick)
        self.token = token or secrets.token_urlsafe(18)
        self.free = asyncio.Semaphore(self.max_sessions)  # one unit per session that may start
        self.executor = ThreadPoolExecutor(max_workers=1, thread_name_prefix="legent-play-env")
        self.server: Server | None = None

    # -- lifetime ---------------------------------------------------------------------------------
    async def start(self) -> None:
        self.server = await serve(self._session, self.host, self.port, process_request=self._http,
                                  max_size=MAX_FRAME, compression=None, ping_interval=20, ping_timeout=20)
        self.port = int(self.server.sockets[0].getsockname()[1])

    @property
    def url(self) -> str:
        host = f"[{self.host}]" if ":" in self.host else self.host
        return f"http://{host}:{self.port}/?token={self.token}"

    async def serve_forever(self) -> None:
        if self.server is None:
            await self.start()
        assert self.server is not None
        await self.server.serve_forever()

    async def stop(self) -> None:
        if self.server is not None:
            self.server.close()
            await self.server.wait_closed()
        self.executor.shutdown(wait=True)

    async def run(self, fn: Callable[..., Any], *args: Any) -> Any:
        """``fn(*args)`` on the env thread."""
        return await asyncio.get_running_loop().run_in_executor(self.executor, fn, *args)

    # -- HTTP -----------------------------------------------------------------------------------
    def _http(self, connection: ServerConnection, request: Request) -> Response | None:
        url = urllib.parse.urlsplit(request.path)
        query = urllib.parse.parse_qs(url.query)
        token_ok = secrets.compare_digest(query.get("token", [""])[0].encode(), self.token.encode())
        if url.path.startswith("/static/"):
            name = url.path[len("/static/"):]
            if name not in STATIC_FILES or name == "index.html":
                return _response(404, "Not Found", b"not found\n")
            return _response(200, "OK", static_file(name), STATIC_FILES[name])
        if url.path == "/favicon.ico":
            return _response(204, "No Content", b"")
        if url.path not in ("/", "/ws"):
            return _response(404, "Not Found", b"not found\n")
        if not token_ok:
            return _response(403, "Forbidden", b"wrong or missing token: use the URL legent-gym play printed\n")
        if url.path == "/":
            return _response(200, "OK", static_file("index.html"), STATIC_FILES["index.html"])
        return None  # /ws with the right token: the WebSocket handshake goes on

    # -- the WebSocket session ------------------------------------------------------------------
    async def _session(self, ws: ServerConnection) -> None:
        try:
            await asyncio.wait_for(self.free.acquire(), SESSION_GRACE)
        except TimeoutError:
            await _send_json(ws, {"type": "error", "fatal": True,
                                  "message": f"this server plays {self.max_sessions} session(s) at a time and "
                                             "all are taken (close the other tab, or start it with --sessions N)"})
            await ws.close(1013, "busy")
            return
        session: PlaySession | None = None
        try:
            try:
                session = await self.run(self.factory)
            except Exception as err:  # the env could not be made: say why on the page
                await _send_json(ws, {"type": "error", "fatal": True, "message": f"could not start: {err}"})
                return
            await self._play(ws, session)
        finally:
            if session is not None:
                with contextlib.suppress(Exception):
                    await self.run(session.close)
            self.free.release()

    async def _play(self, ws: ServerConnection, session: PlaySession) -> None:
        link = _Link(ws, session, self)
        await _send_json(ws, {"type": "hello", "role": session.role, "keys": KEY_ACTIONS,
                              "width": session.width, "height": session.height, "fps": self.fps})
        await link.send_map()
        await link.send_state()
        tasks = [asyncio.create_task(link.frames()), asyncio.create_task(link.ticks())]
        try:
            async for message in ws:
                await link.handle(message)
        except ConnectionClosed:
            pass
        finally:
            for task in tasks:
                task.cancel()
            for task in tasks:
                with contextlib.suppress(asyncio.CancelledError, ConnectionClosed, Exception):
                    await task


async def _send_json(ws: ServerConnection, message: dict[str, Any]) -> None:
    await ws.send(json.dumps(message))


class _Link:
    """One connection's traffic: the frame stream, the agent's ticks, the page's messages."""

    def __init__(self, ws: ServerConnection, session: PlaySession, server: PlayServer):
        self.ws, self.session, self.server = ws, session, server
        self.credits = FRAMES_IN_FLIGHT
        self.credit = asyncio.Event()
        self.credit.set()
        self.sent_version = -1
        self.map_seed: tuple[int, int] | None = None
        self.last_action = time.monotonic()
        self.lock = asyncio.Lock()  # one env call at a time per session (the ticks and the page's)

    async def send_state(self) -> None:
        state = await self.server.run(self.session.state)
        self.sent_version = state["version"]
        await _send_json(self.ws, state)

    async def send_map(self) -> None:
        await _send_json(self.ws, {"type": "map", **self.session.map})

    async def error(self, message: str) -> None:
        await _send_json(self.ws, {"type": "error", "message": message})

    async def frames(self) -> None:
        period = 1.0 / self.server.fps
        while True:
            await self.credit.wait()
            began = time.monotonic()
            async with self.lock:
                jpeg = await self.server.run(self.session.jpeg)
            self.credits -= 1
            if self.credits <= 0:
                self.credit.clear()
            await self.ws.send(jpeg)
            await asyncio.sleep(max(0.0, period - (time.monotonic() - began)))

    async def ticks(self) -> None:
        """The agent acts on its own while the person waits (user mode)."""
        if self.session.role != "user":
            return
        while True:
            await asyncio.sleep(self.server.tick / 2)
            if time.monotonic() - self.last_action < self.server.tick:
                continue
            async with self.lock:
                stepped = await self.server.run(self.session.tick)
            if stepped:
                await self.send_state()

    async def handle(self, message: str | bytes) -> None:
        if isinstance(message, bytes):
            await self.error(f"binary messages are not accepted ({len(message)} bytes ignored)")
            return
        if len(message) > MAX_MESSAGE:
            await self.error(f"message too large ({len(message)} characters; at most {MAX_MESSAGE})")
            return
        try:
            data = json.loads(message)
        except ValueError as err:
            await self.error(f"not JSON: {err}")
            return
        if not isinstance(data, dict) or not isinstance(data.get("type"), str):
            await self.error("a message is a JSON object with a string 'type'")
            return
        kind = data["type"]
        if kind == "ack":
            self.credits = min(FRAMES_IN_FLIGHT, self.credits + 1)
            self.credit.set()
            return
        if kind == "ping":
            await _send_json(self.ws, {"type": "pong"})
            return
        if kind == "key":
            key = data.get("key")
            if not isinstance(key, str) or key not in KEY_ACTIONS:
                await self.error(f"unknown key {str(key)[:40]!r}; known: {', '.join(KEY_ACTIONS)}")
                return
            await self._step(self.session.act, KEY_ACTIONS[key])
        elif kind in ("action", "say"):
            field = "code" if kind == "action" else "text"
            text = data.get(field)
            if not isinstance(text, str) or len(text) > MAX_TEXT:
                await self.error(f"'{kind}' needs a string '{field}' of at most {MAX_TEXT} characters")
                return
            await self._step(self.session.act if kind == "action" else self.session.say, text)
        elif kind == "wait":
            await self._step(lambda _: self.session.tick(), None)
        elif kind == "reset":
            same = data.get("same_house", False)
            if not isinstance(same, bool):
                await self.error("'reset' takes 'same_house': true or false")
                return
            await self._step(self.session.reset, not same)
            await self.send_map()
        else:
            await self.error(f"unknown message type {kind[:40]!r}")
            return
        await self.send_state()

    async def _step(self, fn: Callable[[Any], Any], arg: Any) -> None:
        self.last_action = time.monotonic()
        async with self.lock:
            try:
                await self.server.run(fn, arg)
            except Exception as err:  # an env error: reported, the session goes on
                await self.error(f"{type(err).__name__}: {err}")
        self.last_action = time.monotonic()

"""``legent-gym play``: the real server (started as a user starts it), the real env, and a
real headless Chromium (Debian's ``chromium`` package) driven by Playwright.

The browser tests are skipped only where no Chromium executable can be found."""

from __future__ import annotations

import contextlib
import json
import os
import re
import shutil
import socket
import subprocess
import sys
import time
import urllib.error
import urllib.request
from collections.abc import Iterator
from pathlib import Path

import pytest
import websockets.sync.client as ws_client
from websockets.exceptions import InvalidStatus

from legent_gym.cli import main as cli_main

ROOT = Path(__file__).resolve().parents[2]
CHROMIUM = os.environ.get("LEGENT_CHROMIUM") or shutil.which("chromium") or "/usr/bin/chromium"
HAVE_CHROMIUM = os.path.exists(CHROMIUM)
CHROMIUM_ARGS = ["--no-sandbox", "--headless", "--disable-gpu", "--no-first-run", "--disable-background-networking",
                 "--disable-component-update", "--disable-sync"]
needs_browser = pytest.mark.skipif(not HAVE_CHROMIUM, reason=f"no Chromium at {CHROMIUM} (Debian: apt-get install "
                                                             "chromium; scripts/setup.sh does it with the play extra)")
SMALL = "160x120"


@contextlib.contextmanager
def play_server(env_id: str, *args: str) -> Iterator[str]:
    """``legent-gym play ENV_ID --port 0 ARGS`` in a child process; yields the URL it prints."""
    cmd = [sys.executable, "-m", "legent_gym.cli", "play", env_id, "--port", "0", *args]
    proc = subprocess.Popen(cmd, cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        assert proc.stdout is not None
        line = proc.stdout.readline()  # the server prints its URL once it listens
        match = re.search(r"http://\S+", line)
        if match is None:
            proc.kill()
            raise AssertionError(f"no URL from {' '.join(cmd)}: {line!r} {proc.stderr.read() if proc.stderr else ''}")
        yield match.group(0)
    finally:
        proc.terminate()
        try:
            proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()


def ws_url(url: str, token: str | None = None) -> str:
    base, _, query = url.partition("/?")
    real = query.split("token=", 1)[1]
    return base.replace("http://", "ws://") + f"/ws?token={real if token is None else token}"


def port_of(url: str) -> int:
    return int(url.split(":")[2].split("/")[0])


def receive_json(ws, kind: str | None = None, timeout: float = 20.0) -> dict:
    """The next JSON message (of ``kind``), skipping frames and other messages."""
    deadline = time.monotonic() + timeout
    while True:
        message = ws.recv(timeout=max(0.01, deadline - time.monotonic()))
        if isinstance(message, bytes):
            continue
        data = json.loads(message)
        if kind is None or data["type"] == kind:
            return data


# -- the command line and the server, without a browser -----------------------------------------
def test_non_loopback_host_needs_the_flag(capsys):
    assert cli_main(["play", "Legent/ComeHere-OneRoom-v0", "--host", "0.0.0.0"]) == 2
    assert "--allow-remote" in capsys.readouterr().err
    assert cli_main(["play", "Legent/ComeHere-OneRoom-v0", "--as", "user", "--record", "x"]) == 2
    assert cli_main(["play", "Legent/NoSuchTask-v0"]) == 2


def _listening_addresses(port: int) -> list[str]:
    """Local addresses of the sockets listening on ``port`` (from /proc/net/tcp, tcp6)."""
    found = []
    for name in ("tcp", "tcp6"):
        path = Path("/proc/net") / name
        if not path.exists():
            continue
        for row in path.read_text().splitlines()[1:]:
            local, state = row.split()[1], row.split()[3]
            address, port_hex = local.split(":")
            if state == "0A" and int(port_hex, 16) == port:
                found.append(address)
    return found


def _non_loopback_ip() -> str | None:
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
        try:
            s.connect(("10.255.255.255", 1))  # no packet is sent: this picks the outgoing interface
            ip = s.getsockname()[0]
        except OSError:
            return None
    return None if ip.startswith("127.") else ip


def test_server_is_loopback_only_guards_the_token_and_survives_hostile_messages():
    with play_server("Legent/ComeHere-OneRoom-v0", "--size", SMALL) as url:
        port = port_of(url)
        assert url.startswith("http://127.0.0.1:")
        addresses = _listening_addresses(port)
        assert addresses and all(a == "0100007F" for a in addresses), addresses  # 127.0.0.1 only
        ip = _non_loopback_ip()
        if ip is not None:
            with pytest.raises(OSError), socket.create_connection((ip, port), timeout=2):
                pass
        # the token guards the page and the WebSocket
        page = urllib.request.urlopen(url, timeout=10).read().decode()
        assert "/static/play.js" in page and "https://" not in page  # everything is served here
        for bad in (url.split("?")[0], url.split("?")[0] + "?token=wrong"):
            with pytest.raises(urllib.error.HTTPError) as err:
                urllib.request.urlopen(bad, timeout=10)
            assert err.value.code == 403
        with pytest.raises(InvalidStatus) as status, ws_client.connect(ws_url(url, "wrong"), open_timeout=10):
            pass
        assert status.value.response.status_code == 403

        with ws_client.connect(ws_url(url), max_size=None, open_timeout=30) as ws:
            hello = receive_json(ws, "hello", timeout=60)
            assert hello["role"] == "user" and "forward" in hello["keys"]
            first = receive_json(ws, "state")
            assert first["actions_used"] == 0
            frame = ws.recv(timeout=20)
            assert isinstance(frame, bytes) and frame[:2] == b"\xff\xd8"  # a JPEG

            # one session per server: a second tab is told so and closed
            with ws_client.connect(ws_url(url), open_timeout=10) as other:
                busy = receive_json(other, "error")
                assert busy.get("fatal") and "--sessions" in busy["message"]

            junk = os.urandom(4096)
            hostile = [junk, "not json {", "[1, 2]", '{"type": 5}', '{"type": "teleport"}',
                       '{"type": "key", "key": "fly"}', '{"type": "action", "code": 12}',
                       '{"type": "reset", "same_house": "yes"}', json.dumps({"type": "say", "text": "x" * 600}),
                       "\x00" * 100]
            big_binary, big_text = os.urandom(10 * 1024 * 1024), "a" * (10 * 1024 * 1024)
            for i in range(1000):
                message = big_binary if i % 100 == 0 else big_text if i % 100 == 50 else hostile[i % len(hostile)]
                ws.send(message)
                error = receive_json(ws, "error")
                assert error["message"], message[:40]
            # the session goes on
            ws.send(json.dumps({"type": "key", "key": "left"}))
            state = receive_json(ws, "state")
            assert state["actions_used"] == 1 and state["result"] == "rotate_right(-30): ok"
            ws.send(json.dumps({"type": "ack"}))
            deadline = time.monotonic() + 20
            while not isinstance(frame := ws.recv(timeout=20), bytes):
                assert time.monotonic() < deadline
            assert frame[:2] == b"\xff\xd8"
        # the closed connection freed its session: a new one starts afresh
        with ws_client.connect(ws_url(url), open_timeout=30) as ws:
            assert receive_json(ws, "hello", timeout=60)["role"] == "user"
            assert receive_json(ws, "state")["actions_used"] == 0


# -- the page in a real browser -----------------------------------------------------------------
@pytest.fixture(scope="module")
def browser():
    if not HAVE_CHROMIUM:
        pytest.skip(f"no Chromium at {CHROMIUM}")
    from playwright.sync_api import sync_playwright

    with sync_playwright() as p:
        b = p.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
        yield b
        b.close()


@contextlib.contextmanager
def open_page(browser, url: str):
    # Playwright's waits evaluate strings, which the page's Content-Security-Policy forbids
    # to the page's own scripts: the test's context bypasses the policy.
    context = browser.new_context(bypass_csp=True, viewport={"width": 1280, "height": 820})
    page = context.new_page()
    page.goto(url)
    page.wait_for_function("window.play && window.play.frames >= 2 && window.play.state && window.play.map",
                           timeout=60_000)
    try:
        yield page
    finally:
        context.close()


def canvas(page, name: str) -> str:
    return page.evaluate(f"document.getElementById('{name}').toDataURL()")


def press_and_wait(page, key: str) -> dict:
    """Press ``key``, wait until the step is reported and a later frame is drawn."""
    used = page.evaluate("window.play.state.actions_used")
    page.keyboard.press(key)
    page.wait_for_function(f"window.play.state.actions_used > {used}", timeout=20_000)
    frames = page.evaluate("window.play.frames")
    page.wait_for_function(f"window.play.frames >= {frames + 3}", timeout=20_000)
    return page.evaluate("window.play.state")


def say(page, text: str) -> None:
    page.keyboard.press("Enter")  # Enter: to the chat box
    page.keyboard.type(text)
    page.keyboard.press("Enter")


def test_a_reloaded_page_gets_the_session_its_old_tab_is_still_closing():
    """A page that reconnects while its old session is still closing its env (a reload) waits
    for that session to end and plays; it is not told the server is busy."""
    import asyncio
    import threading

    from legent_gym.play.server import PlayServer
    from legent_gym.play.session import PlaySession

    closed: list[float] = []

    class SlowToClose(PlaySession):
        def close(self) -> None:
            time.sleep(1.5)  # what an env under load can take
            super().close()
            closed.append(time.monotonic())

    server = PlayServer(lambda: SlowToClose("Legent/ComeHere-OneRoom-v0", size=(160, 120)))
    loop = asyncio.new_event_loop()
    started = threading.Event()

    def serve() -> None:
        asyncio.set_event_loop(loop)
        loop.run_until_complete(server.start())
        started.set()
        loop.run_forever()

    thread = threading.Thread(target=serve, daemon=True)
    thread.start()
    assert started.wait(60)
    try:
        with ws_client.connect(ws_url(server.url), open_timeout=30) as ws:
            assert receive_json(ws, "hello", timeout=60)["role"] == "user"
        left = time.monotonic()
        with ws_client.connect(ws_url(server.url), open_timeout=30) as ws:
            hello = receive_json(ws, timeout=60)
            assert hello["type"] == "hello", hello  # not {"type": "error", "fatal": true, ...busy}
            assert closed and closed[0] > left  # it did wait for the old session
    finally:
        asyncio.run_coroutine_threadsafe(server.stop(), loop).result(timeout=60)
        loop.call_soon_threadsafe(loop.stop)
        thread.join(timeout=10)


@needs_browser
def test_page_as_user_keys_map_and_expert_finishes_come_here(browser):
    with play_server("Legent/ComeHere-OneRoom-v0", "--size", SMALL, "--seed", "3") as url, \
            open_page(browser, url) as page:
        assert page.inner_text("#keys").count("\n") >= 7  # the controls are shown
        start = page.evaluate("window.play.state")
        view0, map0 = canvas(page, "view"), canvas(page, "map")
        turned = press_and_wait(page, "d")
        assert turned["user_pose"][2] != start["user_pose"][2]
        assert canvas(page, "view") != view0  # the view changed
        moved = turned
        for key in ("w", "d", "w", "d", "w"):
            moved = press_and_wait(page, key)
            if abs(moved["user_pose"][0] - start["user_pose"][0]) + abs(moved["user_pose"][1] - start["user_pose"][1]) > 0.2:
                break
        assert abs(moved["user_pose"][0] - start["user_pose"][0]) + abs(moved["user_pose"][1] - start["user_pose"][1]) > 0.2
        assert canvas(page, "map") != map0  # the user's marker moved
        frames = page.evaluate("window.play.frames")  # the view streams while the person does nothing
        page.wait_for_function(f"window.play.frames >= {frames + 5}", timeout=20_000)

        page.click("#show-instruction")
        assert "come here" in page.inner_text("#instruction").lower()
        say(page, "Please come here.")
        page.wait_for_function("window.play.state.done", timeout=60_000)
        state = page.evaluate("window.play.state")
        assert state["success"] and page.inner_text("#success") == "yes"
        assert "Please come here." in page.inner_text("#transcript")


@needs_browser
def test_page_as_user_the_agent_answers_in_the_transcript(browser):
    with play_server("Legent/WhereIs-OneRoom-v0", "--size", SMALL, "--tick", "0.3") as url, \
            open_page(browser, url) as page:
        instruction = page.evaluate("window.play.state.instruction")
        say(page, instruction)
        page.wait_for_function("window.play.state.transcript.some(line => line.who === 'agent')", timeout=60_000)
        transcript = page.inner_text("#transcript")
        assert instruction in transcript and "It's on the" in transcript
        page.wait_for_function("window.play.state.done", timeout=30_000)
        assert page.evaluate("window.play.state.success")


@needs_browser
def test_page_reports_a_failing_partner_and_the_person_goes_on(browser):
    with socket.socket() as closed:  # a port nobody listens on: the "LLM endpoint" is down
        closed.bind(("127.0.0.1", 0))
        dead = f"http://127.0.0.1:{closed.getsockname()[1]}/v1"
    with play_server("Legent/ComeHere-OneRoom-v0", "--size", SMALL, "--partner", "llm", "--llm-url", dead) as url, \
            open_page(browser, url) as page:
        say(page, "Please come here.")
        page.wait_for_function("window.play.state.partner_error !== ''", timeout=30_000)
        assert "llm partner failed" in page.inner_text("#partner-error")
        state = press_and_wait(page, "d")
        assert state["result"].endswith(": ok") and not state["done"]


@needs_browser
def test_page_as_agent_records_an_episode_minari_loads(browser, tmp_path):
    from legent_gym.data.legent_format import load_trajectories
    from legent_gym.data.minari_store import load_minari_dataset

    record = tmp_path / "human"
    with play_server("Legent/ComeHere-OneRoom-v0", "--as", "agent", "--size", SMALL, "--record", str(record)) as url:
        with open_page(browser, url) as page:
            assert "Please come here." in page.inner_text("#transcript")  # the user's instruction
            press_and_wait(page, "a")
            press_and_wait(page, "ArrowUp")
            say(page, "On my way!")
            page.wait_for_function("window.play.state.actions_used === 3", timeout=20_000)
            assert "On my way!" in page.inner_text("#transcript")
            page.keyboard.press("x")
            page.wait_for_function("window.play.state.recorded === '000000'", timeout=30_000)
            page.click("#reset-same")
            page.wait_for_function("window.play.state.actions_used === 0 && !window.play.state.done", timeout=30_000)
        dataset = load_minari_dataset(record / "minari", "legent/ComeHere-OneRoom/human-v0")
        assert dataset.total_episodes == 1
        episode = next(iter(dataset.iterate_episodes()))
        assert list(episode.actions) == ["rotate_right(-30)", "move_forward(0.5)", 'speak("On my way!")', "finish()"]
        assert episode.observations["rgb"].shape[0] == 5  # one more view than actions
        trajectories = load_trajectories(record / "legent")
        assert len(trajectories) == 1 and trajectories[0]["steps"] == 4 and not trajectories[0]["success"]
        steps = trajectories[0]["interactions"][1]["trajectory"]
        assert [step["action"] for step in steps] == list(episode.actions)
        assert all((record / "legent" / step["image"]).exists() for step in steps)


@pytest.mark.slow
@needs_browser
def test_stream_reaches_20_fps_at_640x480(browser):
    with play_server("Legent/ComeHere-TwoRoom-v0", "--size", "640x480", "--fps", "60") as url, \
            open_page(browser, url) as page:
        page.wait_for_timeout(1500)
        frames, began = page.evaluate("window.play.frames"), time.monotonic()
        page.wait_for_timeout(4000)
        fps = (page.evaluate("window.play.frames") - frames) / (time.monotonic() - began)
        print(f"frames per second at 640x480: {fps:.1f}")
        assert fps >= 20

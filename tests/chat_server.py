"""A real OpenAI-compatible chat completions server on 127.0.0.1 for tests: each request
takes the next behaviour of a script (then a default) and is recorded."""

from __future__ import annotations

import contextlib
import json
import socket
import threading
import time
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer


def completion(text: str) -> dict:
    return {"id": "chatcmpl-test", "object": "chat.completion", "created": 0, "model": "test-llm",
            "choices": [{"index": 0, "finish_reason": "stop", "message": {"role": "assistant", "content": text}}],
            "usage": {"prompt_tokens": 1, "completion_tokens": 1, "total_tokens": 2}}


#: How long a ``held`` reply waits at most for the server to close.
HOLD_SECONDS = 60.0


class ReplayServer:
    """Behaviours: ``("reply", text)``, ``("held", text)`` (sent when the server closes, or
    after :data:`HOLD_SECONDS`: a client that honours a timeout has given up long before),
    ``("drip", seconds)`` (a body sent a byte at a time for that long, or until the server
    closes), ``("status", code[, headers[, message]])``, ``("raw", bytes)`` (a 200 with that
    body), ``("big", n_bytes)`` (a 200 chat completion of that size), ``("no_choices",)``,
    ``("empty_choices",)``."""

    def __init__(self, script=(), default=("status", 500)):
        self.script, self.default = list(script), default
        self.requests: list[dict] = []
        self.lock = threading.Lock()
        self.closing = threading.Event()
        server = self

        class Handler(BaseHTTPRequestHandler):
            def setup(self):
                super().setup()
                self.connection.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)

            def log_message(self, *args):
                pass

            def do_POST(self):
                body = json.loads(self.rfile.read(int(self.headers["Content-Length"])))
                with server.lock:
                    server.requests.append({"path": self.path, "body": body, "time": time.monotonic(),
                                            "headers": {k.lower(): v for k, v in self.headers.items()}})
                    behaviour = server.script.pop(0) if server.script else server.default
                with contextlib.suppress(BrokenPipeError, ConnectionResetError):
                    self.answer(*behaviour)

            def answer(self, kind, *args):
                if kind == "reply":
                    self.send(200, json.dumps(completion(args[0])).encode())
                elif kind == "held":
                    server.closing.wait(HOLD_SECONDS)
                    self.send(200, json.dumps(completion(args[0])).encode())
                elif kind == "drip":
                    data = json.dumps(completion("{}")).encode()
                    self.send_response(200)
                    self.send_header("Content-Type", "application/json")
                    self.send_header("Content-Length", str(len(data)))
                    self.end_headers()
                    pause = args[0] / len(data)
                    for b in data:
                        self.wfile.write(bytes([b]))
                        self.wfile.flush()
                        if server.closing.wait(pause):
                            return
                elif kind == "status":
                    code = args[0]
                    headers = args[1] if len(args) > 1 else {}
                    message = args[2] if len(args) > 2 else f"test error {code}"
                    self.send(code, json.dumps({"error": {"message": message, "type": "error"}}).encode(), headers)
                elif kind == "raw":
                    self.send(200, args[0])
                elif kind == "big":
                    self.send(200, json.dumps(completion("x" * args[0])).encode())
                elif kind == "no_choices":
                    self.send(200, json.dumps({"id": "x", "object": "chat.completion"}).encode())
                elif kind == "empty_choices":
                    self.send(200, json.dumps({"id": "x", "object": "chat.completion", "choices": []}).encode())
                else:
                    raise AssertionError(f"unknown behaviour {kind}")

            def send(self, code, data, headers=None):
                self.send_response(code)
                self.send_header("Content-Type", "application/json")
                self.send_header("Content-Length", str(len(data)))
                for key, value in (headers or {}).items():
                    self.send_header(key, value)
                self.end_headers()
                self.wfile.write(data)

        self.httpd = ThreadingHTTPServer(("127.0.0.1", 0), Handler)
        self.httpd.daemon_threads = True
        self.url = f"http://127.0.0.1:{self.httpd.server_port}/v1"

    def __enter__(self):
        threading.Thread(target=self.httpd.serve_forever, daemon=True).start()
        return self

    def __exit__(self, *exc):
        self.closing.set()
        self.httpd.shutdown()
        self.httpd.server_close()


def closed_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]

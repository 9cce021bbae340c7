"""One client for any OpenAI-compatible chat completions endpoint (standard library only).

:class:`ChatClient` posts ``{base_url}/chat/completions`` with ``urllib``:

* configuration: ``base_url`` (else ``$OPENAI_BASE_URL``, else OpenAI's), ``api_key`` (else
  ``$OPENAI_API_KEY``; a local endpoint needs none), ``model``, ``timeout`` (seconds per
  request, the whole reply included), ``max_retries``, ``backoff`` and ``max_backoff``
  (exponential backoff: ``backoff * 2**attempt``, a ``Retry-After`` header honoured up to
  ``max_backoff``), ``max_reply_bytes`` (a longer body is refused);
* transient failures (timeouts, refused connections, HTTP 408/409/429/5xx, a body that is
  not a chat completion: not JSON, no ``choices``, no message) are retried; then
  :class:`EndpointError` names the endpoint and the last failure. HTTP 4xx otherwise (a
  wrong key, model or URL) and a body over ``max_reply_bytes`` raise it at once;
* ``json_mode=True`` asks for ``response_format: {"type": "json_object"}``; a server that
  answers HTTP 400 naming ``response_format`` is asked again without it (and not again
  with it);
* :meth:`ChatClient.complete_model` parses the reply as JSON (a code fence around it is
  tolerated) and validates it with a pydantic model; an invalid reply is sent back once
  with the validation error, and a second invalid reply raises :class:`ReplyError`.
"""

from __future__ import annotations

import json
import os
import re
import time
import urllib.error
import urllib.request
from dataclasses import dataclass, field
from typing import Any, Protocol, TypeVar

from pydantic import BaseModel, ValidationError

OPENAI_BASE_URL = "https://api.openai.com/v1"
#: Replies longer than this (bytes of the HTTP body) are refused by default.
MAX_REPLY_BYTES = 1_000_000
# HTTP statuses worth retrying besides 5xx: request timeout, conflict, rate limit.
TRANSIENT_STATUS = frozenset({408, 409, 429})
_FENCE = re.compile(r"^```[A-Za-z]*\s*|\s*```$")

M = TypeVar("M", bound=BaseModel)


class LLMError(RuntimeError):
    """An LLM call failed; the message says where and why."""


class EndpointError(LLMError):
    """The chat endpoint could not be used (unreachable, refusing, or not answering like the API)."""


class ReplyError(LLMError):
    """The model's reply is not what was asked for, also after the error was sent back to it."""


class CallLog(Protocol):
    """Where :meth:`ChatClient.complete` counts requests and records retried failures."""

    requests: int
    errors: list[str]


@dataclass
class Calls:
    """A plain :class:`CallLog`."""

    requests: int = 0
    errors: list[str] = field(default_factory=list)


class _Transient(Exception):
    def __init__(self, failure: str, wait: float | None = None):
        super().__init__(failure)
        self.failure, self.wait = failure, wait


def short(text: str, limit: int = 200) -> str:
    """``text`` on one line, cut to ``limit`` characters."""
    text = " ".join(text.split())
    return text if len(text) <= limit else text[:limit] + "..."


class ChatClient:
    """An OpenAI-compatible chat completions endpoint with retries (see the module docstring)."""

    def __init__(self, base_url: str | None = None, api_key: str | None = None, *, model: str,
                 timeout: float = 60.0, max_retries: int = 3, backoff: float = 1.0, max_backoff: float = 30.0,
                 max_reply_bytes: int = MAX_REPLY_BYTES):
        base_url = base_url or os.environ.get("OPENAI_BASE_URL") or OPENAI_BASE_URL
        if not re.match(r"^https?://[^/\s]+", base_url):
            raise ValueError(f"base URL must be an http(s) URL, got {base_url!r}")
        api_key = api_key or os.environ.get("OPENAI_API_KEY")
        if not api_key and base_url.rstrip("/") == OPENAI_BASE_URL:
            raise ValueError(f"{OPENAI_BASE_URL} needs an API key: pass --api-key or set OPENAI_API_KEY")
        if not model:
            raise ValueError("model must be a non-empty name")
        if isinstance(timeout, bool) or not isinstance(timeout, int | float) or not timeout > 0:
            raise ValueError(f"timeout must be positive seconds, got {timeout!r}")
        if isinstance(max_retries, bool) or not isinstance(max_retries, int) or max_retries < 0:
            raise ValueError(f"max_retries must be a non-negative integer, got {max_retries!r}")
        if backoff < 0 or max_backoff < 0:
            raise ValueError(f"backoff and max_backoff must be non-negative, got {backoff!r}, {max_backoff!r}")
        if max_reply_bytes < 1:
            raise ValueError(f"max_reply_bytes must be positive, got {max_reply_bytes!r}")
        self.base_url = base_url
        self.url = base_url.rstrip("/") + "/chat/completions"
        self.api_key = api_key
        self.model, self.timeout, self.max_retries = model, float(timeout), max_retries
        self.backoff, self.max_backoff, self.max_reply_bytes = backoff, max_backoff, max_reply_bytes
        self.json_mode_offered = True  # False once the server refused response_format

    # -- one completion ------------------------------------------------------------------

    def complete(self, messages: list[dict[str, Any]], *, max_tokens: int | None = None,
                 temperature: float = 0.0, json_mode: bool = False, log: CallLog | None = None) -> str:
        """The first choice's text (``""`` if its message has none). Retries transient
        failures; raises :class:`EndpointError` naming the endpoint when they persist or
        are not transient."""
        log = log if log is not None else Calls()
        attempts = 1 + self.max_retries
        attempt = 0
        while attempt < attempts:
            log.requests += 1
            body: dict[str, Any] = {"model": self.model, "messages": messages, "temperature": temperature}
            if max_tokens is not None:
                body["max_tokens"] = max_tokens
            use_json = json_mode and self.json_mode_offered
            if use_json:
                body["response_format"] = {"type": "json_object"}
            try:
                return self._post(body)
            except _Refused as err:
                if use_json and err.status == 400 and "response_format" in err.detail:
                    self.json_mode_offered = False  # not counted as an attempt: ask plainly
                    continue
                raise EndpointError(f"chat endpoint {self.base_url} refused the request: HTTP "
                                    f"{err.status}: {short(err.detail)}") from None
            except _Transient as err:
                log.errors.append(err.failure)
                attempt += 1
                if attempt < attempts:
                    delay = self.backoff * 2 ** (attempt - 1)
                    time.sleep(min(self.max_backoff, max(delay, err.wait or 0.0)))
        raise EndpointError(f"chat endpoint {self.base_url} failed {attempts} time(s) "
                            f"(last: {log.errors[-1]})") from None

    def _post(self, body: dict[str, Any]) -> str:
        headers = {"Content-Type": "application/json", "Accept": "application/json"}
        if self.api_key:
            headers["Authorization"] = f"Bearer {self.api_key}"
        request = urllib.request.Request(self.url, data=json.dumps(body).encode(), headers=headers, method="POST")
        deadline = time.monotonic() + self.timeout
        try:
            with urllib.request.urlopen(request, timeout=self.timeout) as response:
                data = self._read(response, deadline)
        except urllib.error.HTTPError as err:
            detail = _error_detail(self._read_quietly(err, deadline), err.reason)
            if err.code in TRANSIENT_STATUS or err.code >= 500:
                raise _Transient(f"HTTP {err.code}", _retry_after(err.headers.get("Retry-After"))) from None
            raise _Refused(err.code, detail) from None
        except TimeoutError:
            raise _Transient(f"no reply within {self.timeout:g} s") from None
        except urllib.error.URLError as err:
            if isinstance(err.reason, TimeoutError):
                raise _Transient(f"no reply within {self.timeout:g} s") from None
            raise _Transient(f"connection failed: {short(str(err.reason))}") from None
        except (ConnectionError, OSError) as err:  # reset or closed while reading
            raise _Transient(f"connection failed: {short(str(err))}") from None
        return _content(data)

    def _read(self, response: Any, deadline: float) -> bytes:
        """The body, at most ``max_reply_bytes``, within the request's deadline."""
        chunks: list[bytes] = []
        size = 0
        while True:
            if time.monotonic() > deadline:
                raise TimeoutError
            chunk = response.read1(65536) if hasattr(response, "read1") else response.read(65536)
            if not chunk:
                return b"".join(chunks)
            size += len(chunk)
            if size > self.max_reply_bytes:
                raise EndpointError(f"chat endpoint {self.base_url} sent a reply over {self.max_reply_bytes} "
                                    "bytes (max_reply_bytes)")
            chunks.append(chunk)

    def _read_quietly(self, err: urllib.error.HTTPError, deadline: float) -> bytes:
        try:
            return self._read(err, deadline)
        except (EndpointError, OSError):
            return b""

    # -- validated JSON ------------------------------------------------------------------

    def complete_model(self, messages: list[dict[str, Any]], model: type[M], *, max_tokens: int | None = None,
                       temperature: float = 0.0, log: CallLog | None = None,
                       check: Any = None) -> tuple[M, str]:
        """The reply parsed as JSON and validated by ``model`` (and ``check(value)``, which
        may raise ``ValueError``), with the raw reply text. An invalid reply is sent back
        once with the error; a second one raises :class:`ReplyError`."""
        convo = list(messages)
        error = ""
        for round_ in range(2):
            text = self.complete(convo, max_tokens=max_tokens, temperature=temperature, json_mode=True, log=log)
            try:
                value = parse_reply(text, model)
                if check is not None:
                    check(value)
                return value, text
            except ValueError as err:
                error = describe_error(err)
            if round_ == 0:
                convo = [*convo, {"role": "assistant", "content": text[:20000]},
                         {"role": "user", "content": f"That reply is not valid: {error}. Reply again with the "
                                                     "corrected JSON object only."}]
        raise ReplyError(f"the model {self.model!r} at {self.base_url} sent an invalid {model.__name__} twice "
                         f"(last: {error})")


class _Refused(Exception):
    def __init__(self, status: int, detail: str):
        super().__init__(f"HTTP {status}")
        self.status, self.detail = status, detail


def _content(data: bytes) -> str:
    try:
        payload = json.loads(data)
    except (json.JSONDecodeError, UnicodeDecodeError) as err:
        raise _Transient(f"not a chat completion: the body is not JSON ({short(str(err))}): "
                         f"{short(data[:200].decode('utf-8', 'replace'))}") from None
    if not isinstance(payload, dict):
        raise _Transient(f"not a chat completion: the body is {short(repr(payload))}")
    choices = payload.get("choices")
    if not isinstance(choices, list) or not choices:
        raise _Transient("not a chat completion: no choices in the response")
    message = choices[0].get("message") if isinstance(choices[0], dict) else None
    if not isinstance(message, dict):
        raise _Transient("not a chat completion: the first choice has no message")
    content = message.get("content")
    if content is None:
        return ""
    if isinstance(content, list):  # content parts
        return "".join(p.get("text", "") for p in content if isinstance(p, dict))
    return str(content)


def _error_detail(data: bytes, reason: Any) -> str:
    """The server's own error message when the body has one (the API's ``{"error": {"message"}}``)."""
    try:
        body = json.loads(data)
    except (json.JSONDecodeError, UnicodeDecodeError):
        return short(data.decode("utf-8", "replace")) or str(reason)
    if isinstance(body, dict):
        inner = body.get("error", body)
        if isinstance(inner, dict) and inner.get("message"):
            return str(inner["message"])
        if isinstance(inner, str):
            return inner
    return str(reason)


def _retry_after(value: str | None) -> float | None:
    try:
        return float(value) if value is not None else None
    except ValueError:
        return None


def parse_reply(text: str, model: type[M]) -> M:
    """``text`` (JSON, perhaps in a code fence or with words around one object) validated by
    ``model``; ``ValueError`` if not."""
    body = _FENCE.sub("", text.strip()).strip()
    if not body:
        raise ValueError("the reply is empty")
    try:
        data = json.loads(body)
    except json.JSONDecodeError as err:
        start, end = body.find("{"), body.rfind("}")
        try:  # a JSON object with words around it
            data = json.loads(body[start:end + 1]) if 0 <= start < end else None
        except json.JSONDecodeError:
            data = None
        if data is None:
            raise ValueError(f"the reply is not JSON: {err}") from None
    return model.model_validate(data)


def describe_error(err: ValueError) -> str:
    """A short, one-line account of a validation error (at most three problems)."""
    if isinstance(err, ValidationError):
        parts = []
        for e in err.errors()[:3]:
            where = ".".join(str(p) for p in e["loc"]) or "(top)"
            parts.append(f"{where}: {e['msg']}")
        more = len(err.errors()) - 3
        return "; ".join(parts) + (f"; and {more} more" if more > 0 else "")
    return short(str(err), 400)

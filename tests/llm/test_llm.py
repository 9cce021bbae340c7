"""legent_gym.llm against a real chat completions server on 127.0.0.1 (tests/chat_server.py)."""

from __future__ import annotations

import time

import pytest
from pydantic import BaseModel

from legent_gym.llm import ChatClient, EndpointError, ReplyError
from tests.chat_server import HOLD_SECONDS, ReplayServer, closed_port


class Pair(BaseModel):
    name: str
    count: int


def _client(server, **kwargs) -> ChatClient:
    options = {"model": "test-llm", "api_key": "k", "timeout": 5.0, "max_retries": 2, "backoff": 0.0}
    return ChatClient(server.url, **{**options, **kwargs})


def test_complete_posts_a_chat_request_and_returns_the_text():
    with ReplayServer([("reply", "hello")]) as server:
        text = _client(server).complete([{"role": "user", "content": "hi"}], max_tokens=7, temperature=0.5)
    assert text == "hello"
    request = server.requests[0]
    assert request["path"] == "/v1/chat/completions"
    assert request["headers"]["authorization"] == "Bearer k"
    assert request["body"]["model"] == "test-llm" and request["body"]["max_tokens"] == 7
    assert request["body"]["messages"] == [{"role": "user", "content": "hi"}]
    assert "response_format" not in request["body"]


def test_complete_model_validates_and_uses_json_mode():
    with ReplayServer([("reply", '```json\n{"name": "apple", "count": 2}\n```')]) as server:
        value, raw = _client(server).complete_model([{"role": "user", "content": "x"}], Pair)
    assert value == Pair(name="apple", count=2) and "apple" in raw
    assert server.requests[0]["body"]["response_format"] == {"type": "json_object"}


def test_words_around_the_json_object_are_tolerated():
    with ReplayServer([("reply", 'Here is the plan: {"name": "pear", "count": 1} Enjoy!')]) as server:
        assert _client(server).complete_model([{"role": "user", "content": "x"}], Pair)[0].name == "pear"
    assert len(server.requests) == 1


def test_a_server_without_json_mode_is_asked_again_plainly():
    script = [("status", 400, {}, "unknown field: response_format"), ("reply", '{"name": "a", "count": 1}'),
              ("reply", '{"name": "b", "count": 1}')]
    with ReplayServer(script) as server:
        client = _client(server, max_retries=0)
        assert client.complete_model([{"role": "user", "content": "x"}], Pair)[0].name == "a"
        assert client.complete_model([{"role": "user", "content": "x"}], Pair)[0].name == "b"
    assert [("response_format" in r["body"]) for r in server.requests] == [True, False, False]


@pytest.mark.parametrize("bad, error", [("not json at all", "not JSON"), ('{"name": "a", "count": "many"}', "count"),
                                        ("", "empty")])
def test_an_invalid_reply_is_sent_back_once_with_the_error(bad, error):
    with ReplayServer([("reply", bad), ("reply", '{"name": "a", "count": 3}')]) as server:
        value, _ = _client(server).complete_model([{"role": "user", "content": "x"}], Pair)
    assert value.count == 3
    second = server.requests[1]["body"]["messages"]
    assert [m["role"] for m in second] == ["user", "assistant", "user"]
    assert second[1]["content"] == bad and error in second[2]["content"]


def test_two_invalid_replies_raise_a_reply_error():
    server = ReplayServer(default=("reply", '{"name": 3}'))
    with server, pytest.raises(ReplyError, match=r"invalid Pair twice \(last: name: .*count: Field required"):
        _client(server).complete_model([{"role": "user", "content": "x"}], Pair)
    assert len(server.requests) == 2


def test_a_check_failure_counts_as_invalid():
    def check(value):
        if value.count > 5:
            raise ValueError("count must be at most 5")

    with ReplayServer([("reply", '{"name": "a", "count": 9}'), ("reply", '{"name": "a", "count": 4}')]) as server:
        value, _ = _client(server).complete_model([{"role": "user", "content": "x"}], Pair, check=check)
    assert value.count == 4 and "at most 5" in server.requests[1]["body"]["messages"][-1]["content"]


@pytest.mark.parametrize("behaviour, failure", [
    (("status", 500), "HTTP 500"), (("raw", b"<html>bad gateway</html>"), "not a chat completion: the body is not JSON"),
    (("no_choices",), "no choices"), (("empty_choices",), "no choices"), (("raw", b"[1, 2]"), "the body is [1, 2]"),
])
def test_persistent_failures_raise_naming_the_endpoint(behaviour, failure):
    server = ReplayServer(default=behaviour)
    with server, pytest.raises(EndpointError, match=f"chat endpoint {server.url} failed 3 time") as info:
        _client(server).complete([{"role": "user", "content": "x"}])
    assert failure in str(info.value) and len(server.requests) == 3
    assert info.value.__cause__ is None


def test_transient_failures_are_retried_with_backoff():
    script = [("status", 503), ("status", 429, {"Retry-After": "0.2"}), ("reply", "ok")]
    with ReplayServer(script) as server:
        from legent_gym.llm import Calls

        log = Calls()
        assert _client(server, backoff=0.05).complete([{"role": "user", "content": "x"}], log=log) == "ok"
    assert log.requests == 3 and log.errors == ["HTTP 503", "HTTP 429"]
    t = [r["time"] for r in server.requests]
    assert t[1] - t[0] >= 0.05 and t[2] - t[1] >= 0.2


def test_client_errors_are_not_retried():
    server = ReplayServer(default=("status", 401, {}, "bad key"))
    with server, pytest.raises(EndpointError, match="refused the request: HTTP 401: bad key"):
        _client(server).complete([{"role": "user", "content": "x"}])
    assert len(server.requests) == 1


def test_timeouts_bound_the_whole_reply():
    with ReplayServer([("held", "late"), ("drip", HOLD_SECONDS)]) as server:
        started = time.monotonic()
        with pytest.raises(EndpointError, match=r"failed 2 time\(s\) \(last: no reply within 0.4 s\)"):
            _client(server, timeout=0.4, max_retries=1).complete([{"role": "user", "content": "x"}])
        # Far above the 2 x 0.4 s it takes; a timeout per read would wait for the whole drip.
        assert time.monotonic() - started < HOLD_SECONDS / 2


def test_a_huge_reply_is_refused_at_once():
    with ReplayServer(default=("big", 5_000_000)) as server:
        started = time.monotonic()
        with pytest.raises(EndpointError, match="over 100000 bytes"):
            _client(server, max_reply_bytes=100_000).complete([{"role": "user", "content": "x"}])
        assert time.monotonic() - started < 3.0
    assert len(server.requests) == 1


def test_unreachable_endpoint():
    url = f"http://127.0.0.1:{closed_port()}/v1"
    with pytest.raises(EndpointError, match=rf"{url} failed 2 time\(s\) \(last: connection failed"):
        ChatClient(url, model="m", max_retries=1, backoff=0.0, timeout=2.0).complete([{"role": "user", "content": "x"}])


def test_configuration(monkeypatch):
    monkeypatch.delenv("OPENAI_API_KEY", raising=False)
    monkeypatch.setenv("OPENAI_BASE_URL", "http://127.0.0.1:9/v1")
    assert ChatClient(model="m").base_url == "http://127.0.0.1:9/v1"
    monkeypatch.delenv("OPENAI_BASE_URL")
    with pytest.raises(ValueError, match="needs an API key"):
        ChatClient(model="m")
    for bad, match in [({"base_url": "localhost:1"}, "http"), ({"timeout": 0}, "timeout"),
                       ({"max_retries": -1}, "max_retries"), ({"model": ""}, "model")]:
        with pytest.raises(ValueError, match=match):
            ChatClient(**{"base_url": "http://127.0.0.1:9/v1", "model": "m", **bad})

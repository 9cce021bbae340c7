"""The play page's Content-Security-Policy, in force: every response carries it, the page
works under it (no violation of its own), and a script injected into the page does not run.
The other browser tests (tests/play/test_play.py) bypass the policy, since Playwright's waits
evaluate strings; here the waits poll from Python instead."""

from __future__ import annotations

import time
import urllib.error
import urllib.request

from legent_gym.play.server import CSP
from tests.play.test_play import SMALL, browser, needs_browser, play_server  # noqa: F401  (browser: a fixture)

#: Records every violation of the policy the page reports (an init script is the browser's,
#: run before the page's own; it is not subject to the page's policy).
RECORD_VIOLATIONS = ("window.violations = []; document.addEventListener('securitypolicyviolation', "
                     "(e) => window.violations.push(e.violatedDirective));")
#: What an attacker who got markup into the page would try: an inline script, an inline
#: event handler.
INJECT = """() => {
  const script = document.createElement('script');
  script.textContent = 'window.injected = true';
  document.body.appendChild(script);
  const box = document.createElement('div');
  box.innerHTML = '<img src="data:," onerror="window.injectedHandler = true">';
  document.body.appendChild(box);
}"""


def wait_until(page, predicate: str, timeout: float = 60.0) -> None:
    """Poll ``predicate`` (JavaScript) from here: ``page.wait_for_function`` evaluates a
    string in the page, which the policy forbids."""
    deadline = time.monotonic() + timeout
    while not page.evaluate(f"() => Boolean({predicate})"):
        assert time.monotonic() < deadline, f"not within {timeout} s: {predicate}"
        time.sleep(0.05)


def test_every_response_carries_the_policy():
    assert "script-src 'self'" in CSP and "unsafe-inline" not in CSP and "unsafe-eval" not in CSP
    with play_server("Legent/ComeHere-OneRoom-v0", "--size", SMALL) as url:
        base = url.split("?")[0]
        for address in (url, base + "static/play.js", base + "static/play.css", base):  # the last: a 403
            try:
                response = urllib.request.urlopen(address, timeout=30)
            except urllib.error.HTTPError as refused:
                response = refused
            assert response.headers["Content-Security-Policy"] == CSP, address


@needs_browser
def test_the_page_works_under_its_policy_and_an_injected_script_does_not_run(browser):  # noqa: F811
    outcome = {}
    with play_server("Legent/ComeHere-OneRoom-v0", "--size", SMALL, "--sessions", "2") as url:
        for bypass in (False, True):
            context = browser.new_context(bypass_csp=bypass)
            context.add_init_script(script=RECORD_VIOLATIONS)
            page = context.new_page()
            try:
                page.goto(url)
                wait_until(page, "window.play && window.play.frames >= 2 && window.play.state && window.play.map")
                if not bypass:  # the page's own script, style, images and WebSocket keep to the policy
                    page.keyboard.press("d")
                    wait_until(page, "window.play.state.actions_used === 1")
                    frames = page.evaluate("() => window.play.frames")
                    wait_until(page, f"window.play.frames >= {frames + 3}")
                    assert page.inner_text("#connection") == "connected"
                    assert page.evaluate("() => window.violations") == []
                page.evaluate(INJECT)
                wait_until(page, "window.injectedHandler || window.violations.includes('script-src-attr')")
                outcome[bypass] = page.evaluate(
                    "() => [window.injected === true, window.injectedHandler === true, window.violations]")
            finally:
                context.close()
    assert outcome[False][:2] == [False, False]  # neither ran...
    assert {"script-src-elem", "script-src-attr"} <= set(outcome[False][2])  # ...the policy stopped both
    assert outcome[True] == [True, True, []]  # the same injection runs where the policy is bypassed

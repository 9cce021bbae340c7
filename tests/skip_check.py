"""``--check-skips``, which ``bash scripts/test.sh`` passes when it runs the whole default
suite: the run fails if a test skipped for a reason that is not an allowed absence, so a
module that silently stops running (a missing extra, a missing file) is noticed. A pytest
plugin (its hooks are imported by tests/conftest.py); it reads the skips that the terminal
reporter counted, which under pytest-xdist are the workers' reports, on the controller."""

from __future__ import annotations

import pytest

#: The only reasons a test may skip in a run with ``--check-skips``: an absence that
#: scripts/setup.sh cannot remedy on this machine. On a Debian machine with two or more cores
#: that it set up, the default run skips no test. README.md lists the same.
ALLOWED_SKIPS = {
    "no Chromium at ": "no apt-get to install Debian's chromium (the browser tests of legent-gym play)",
    "no Xvfb ": "no apt-get to install xvfb (rendering through an X display)",
    "needs two cores": "a machine with one core (workers pinned to different cores)",
    "no CPU affinity here": "no sched_setaffinity (not Linux)",
    "no git history here": "a clone without history (the figures' commit checks)",
}


def pytest_addoption(parser):
    parser.addoption("--check-skips", action="store_true",
                     help="fail the run if a test skips for a reason that is not an absence listed in "
                          "tests/skip_check.py's ALLOWED_SKIPS (bash scripts/test.sh passes it for the whole suite)")


def _skip_reason(report) -> str:
    longrepr = report.longrepr
    reason = longrepr[2] if isinstance(longrepr, tuple) else str(longrepr)
    return reason.removeprefix("Skipped: ")


def _unexpected_skips(config) -> list[str]:
    reporter = config.pluginmanager.get_plugin("terminalreporter")
    skipped = reporter.stats.get("skipped", []) if reporter is not None else []
    return [f"{report.nodeid}: {_skip_reason(report)}" for report in skipped
            if not any(allowed in _skip_reason(report) for allowed in ALLOWED_SKIPS)]


def _checked(config) -> bool:
    """With --check-skips, on the controller (pytest-xdist's workers send it their reports)."""
    return bool(config.getoption("check_skips")) and not hasattr(config, "workerinput")


def pytest_sessionfinish(session, exitstatus):
    if _checked(session.config) and _unexpected_skips(session.config) and session.exitstatus == pytest.ExitCode.OK:
        session.exitstatus = pytest.ExitCode.TESTS_FAILED


def pytest_terminal_summary(terminalreporter, exitstatus, config):
    if _checked(config):
        unexpected = _unexpected_skips(config)
        if unexpected:
            terminalreporter.section("skips outside ALLOWED_SKIPS (tests/skip_check.py)", red=True)
            for line in unexpected:
                terminalreporter.line(line, red=True)
            terminalreporter.line(f"{len(unexpected)} test(s) skipped for a reason that is not an allowed absence: "
                                  "install what they need, or fix them", red=True)

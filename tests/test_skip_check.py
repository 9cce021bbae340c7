"""`--check-skips` (tests/skip_check.py, passed by scripts/test.sh): a skip for a reason outside
ALLOWED_SKIPS fails the run, under pytest-xdist too; allowed absences, and runs without the
option, pass."""

from __future__ import annotations

import subprocess
import sys

from .conftest import REPO
from .skip_check import ALLOWED_SKIPS

FILES = {
    "conftest.py": "from tests.skip_check import pytest_addoption, pytest_sessionfinish, pytest_terminal_summary  # noqa\n",
    "test_ok.py": "def test_passes():\n    pass\n",
    "test_allowed.py": "import pytest\n\n\n@pytest.mark.skipif(True, reason='no Chromium at /nowhere')\n"
                       "def test_browser():\n    pass\n",
}
SKIPS = {
    "test_module.py": "import pytest\n\npytest.importorskip('legent_gym_no_such_module')\n\n\ndef test_never():\n    pass\n",
    "test_gives_up.py": "import pytest\n\n\ndef test_gives_up():\n    pytest.skip('the sample file is missing')\n",
}


def _run(folder, *options: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "pytest", "-p", "no:cacheprovider", "-q", *options, str(folder)],
                          cwd=folder, capture_output=True, text=True, timeout=300,
                          env={"PYTHONPATH": str(REPO), "PATH": "/usr/bin:/bin", "HOME": str(folder)})


def test_skips_outside_the_list_fail_the_checked_run(tmp_path):
    for name, text in {**FILES, **SKIPS}.items():
        (tmp_path / name).write_text(text)
    done = _run(tmp_path, "-n", "2", "--check-skips")
    assert done.returncode == 1, done.stdout + done.stderr
    assert "skips outside ALLOWED_SKIPS" in done.stdout, done.stdout
    assert "test_module.py: could not import 'legent_gym_no_such_module'" in done.stdout
    assert "test_gives_up.py::test_gives_up: the sample file is missing" in done.stdout
    assert "2 test(s) skipped for a reason that is not an allowed absence" in done.stdout
    assert "test_allowed.py" not in done.stdout.split("skips outside ALLOWED_SKIPS")[1]
    # Unchecked (a subset a user runs), the same skips pass.
    assert _run(tmp_path).returncode == 0


def test_allowed_absences_pass_the_checked_run(tmp_path):
    for name, text in FILES.items():
        (tmp_path / name).write_text(text)
    done = _run(tmp_path, "-n", "2", "--check-skips")
    assert done.returncode == 0 and "1 passed, 1 skipped" in done.stdout, done.stdout + done.stderr
    assert any(allowed in "no Chromium at /nowhere" for allowed in ALLOWED_SKIPS)

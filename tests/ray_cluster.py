"""Ray clusters for tests: one at a time per test run, and one started as a user starts it."""

from __future__ import annotations

import contextlib
import fcntl
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from collections.abc import Iterator
from pathlib import Path


@contextlib.contextmanager
def one_cluster_at_a_time(tmp_path_factory) -> Iterator[None]:
    """Held while this process runs a Ray cluster: pytest-xdist may give tests that start one
    to both workers, and two clusters of 2 CPUs each would share the 2-core machine. The lock
    file is in the run's temporary root, which the workers share."""
    with (tmp_path_factory.getbasetemp().parent / "ray-cluster.lock").open("w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        yield


@contextlib.contextmanager
def ray_start_head(cpus: int = 2) -> Iterator[dict[str, str]]:
    """``ray start --head --block`` on 127.0.0.1 (no dashboard) in a session of its own, with
    its own temporary folder (``RAY_TMPDIR``), so that ``address="auto"`` in a process with
    the environment this yields finds this cluster and no other on the machine. Yields that
    environment (``RAY_ADDRESS`` removed) with ``"address"`` added: the head's GCS address.
    Stopped by signalling its process group (not ``ray stop``, which stops every Ray of the
    user)."""
    temp = tempfile.mkdtemp(prefix="ray", dir="/tmp")  # short: Ray's socket paths must fit 107 bytes
    env = {k: v for k, v in os.environ.items() if k != "RAY_ADDRESS"}
    env.update(RAY_TMPDIR=temp, RAY_USAGE_STATS_ENABLED="0", RAY_ENABLE_WINDOWS_OR_OSX_CLUSTER="0")
    ray = str(Path(sys.executable).parent / "ray")
    proc = subprocess.Popen([ray, "start", "--head", "--block", "--node-ip-address", "127.0.0.1", "--port", "0",
                             "--num-cpus", str(cpus), "--include-dashboard", "false", "--disable-usage-stats"],
                            env=env, start_new_session=True, stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
    address_file = Path(temp) / "ray" / "ray_current_cluster"  # written by `ray start` once the head is up
    try:
        deadline = time.monotonic() + 120
        while not (address_file.exists() and address_file.read_text().strip()):
            if proc.poll() is not None or time.monotonic() > deadline:
                output = proc.stdout.read().decode() if proc.poll() is not None and proc.stdout else ""
                raise RuntimeError(f"ray start --head did not come up: {output[-3000:]}")
            time.sleep(0.2)
        yield {**env, "address": address_file.read_text().strip()}
    finally:
        with contextlib.suppress(ProcessLookupError):
            os.killpg(proc.pid, signal.SIGTERM)  # `ray start --block` stops its cluster on SIGTERM
        with contextlib.suppress(subprocess.TimeoutExpired):
            proc.wait(timeout=60)
        with contextlib.suppress(ProcessLookupError):
            os.killpg(proc.pid, signal.SIGKILL)  # what is left of the group
        if proc.stdout is not None:
            proc.stdout.close()
        shutil.rmtree(temp, ignore_errors=True)

"""The Ray backend (legent_gym/utils/scale.py): collection and evaluation as Ray tasks on a local
cluster (loopback only, 2 CPUs, no dashboard) give what the process backend gives, survive
a killed Ray worker and a killed driver, and a missing Ray is one line naming the extra."""

from __future__ import annotations

import fcntl
import importlib.util
import json
import os
import signal
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

from legent_gym.cli import main
from legent_gym.data import CollectConfig, collect
from legent_gym.data.legent_format import load_trajectories
from legent_gym.data.minari_store import load_minari_dataset
from legent_gym.utils.scale import Backend
from legent_gym.utils.workers import map_ordered
from tests.conftest import REPO
from tests.data.test_data_collect import DATASET_ID, ENV_ID, _check_whole, _committed

N = 20
SMALL = {"width": 32, "height": 32}
SIZE = ["--width", "32", "--height", "32"]
FORMATS = ("minari", "legent")
HAS_RAY = importlib.util.find_spec("ray") is not None
needs_ray = pytest.mark.skipif(not HAS_RAY, reason='Ray is not installed (the "scale" extra: pip install -e ".[scale]")')


@pytest.fixture(scope="module")
def one_cluster_at_a_time(tmp_path_factory):
    """Held while this process runs a Ray cluster: pytest-xdist may give this module's tests to
    both workers, and two clusters of 2 CPUs each would share the 2-core machine. The lock file
    is in the run's temporary root, which the workers share."""
    with (tmp_path_factory.getbasetemp().parent / "ray-cluster.lock").open("w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        yield


@pytest.fixture(scope="module")
def ray_address(one_cluster_at_a_time):
    """A Ray cluster on this machine for the module's tests: loopback only, 2 CPUs, no
    dashboard. Its address lets drivers in other processes join it."""
    # Read when ray is imported: the node binds and advertises 127.0.0.1 only.
    os.environ.setdefault("RAY_ENABLE_WINDOWS_OR_OSX_CLUSTER", "0")
    os.environ.setdefault("RAY_USAGE_STATS_ENABLED", "0")
    import ray

    if ray.is_initialized():  # not ours: leave it
        pytest.skip("this process is connected to another Ray cluster")
    context = ray.init(address="local", num_cpus=2, include_dashboard=False, _node_ip_address="127.0.0.1")
    address = context.address_info["address"]
    assert address.startswith("127.0.0.1:")
    yield address
    ray.shutdown()


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    """N episodes from the process backend with 2 workers."""
    out = tmp_path_factory.mktemp("process")
    collect(CollectConfig(ENV_ID, N, str(out), formats=FORMATS, workers=2, env_kwargs=SMALL), show_progress=False)
    return out


def _same_episodes(out, reference) -> None:
    """Same trajectories, same actions, equal observations, same order."""
    assert load_trajectories(out / "legent") == load_trajectories(reference / "legent")
    assert (out / "legent" / "interleaved.jsonl").read_bytes() == (reference / "legent" / "interleaved.jsonl").read_bytes()
    ours = list(load_minari_dataset(out / "minari", DATASET_ID).iterate_episodes())
    theirs = list(load_minari_dataset(reference / "minari", DATASET_ID).iterate_episodes())
    assert len(ours) == len(theirs) == N
    for a, b in zip(ours, theirs):
        assert list(a.actions) == list(b.actions)
        assert np.array_equal(a.observations["rgb"], b.observations["rgb"])
        assert list(a.observations["instruction"]) == list(b.observations["instruction"])
        assert np.array_equal(a.rewards, b.rewards)


def _driver(out, address: str) -> subprocess.Popen:
    """``legent-gym collect --backend ray`` in a process of its own, joining the cluster."""
    command = [sys.executable, "-m", "legent_gym.cli", "collect", ENV_ID, "--episodes", str(N), "--out", str(out),
               "--format", ",".join(FORMATS), "--workers", "2", "--backend", "ray", "--ray-address", address,
               "--quiet", *SIZE]
    return subprocess.Popen(command, cwd=REPO, start_new_session=True, stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT)


def _wait_for_episodes(out, count: int, proc: subprocess.Popen | None = None, timeout: float = 120) -> None:
    deadline = time.monotonic() + timeout
    while _committed(out) < count and time.monotonic() < deadline:
        if proc is not None and proc.poll() is not None:
            break
        time.sleep(0.02)
    assert _committed(out) >= count, proc.stdout.read().decode()[-3000:] if proc is not None else "too slow"


_inits = 0


def _count_init(log: str) -> None:
    """Counts this process's initializer runs, and logs its process id to ``log``."""
    global _inits
    _inits += 1
    with open(log, "a") as f:
        f.write(f"{os.getpid()}\n")


def _step(kind: str, seconds: float):
    """A call for the ordered map: sleeps, then returns where it ran, or fails."""
    time.sleep(seconds)
    if kind == "fail":
        raise ValueError(f"failed after {seconds} s")
    return kind, os.getpid(), _inits


@needs_ray
def test_the_ray_map_keeps_order_sets_up_each_worker_once_and_raises_early(ray_address, tmp_path):
    calls = [("a", 0.6), ("b", 0.0), ("c", 0.3), ("d", 0.0), ("e", 0.0), ("f", 0.2)]
    logs = [tmp_path / "first.log", tmp_path / "again.log"]
    first = list(map_ordered(_step, calls, workers=2, initializer=_count_init, initargs=(str(logs[0]),),
                             backend="ray"))
    assert [kind for kind, _, _ in first] == ["a", "b", "c", "d", "e", "f"]
    again = list(map_ordered(_step, calls[:2], workers=1, initializer=_count_init, initargs=(str(logs[1]),),
                             backend="ray"))
    assert [kind for kind, _, _ in again] == ["a", "b"]
    # The initializer ran once in each worker process of each map (a process that stays from
    # the first map runs it again for the next), before that process's first call: each call
    # sees as many runs in its process as the logs of the maps so far hold for it.
    ran_first, ran_again = logs[0].read_text().split(), logs[1].read_text().split()
    assert sorted(ran_first) == sorted({str(pid) for _, pid, _ in first})
    assert sorted(ran_again) == sorted({str(pid) for _, pid, _ in again})
    assert all(n == ran_first.count(str(pid)) for _, pid, n in first)
    assert all(n == ran_first.count(str(pid)) + ran_again.count(str(pid)) for _, pid, n in again)

    began = time.monotonic()
    with pytest.raises(ValueError, match="failed after 0.1 s"):
        list(map_ordered(_step, [("slow", 30.0), ("fail", 0.1)], workers=2, backend="ray"))
    assert time.monotonic() - began < 20  # raised while the first call still ran


@needs_ray
def test_ray_collects_the_episodes_of_the_process_backend(ray_address, reference, tmp_path):
    out = tmp_path / "ray"
    summary = collect(CollectConfig(ENV_ID, N, str(out), formats=FORMATS, workers=2, env_kwargs=SMALL,
                                    backend="ray"), show_progress=False)
    assert summary.episodes == N
    _same_episodes(out, reference)


def _stopping_expert(gate: str, house_seed: int):
    """The expert, except that its first call in the house ``house_seed`` writes its process
    id to ``gate/caught`` and waits there to be killed (a retry of that attempt finds the
    file and plays on). Pickled by value (a closure), so Ray's workers get the gate."""
    def policy(obs, info):
        if info["house_seed"] == house_seed:
            mine = os.path.join(gate, f"pid.{os.getpid()}")
            with open(mine, "w") as f:
                f.write(str(os.getpid()))
            try:
                os.link(mine, os.path.join(gate, "caught"))  # made whole, and by one call only
            except FileExistsError:
                return info["expert_action"]
            time.sleep(600)
            raise RuntimeError("the test did not kill the worker in 600 s")
        return info["expert_action"]
    return policy


@needs_ray
def test_a_ray_worker_killed_mid_collection_is_retried(ray_address, reference, tmp_path):
    """The worker running attempt 5 is killed while it runs it: the policy holds that call
    until the test has killed its process, so the kill always lands mid-collection."""
    import gymnasium as gym

    with gym.make(ENV_ID, **SMALL) as env:
        house_seed = env.reset(seed=5)[1]["house_seed"]
    out, gate, errors = tmp_path / "ray", tmp_path / "gate", []
    gate.mkdir()

    def run() -> None:
        try:
            collect(CollectConfig(ENV_ID, N, str(out), formats=FORMATS, workers=2, env_kwargs=SMALL, backend="ray",
                                  dataset_id=DATASET_ID),
                    policy=_stopping_expert(str(gate), house_seed), show_progress=False)
        except BaseException as err:  # noqa: BLE001  (reported below)
            errors.append(err)

    driver = threading.Thread(target=run)
    driver.start()
    try:
        deadline = time.monotonic() + 300
        while not (gate / "caught").is_file() and driver.is_alive() and time.monotonic() < deadline:
            time.sleep(0.05)
        assert (gate / "caught").is_file(), f"attempt 5 never ran: {errors}"
        pid = int((gate / "caught").read_text())
        assert _committed(out) <= 5  # attempt 5 is running: it and those after it are not committed
        os.kill(pid, signal.SIGKILL)  # a worker process of the cluster this test started
    finally:
        driver.join(timeout=300)
    assert not driver.is_alive() and not errors, errors
    assert _check_whole(out, expected=N) == N
    _same_episodes(out, reference)


@needs_ray
def test_the_driver_killed_then_rerun_resumes_from_its_episodes(ray_address, reference, tmp_path):
    out = tmp_path / "ray"
    proc = _driver(out, ray_address)
    try:
        _wait_for_episodes(out, 3, proc)
        assert proc.poll() is None, proc.stdout.read().decode()[-3000:]
        os.kill(proc.pid, signal.SIGKILL)
        proc.wait()
    finally:
        if proc.poll() is None:
            os.kill(proc.pid, signal.SIGKILL)
        proc.stdout.close()
    survived = _check_whole(out)
    assert 3 <= survived < N
    before = json.loads((out / "progress.json").read_text())["progress"]

    # The rerun (here, joining the same cluster) adds the rest: no episode twice, none missing.
    assert main(["collect", ENV_ID, "--episodes", str(N), "--out", str(out), "--format", ",".join(FORMATS),
                 "--workers", "2", "--backend", "ray", "--ray-address", ray_address, "--quiet", *SIZE]) == 0
    assert _check_whole(out, expected=N) == N
    after = json.loads((out / "progress.json").read_text())["progress"]
    assert after["committed"] == N and after["next_attempt"] >= before["next_attempt"]
    _same_episodes(out, reference)


@needs_ray
def test_evaluation_through_ray_equals_in_process(ray_address, capsys):
    from baselines.evaluate import main as evaluate_main
    from baselines.vla.evaluate import evaluate_many, success_rate

    jobs = [("random", ENV_ID)]
    (here,) = evaluate_many(jobs, N, 0, SMALL, workers=1)  # in this process
    (on_ray,) = evaluate_many(jobs, N, 0, SMALL, workers=2, backend=Backend("ray", ray_address))
    assert on_ray == here  # episode by episode: seeds, steps, returns, success
    assert 0 < success_rate(on_ray) < 1  # a rate that could have come out otherwise

    args = ["--episodes", str(N), "--seed", "0", *SIZE]
    assert evaluate_main(args) == 0
    assert evaluate_main([*args, "--workers", "2", "--backend", "ray", "--ray-address", ray_address]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[0] == lines[1] == (f"random on {ENV_ID}: success {success_rate(here):.3f} over {N} "
                                    "episodes (seed 0)")


@needs_ray
def test_a_ray_started_by_collect_serves_the_loopback_interface_only(one_cluster_at_a_time, tmp_path):
    """Without --ray-address, collect starts a Ray of --workers CPUs bound to 127.0.0.1."""
    script = ("import sys; from legent_gym.cli import main; code = main(sys.argv[1:]); import ray; "
              "print(ray.get_runtime_context().gcs_address, ray.cluster_resources()['CPU']); sys.exit(code)")
    env = {k: v for k, v in os.environ.items() if not k.startswith("RAY_")}
    done = subprocess.run([sys.executable, "-c", script, "collect", ENV_ID, "--episodes", "2", "--out",
                           str(tmp_path / "out"), "--backend", "ray", "--quiet", *SIZE], cwd=REPO, env=env,
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr[-3000:]
    address, cpus = done.stdout.split()[-2:]
    assert address.startswith("127.0.0.1:") and float(cpus) == 1.0  # --workers 1
    assert _check_whole(tmp_path / "out", expected=2) == 2


def test_a_missing_ray_is_one_line_naming_the_extra(tmp_path):
    hide_ray = ("import sys; sys.modules['ray'] = None; from legent_gym.cli import main; "
                "sys.exit(main(sys.argv[1:]))")
    done = subprocess.run([sys.executable, "-c", hide_ray, "collect", ENV_ID, "--episodes", "2", "--out",
                           str(tmp_path / "out"), "--backend", "ray"], cwd=REPO, capture_output=True, text=True)
    assert done.returncode == 2
    assert done.stderr.count("\n") == 1 and "Traceback" not in done.stderr
    assert 'the "scale" extra' in done.stderr and 'pip install -e ".[scale]"' in done.stderr
    assert not (tmp_path / "out" / "minari").exists()


@pytest.mark.parametrize(("argv", "message"), [
    (["--ray-address", "auto"], "a Ray address needs the ray backend"),
    (["--backend", "ray", "--ray-address", "nowhere"], "must be 'auto' or HOST:PORT"),
])
def test_bad_backend_arguments_are_refused(tmp_path, capsys, argv, message):
    assert main(["collect", ENV_ID, "--episodes", "2", "--out", str(tmp_path / "out"), *argv]) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1


def test_the_table_passes_the_backend_to_its_collections(tmp_path):
    from baselines.reproduce_table import SCALES, collect_command

    scale = SCALES["small"]
    assert "--backend" not in collect_command("ComeHere-OneRoom", 0, 5, tmp_path, scale, 2)
    command = collect_command("ComeHere-OneRoom", 0, 5, tmp_path, scale, 2, backend=Backend("ray", "auto"))
    assert command[command.index("--backend"):][:4] == ["--backend", "ray", "--ray-address", "auto"]
    local = collect_command("ComeHere-OneRoom", 0, 5, tmp_path, scale, 2, backend=Backend("ray"))
    assert "--ray-address" not in local and local[local.index("--backend") + 1] == "ray"


@pytest.mark.parametrize("script", ["baselines/evaluate.py", "baselines/reproduce_table.py"])
def test_the_baselines_name_the_extra_when_ray_is_missing(script, tmp_path):
    hide_ray = ("import runpy, sys; sys.modules['ray'] = None; sys.argv = sys.argv[1:]; "
                "runpy.run_path(sys.argv[0], run_name='__main__')")
    done = subprocess.run([sys.executable, "-c", hide_ray, script, "--backend", "ray", "--out", str(tmp_path)]
                          if script.endswith("table.py") else
                          [sys.executable, "-c", hide_ray, script, "--backend", "ray", "--episodes", "1"],
                          cwd=REPO, capture_output=True, text=True)
    assert done.returncode == 2, done.stderr[-2000:]
    assert 'pip install -e ".[scale]"' in done.stderr and "Traceback" not in done.stderr

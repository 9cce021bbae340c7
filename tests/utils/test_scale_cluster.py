"""Ray as a cluster's user runs it: ``ray start --head`` then ``--ray-address auto`` (the
cluster this machine belongs to), and ``baselines/reproduce_table.py --backend ray`` end to
end. Loopback only, no dashboard; one cluster at a time per test run
(:func:`tests.ray_cluster.one_cluster_at_a_time`)."""

from __future__ import annotations

import csv
import importlib.util
import json
import subprocess
import sys

import numpy as np
import pytest

from legent_gym.data.legent_format import load_trajectories
from legent_gym.data.minari_store import load_minari_dataset
from tests.conftest import REPO
from tests.data.test_data_collect import DATASET_ID, ENV_ID
from tests.ray_cluster import one_cluster_at_a_time, ray_start_head

HAS_RAY = importlib.util.find_spec("ray") is not None
needs_ray = pytest.mark.skipif(not HAS_RAY, reason='Ray is not installed (the "scale" extra: pip install -e ".[scale]")')
SIZE = ["--width", "32", "--height", "32"]
N = 4


def _collect(out, *backend: str, env=None) -> subprocess.CompletedProcess:
    """``legent-gym collect`` in a process of its own; it prints, after the collection, the
    GCS address of the Ray it used and that cluster's CPUs (nothing without Ray)."""
    script = ("import sys; from legent_gym.cli import main; code = main(sys.argv[1:]); "
              "ray = sys.modules.get('ray'); "
              "ray and ray.is_initialized() and print(ray.get_runtime_context().gcs_address, "
              "ray.cluster_resources()['CPU']); sys.exit(code)")
    return subprocess.run([sys.executable, "-c", script, "collect", ENV_ID, "--episodes", str(N), "--out", str(out),
                           "--format", "minari,legent", "--workers", "1", "--quiet", *SIZE, *backend],
                          cwd=REPO, env=env, capture_output=True, text=True, timeout=600)


@needs_ray
def test_collect_with_address_auto_joins_the_cluster_ray_start_made(tmp_path, tmp_path_factory):
    reference = _collect(tmp_path / "process")
    assert reference.returncode == 0, reference.stderr[-3000:]
    with one_cluster_at_a_time(tmp_path_factory), ray_start_head(cpus=2) as env:
        done = _collect(tmp_path / "ray", "--backend", "ray", "--ray-address", "auto", env=env)
        assert done.returncode == 0, done.stderr[-3000:]
        address, cpus = done.stdout.split()[-2:]
        # the head `ray start` made (2 CPUs), not a Ray of its own (--workers 1: 1 CPU)
        assert address == env["address"] and address.startswith("127.0.0.1:") and float(cpus) == 2.0
    # the same episodes as the process backend's
    assert load_trajectories(tmp_path / "ray" / "legent") == load_trajectories(tmp_path / "process" / "legent")
    ours, theirs = (list(load_minari_dataset(tmp_path / side / "minari", DATASET_ID).iterate_episodes())
                    for side in ("ray", "process"))
    assert len(ours) == len(theirs) == N
    for a, b in zip(ours, theirs):
        assert list(a.actions) == list(b.actions) and np.array_equal(a.observations["rgb"], b.observations["rgb"])


def _table(out, *backend: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, str(REPO / "baselines" / "reproduce_table.py"), "--scale", "small",
                           "--out", str(out), *backend], cwd=REPO, capture_output=True, text=True, timeout=1800)


@pytest.mark.slow
@needs_ray
def test_the_table_through_ray_equals_the_process_backend(tmp_path, tmp_path_factory):
    """``reproduce_table.py --backend ray --scale small`` (a Ray it starts for every phase)
    gives the process backend's table, evaluation episodes and model weights."""
    pytest.importorskip("torch", reason="install the 'baselines' extra: pip install -e '.[baselines]'")
    import torch

    from baselines.vla.checkpoint import read_checkpoint

    process = _table(tmp_path / "process")
    assert process.returncode == 0, process.stderr[-3000:]
    with one_cluster_at_a_time(tmp_path_factory):
        ray = _table(tmp_path / "ray", "--backend", "ray")
    assert ray.returncode == 0, ray.stderr[-3000:]

    tables = [list(csv.reader((tmp_path / side / "table.csv").open())) for side in ("process", "ray")]
    assert tables[0] == tables[1]
    results = [json.loads((tmp_path / side / "results.json").read_text()) for side in ("process", "ray")]
    assert results[0]["episodes"] == results[1]["episodes"]
    models = sorted(p.relative_to(tmp_path / "process") for p in (tmp_path / "process" / "models").glob("*/model.pt"))
    assert len(models) == 7  # 3 tasks x 2 amounts and the joint model
    for model in models:
        ours, theirs = (read_checkpoint(tmp_path / side / model)["weights"] for side in ("process", "ray"))
        assert ours.keys() == theirs.keys()
        assert all(torch.equal(ours[k], theirs[k]) for k in ours), model

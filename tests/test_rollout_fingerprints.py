"""Every env id still produces the episodes recorded in ``tests/fixtures/rollouts.json``.

The file pins observations (RGB, depth, segmentation), rewards, ends and infos of seeded
rollouts (see :mod:`tests.rollout_fingerprint`). A change that is meant to alter episodes
regenerates it with ``python -m tests.rollout_fingerprint`` and says why in its commit.
"""

import json

import pytest

from tests.rollout_fingerprint import PATH, cases, fingerprint, key

RECORDED = json.loads(PATH.read_text())


@pytest.mark.parametrize("case", cases(), ids=lambda c: key(*c))
def test_rollout_matches_recording(case):
    assert fingerprint(*case) == RECORDED[key(*case)]


def test_every_case_is_recorded():
    assert sorted(RECORDED) == sorted(key(*c) for c in cases())

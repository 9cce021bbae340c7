"""legent_gym.utils.heap: trimming only once the process has grown since the last trim."""

from __future__ import annotations

import pytest

from legent_gym.utils import heap


def test_resident_bytes_reads_this_process():
    size = heap.resident_bytes()
    if size is None:
        pytest.skip("no /proc here")
    assert size > 10 << 20  # an interpreter with NumPy and MuJoCo loaded


def test_trim_waits_for_growth():
    if not heap.trim():  # always trims (no threshold): False only without glibc's malloc_trim
        pytest.skip("the C library has no malloc_trim")
    # Right after a trim the process has not grown by a gigabyte: nothing to do.
    assert not heap.trim(min_growth=1 << 30)
    # 64 MiB more resident (bytearray zero-fills them): past a 32 MiB threshold.
    block = bytearray(64 << 20)
    assert heap.trim(min_growth=32 << 20)
    del block

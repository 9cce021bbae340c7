"""Handing the C heap's free memory back to the system (glibc's ``malloc_trim``).

A house's compiled model, meshes and grids are freed when the episode moves to another
house, but glibc keeps freed heap pages for reuse and returns them only when the top of a
heap is free; in between, the resident size of a process that builds a new house at every
reset climbs by fragmentation, where nothing leaks. :func:`trim` returns those pages;
:class:`legent_gym.envs.episode.Episode` calls it after a built house it does not keep is
dropped, once the process has grown by :data:`TRIM_GROWTH` since the last trim: the next
house reuses the pages the last one freed where they are kept, and trimming after every
house cost each reset the page faults that took the same pages back. ``python
benchmarks/soak.py --no-trim`` shows the resident size a process holds. Where the C library
is not glibc, :func:`trim` does nothing.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import functools
import os

__all__ = ["TRIM_GROWTH", "resident_bytes", "trim"]

#: Growth of the resident size (bytes) since the last trim above which
#: :class:`~legent_gym.envs.episode.Episode` trims.
TRIM_GROWTH = 16 << 20

#: The resident size right after the last trim (None before the first).
_after_trim: int | None = None


def resident_bytes() -> int | None:
    """This process's resident size, or None where ``/proc`` does not say."""
    try:
        with open("/proc/self/statm", "rb") as fh:
            return int(fh.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")
    except (OSError, ValueError, IndexError):
        return None


@functools.lru_cache(maxsize=1)
def _malloc_trim():
    try:
        libc = ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6")
        fn = libc.malloc_trim
    except (OSError, AttributeError):
        return None
    fn.argtypes = [ctypes.c_size_t]
    fn.restype = ctypes.c_int
    return fn


def trim(min_growth: int = 0) -> bool:
    """Return the free pages of every malloc arena to the system, if the resident size grew
    by more than ``min_growth`` bytes since the last trim (always where it cannot be read);
    whether it trimmed (False also where the C library has no ``malloc_trim``)."""
    global _after_trim
    fn = _malloc_trim()
    if fn is None:
        return False
    if min_growth > 0 and _after_trim is not None:
        now = resident_bytes()
        if now is not None and now <= _after_trim + min_growth:
            return False
    fn(0)
    _after_trim = resident_bytes()
    return True

"""Handing the C heap's free memory back to the system (glibc's ``malloc_trim``).

A house's compiled model, meshes and grids are freed when the episode moves to another
house, but glibc keeps freed heap pages for reuse and returns them only when the top of a
heap is free; in between, the resident size of a process that builds a new house at every
reset climbs by fragmentation, where nothing leaks. :func:`trim` returns those pages;
:class:`legent_gym.envs.episode.Episode` calls it after a built house it does not keep is
dropped. ``python benchmarks/soak.py --no-trim`` shows the resident size a process holds.
Where the C library is not glibc, :func:`trim` does nothing.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import functools

__all__ = ["trim"]


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


def trim() -> bool:
    """Return the free pages of every malloc arena to the system; False where the C
    library has no ``malloc_trim``."""
    fn = _malloc_trim()
    if fn is None:
        return False
    fn(0)
    return True

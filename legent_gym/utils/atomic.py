"""Atomic file writes: readers see the old file or the new one, never half of either.

Everything legent_gym writes (scenes, maps, datasets) goes through here: the data is
written to a temporary file in the target's directory, flushed to disk, then renamed over
the target (a rename within one directory is atomic on POSIX).
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path


def _default_mode() -> int:
    """The mode a plain ``open(path, "w")`` would give: 0o666 less the process umask."""
    umask = os.umask(0)
    os.umask(umask)
    return 0o666 & ~umask


def atomic_write_bytes(path: str | os.PathLike, data: bytes, *, durable: bool = True) -> None:
    """``durable=False`` skips the fsync (~5 ms here): the file is still whole or absent
    after a crashed process, only not guaranteed after a power cut. For bulk outputs that
    a later fsync or ``os.sync()`` makes durable together."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
            fh.flush()
            if durable:
                os.fsync(fh.fileno())
        os.chmod(tmp, _default_mode())  # mkstemp makes files private (0600); ours are ordinary files
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def atomic_write_text(path: str | os.PathLike, text: str, *, durable: bool = True) -> None:
    atomic_write_bytes(path, text.encode("utf-8"), durable=durable)

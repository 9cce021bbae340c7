"""A ``Text`` space whose values cross Gymnasium's ``AsyncVectorEnv`` shared memory intact.

``gym.make_vec(id, num_envs=N, vectorization_mode="async")`` sends observations from the
worker processes back through shared memory (``shared_memory=True``, the default). Gymnasium
1.4 reads the shared memory of a ``Text`` space once, when the vector env is made, into a
tuple of strings: unlike the array views it makes for ``Box`` spaces, the tuple never sees
what the workers write later, so every ``reset`` and ``step`` returns that first reading,
``max_length`` copies of the charset's first character (spaces, for our charsets). A toy
env with a plain ``gymnasium.spaces.Text`` observation does the same.

:class:`VectorSafeText` is a ``Text`` (equal to a plain one with the same bounds and
charset, serialised like one by Minari) with its own shared-memory functions, registered
with Gymnasium's ``create_shared_memory`` / ``write_to_shared_memory`` /
``read_from_shared_memory``: the memory holds each env's string as Unicode code points
(``max_length`` int32 per env, zero-padded), and the read gives a :class:`TextView` that
decodes the memory whenever it is read. The vector env returns a deep copy of its buffers
(``copy=True``, the default), which for a :class:`TextView` is a plain tuple of ``str``, as
the sync vector env returns; with ``copy=False`` the caller gets the view itself, which,
like the ``Box`` arrays then, shows the next step's values once it is taken.

Every ``Text`` observation of the envs and wrappers (:func:`legent_gym.envs.action_spaces.speech_space`,
the history wrapper) is a :class:`VectorSafeText`.
"""

from __future__ import annotations

import multiprocessing
from collections.abc import Iterator, Sequence
from types import ModuleType
from typing import Any, overload

import numpy as np
from gymnasium import spaces
from gymnasium.vector.utils import (
    create_shared_memory,
    read_from_shared_memory,
    write_to_shared_memory,
)

__all__ = ["TextView", "VectorSafeText"]


class VectorSafeText(spaces.Text):
    """``gymnasium.spaces.Text`` that survives ``AsyncVectorEnv``'s shared memory (see the
    module docstring); otherwise the same space."""


def _strings(space: VectorSafeText, shared_memory: Any, n: int) -> np.ndarray:
    """The first ``n`` envs' strings, as a NumPy string array viewing the shared memory
    (``str_`` items are UTF-32 code points, trailing zeros dropped on reading)."""
    return np.frombuffer(shared_memory.get_obj(), dtype=np.dtype((np.str_, space.max_length)), count=n)


class TextView(Sequence[str]):
    """The envs' current strings in a vector env's shared memory, decoded on every read.
    ``copy.deepcopy`` and ``copy.copy`` give a plain tuple of ``str``."""

    __slots__ = ("_strings",)

    def __init__(self, strings: np.ndarray):
        self._strings = strings

    @overload
    def __getitem__(self, index: int) -> str: ...

    @overload
    def __getitem__(self, index: slice) -> tuple[str, ...]: ...

    def __getitem__(self, index: int | slice) -> str | tuple[str, ...]:
        if isinstance(index, slice):
            return tuple(str(text) for text in self._strings[index])
        return str(self._strings[index])

    def __len__(self) -> int:
        return len(self._strings)

    def __iter__(self) -> Iterator[str]:
        return (str(text) for text in self._strings)

    def __eq__(self, other: object) -> bool:
        return tuple(self) == (tuple(other) if isinstance(other, TextView) else other)

    __hash__ = None  # type: ignore[assignment]  # mutable: its strings change with the memory

    def __copy__(self) -> tuple[str, ...]:
        return tuple(self)

    def __deepcopy__(self, memo: dict) -> tuple[str, ...]:
        return tuple(self)

    def __repr__(self) -> str:
        return f"TextView({tuple(self)!r})"


@create_shared_memory.register(VectorSafeText)
def _create_text_memory(space: VectorSafeText, n: int = 1, ctx: ModuleType = multiprocessing) -> Any:
    return ctx.Array(np.dtype(np.int32).char, n * space.max_length)


@read_from_shared_memory.register(VectorSafeText)
def _read_text_memory(space: VectorSafeText, shared_memory: Any, n: int = 1) -> TextView:
    return TextView(_strings(space, shared_memory, n))


@write_to_shared_memory.register(VectorSafeText)
def _write_text_memory(space: VectorSafeText, index: int, value: str, shared_memory: Any) -> None:
    if len(value) > space.max_length:
        raise ValueError(f"a text of {len(value)} characters does not fit its space's max_length={space.max_length}: "
                         f"{value[:40]!r}...")
    _strings(space, shared_memory, index + 1)[index] = value

"""The asset registry: asset ids -> factories that make an :class:`AssetModel` from a seed.

Built-in assets register themselves when :mod:`legent_gym.world.assets` is imported. Users
add their own with :func:`register` (a factory of their own) or
:func:`legent_gym.world.assets.gltf.register_gltf` (a glTF/GLB file).

A factory takes a ``numpy.random.Generator`` and returns an :class:`AssetModel`; the
generator is seeded from (asset id, variant), so an asset's look is a pure function of its
variant number. Made models are cached: they are immutable by convention.
"""

from __future__ import annotations

import dataclasses
import zlib
from collections.abc import Callable
from dataclasses import dataclass
from functools import lru_cache
from typing import Any

import numpy as np
from numpy.random.bit_generator import ISeedSequence

from legent_gym.world.assets.model import AssetModel

AssetFactory = Callable[[np.random.Generator], AssetModel]


@dataclass(frozen=True)
class AssetEntry:
    asset_id: str
    factory: AssetFactory
    builtin: bool
    #: The scene ``assets`` entry (an ImportedAsset) that builds this asset from its file,
    #: for an asset registered from an annotated glTF; None for the others.
    imported: Any = None


_ENTRIES: dict[str, AssetEntry] = {}
#: Bumped by every change of the registry (see :func:`version`).
_VERSION = 0


class UnknownAssetError(KeyError):
    def __str__(self) -> str:  # KeyError quotes its message; we want a sentence
        return self.args[0]


def register(asset_id: str, factory: AssetFactory, *, builtin: bool = False, replace: bool = False,
             imported: Any = None) -> None:
    """Make ``asset_id`` usable in scenes. ``replace=True`` overrides an existing id.
    ``imported``: the scene ``assets`` entry (:class:`~legent_gym.world.scene.ImportedAsset`)
    that builds the same model from its file; generators write it into the scenes that use
    the asset (see :func:`imported_entry`)."""
    if not asset_id or not isinstance(asset_id, str):
        raise ValueError("asset id must be a non-empty string")
    if asset_id in _ENTRIES and not replace:
        raise ValueError(f"asset id {asset_id!r} is already registered (pass replace=True to override)")
    _ENTRIES[asset_id] = AssetEntry(asset_id, factory, builtin, imported)
    _changed()


def imported_entry(asset_id: str) -> Any:
    """The scene ``assets`` entry registered with ``asset_id`` (None: none, or no such id)."""
    entry = _ENTRIES.get(asset_id)
    return None if entry is None else entry.imported


def unregister(asset_id: str) -> None:
    _ENTRIES.pop(asset_id, None)
    _changed()


def _changed() -> None:
    global _VERSION
    _VERSION += 1
    make.cache_clear()


def version() -> int:
    """A number that changes whenever an asset is registered or unregistered (what is
    derived from the registry, such as the generator's catalog, is kept until it does)."""
    return _VERSION


def has(asset_id: str) -> bool:
    return asset_id in _ENTRIES


def asset_ids(*, builtin: bool | None = None) -> list[str]:
    """Registered ids, sorted; ``builtin=True``/``False`` filters."""
    return sorted(k for k, e in _ENTRIES.items() if builtin is None or e.builtin == builtin)


def variant_rng(asset_id: str, variant: int) -> np.random.Generator:
    # crc32 rather than hash(): stable across processes (PYTHONHASHSEED).
    return np.random.default_rng([zlib.crc32(asset_id.encode()), int(variant)])


#: Variants 0..VARIANTS-1 of a built-in asset get :func:`variant_rng`'s generator from a
#: table of seeds made once per asset.
VARIANTS = 1000
#: The variants the house generator draws for an asset type: 0..GENERATED_VARIANTS-1, each
#: a different look (shape, proportions, parts, colours, materials). About 110 types give
#: some 3,500 distinct objects (ProcTHOR draws from 1,633 assets), few enough that a process
#: making house after house keeps every model it made (:data:`MODELS_KEPT`) and soon makes
#: none: a house costs its placement, not its models.
GENERATED_VARIANTS = 32
_SEEDS: dict[str, np.ndarray] = {}


class _Seeded(ISeedSequence):
    """A seed sequence that hands PCG64 the state words it was made with."""

    __slots__ = ("words",)

    def __init__(self, words: np.ndarray):
        self.words = words

    def generate_state(self, n_words: int, dtype=np.uint32) -> np.ndarray:
        if n_words != 4 or np.dtype(dtype) != np.uint64:
            raise ValueError("only PCG64's four 64-bit words are kept")
        return self.words


def _seed_table(entropy: int, n: int) -> np.ndarray:
    """``SeedSequence([entropy, v]).generate_state(4, np.uint64)`` for v = 0..n-1, (n, 4):
    NumPy's SeedSequence algorithm (a pool of four 32-bit words mixed by multiply-xorshift
    hashes whose constants do not depend on the entropy), on all variants at once."""
    mask = 0xFFFFFFFF
    hash_a, hash_b = 0x43B0D7E5, 0x8B51F9DD
    pool = [np.full(n, entropy, dtype=np.uint32), np.arange(n, dtype=np.uint32),
            np.zeros(n, dtype=np.uint32), np.zeros(n, dtype=np.uint32)]

    def hashmix(value: np.ndarray) -> np.ndarray:
        nonlocal hash_a
        value = value ^ np.uint32(hash_a)
        hash_a = (hash_a * 0x931E8875) & mask
        value = value * np.uint32(hash_a)
        return value ^ (value >> np.uint32(16))

    pool = [hashmix(word) for word in pool]
    for src in range(4):
        for dst in range(4):
            if src != dst:
                mixed: np.ndarray = pool[dst] * np.uint32(0xCA01F9DD) - hashmix(pool[src]) * np.uint32(0x4973F715)
                pool[dst] = mixed ^ (mixed >> np.uint32(16))
    words = []
    for i in range(8):
        value = pool[i % 4] ^ np.uint32(hash_b)
        hash_b = (hash_b * 0x58F38DED) & mask
        value = value * np.uint32(hash_b)
        words.append((value ^ (value >> np.uint32(16))).astype(np.uint64))
    return np.stack([words[k] | (words[k + 1] << np.uint64(32)) for k in range(0, 8, 2)], axis=1)


def _builtin_rng(asset_id: str, variant: int) -> np.random.Generator:
    """:func:`variant_rng`'s generator (the same stream), without its seed sequence's cost
    for a variant of the table; its ``bit_generator.seed_seq`` is not a SeedSequence (the
    built-in factories never spawn from it)."""
    if not 0 <= variant < VARIANTS:
        return variant_rng(asset_id, variant)
    table = _SEEDS.get(asset_id)
    if table is None:
        table = _SEEDS[asset_id] = _seed_table(zlib.crc32(asset_id.encode()), VARIANTS)
    # PCG64 takes any ISeedSequence; NumPy's type hints name SeedSequence only.
    return np.random.Generator(np.random.PCG64(_Seeded(table[variant])))  # type: ignore[arg-type]


#: Models :func:`make` keeps: every variant the house generator draws of every built-in
#: type (:data:`GENERATED_VARIANTS` each, and the shelved books' wider range), with room to
#: spare, about 5 KiB of geometry each (docs/performance.md, "Long runs and memory").
MODELS_KEPT = 4096


@lru_cache(maxsize=MODELS_KEPT)
def make(asset_id: str, variant: int = 0) -> AssetModel:
    """The asset's model for a variant (the last :data:`MODELS_KEPT` are cached)."""
    entry = _ENTRIES.get(asset_id)
    if entry is None:
        raise UnknownAssetError(f"unknown asset id {asset_id!r}; known ids: {', '.join(asset_ids())}")
    rng = _builtin_rng(asset_id, int(variant)) if entry.builtin else variant_rng(asset_id, variant)
    model = entry.factory(rng)
    if model.asset_id != asset_id:  # a factory shared by several ids: name this copy
        model = dataclasses.replace(model, asset_id=asset_id)
    return model


def describe(asset_id: str) -> AssetModel:
    """The annotations of an asset (its variant 0), for generators choosing what to place."""
    return make(asset_id, 0)


def by_category(category: str) -> list[str]:
    return [a for a in asset_ids() if describe(a).category == category]

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
    make.cache_clear()


def imported_entry(asset_id: str) -> Any:
    """The scene ``assets`` entry registered with ``asset_id`` (None: none, or no such id)."""
    entry = _ENTRIES.get(asset_id)
    return None if entry is None else entry.imported


def unregister(asset_id: str) -> None:
    _ENTRIES.pop(asset_id, None)
    make.cache_clear()


def has(asset_id: str) -> bool:
    return asset_id in _ENTRIES


def asset_ids(*, builtin: bool | None = None) -> list[str]:
    """Registered ids, sorted; ``builtin=True``/``False`` filters."""
    return sorted(k for k, e in _ENTRIES.items() if builtin is None or e.builtin == builtin)


def variant_rng(asset_id: str, variant: int) -> np.random.Generator:
    # crc32 rather than hash(): stable across processes (PYTHONHASHSEED).
    return np.random.default_rng([zlib.crc32(asset_id.encode()), int(variant)])


#: Models :func:`make` keeps. A generated house asks for about 100 models, 25 of them
#: distinct, and draws variants from a thousand per asset, so nearly every repeat is within
#: one house: over 200 new TwoRoom houses, 72% of the calls hit with 256 kept and 76% with
#: 4,096, which with their link geometry held about 30 MiB more (docs/performance.md, "Memory per env process").
MODELS_KEPT = 256


@lru_cache(maxsize=MODELS_KEPT)
def make(asset_id: str, variant: int = 0) -> AssetModel:
    """The asset's model for a variant (the last :data:`MODELS_KEPT` are cached)."""
    entry = _ENTRIES.get(asset_id)
    if entry is None:
        raise UnknownAssetError(f"unknown asset id {asset_id!r}; known ids: {', '.join(asset_ids())}")
    model = entry.factory(variant_rng(asset_id, variant))
    if model.asset_id != asset_id:  # a factory shared by several ids: name this copy
        model = dataclasses.replace(model, asset_id=asset_id)
    return model


def describe(asset_id: str) -> AssetModel:
    """The annotations of an asset (its variant 0), for generators choosing what to place."""
    return make(asset_id, 0)


def by_category(category: str) -> list[str]:
    return [a for a in asset_ids() if describe(a).category == category]

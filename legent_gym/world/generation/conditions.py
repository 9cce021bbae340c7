"""What a generated house must satisfy: :class:`HouseSpec`, its parsing, and the asset catalog
that conditions are checked against.

Conditions name objects by category or by what people call them ("an orange on the
sofa", "2 apples", "countertop"); :class:`Catalog` resolves names to registered categories
and raises :class:`GenerationError` with the known list for unknown ones.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from typing import Any

from pydantic import BaseModel, ConfigDict, Field, ValidationError, field_validator, model_validator

from legent_gym.world.assets import registry
from legent_gym.world.assets.model import AssetModel
from legent_gym.world.generation.roomtypes import normalise_room_types, parse_rooms, singular


class GenerationError(ValueError):
    """A house that cannot be generated; the message names the condition that failed."""


# ---------------------------------------------------------------------------------------
# The asset catalog, as generation sees it

#: Extra names for categories (the assets' own ``names`` are added to these).
SYNONYMS: dict[str, tuple[str, ...]] = {
    "cola_can": ("cola", "coke", "soda", "can", "soda can"),
    "kitchen_counter": ("countertop", "counter", "counter top", "kitchen countertop"),
    "sofa": ("couch",),
    "fridge": ("refrigerator",),
    "tv": ("television",),
    "tv_stand": ("tv cabinet", "media console"),
    "bookshelf": ("shelf", "bookcase", "book shelf"),
    "nightstand": ("night stand", "bedside table"),
    "floor_lamp": ("lamp",),
    "phone": ("cellphone", "cell phone", "mobile phone", "smartphone"),
    "remote": ("remote control",),
    "mug": ("coffee mug",),
    "plant": ("potted plant", "houseplant"),
    "toy": ("toy car", "teddy bear"),
    "dining_table": ("table",),
    "coffee_table": ("table",),
    "side_table": ("table",),
    "desk": ("table",),
}
_ARTICLES = re.compile(r"^(?:an?|the|some|one)\s+")
#: registry version -> its catalog (see Catalog.from_registry).
_CATALOG: dict[int, Catalog] = {}


def normalise_name(text: str) -> str:
    """Lower case, single spaces, no leading article, underscores as spaces."""
    t = " ".join(text.lower().replace("_", " ").replace("-", " ").split())
    return _ARTICLES.sub("", t).strip()


@dataclass
class Catalog:
    """A snapshot of the asset registry: ids per category and names to categories."""

    models: dict[str, AssetModel]
    by_category: dict[str, list[str]] = field(default_factory=dict)
    aliases: dict[str, list[str]] = field(default_factory=dict)
    #: Facts generation derives from the catalog alone, kept (see furnish.extra_rules).
    memo: dict[object, object] = field(default_factory=dict, repr=False, compare=False)

    def __post_init__(self) -> None:
        for asset_id in sorted(self.models):
            self.by_category.setdefault(self.models[asset_id].category, []).append(asset_id)
        for cat in sorted(self.by_category):
            names = {cat, cat.replace("_", " ")} | set(SYNONYMS.get(cat, ()))
            for asset_id in self.by_category[cat]:
                names |= {normalise_name(n) for n in self.models[asset_id].names}
            for name in sorted(names):
                targets = self.aliases.setdefault(normalise_name(name), [])
                if cat not in targets:
                    targets.append(cat)

    @classmethod
    def from_registry(cls) -> Catalog:
        """The catalog of the registry as it is now (one object, shared, until the registry
        changes: treat it as read-only)."""
        version = registry.version()
        cached = _CATALOG.get(version)
        if cached is None:
            _CATALOG.clear()
            cached = _CATALOG[version] = cls({a: registry.describe(a) for a in registry.asset_ids()})
        return cached

    @property
    def categories(self) -> list[str]:
        return sorted(self.by_category)

    def describe(self, category: str) -> AssetModel:
        """The annotations of the first asset of a category."""
        return self.models[self.by_category[category][0]]

    def is_small(self, category: str) -> bool:
        """Things that rest on surfaces and can be picked up (apples, mugs)."""
        return any(self.models[a].pickupable for a in self.by_category[category])

    def is_furniture(self, category: str) -> bool:
        return not self.is_small(category)

    def resolve(self, name: str, what: str = "object") -> list[str]:
        """Categories a name refers to (several for "table"). Raises
        :class:`GenerationError` with the known names when there is none."""
        key = normalise_name(name)
        for candidate in (key, " ".join(singular(w) for w in key.split())):
            if candidate in self.aliases:
                return list(self.aliases[candidate])
        known = ", ".join(self.categories) or "(the asset registry is empty)"
        raise GenerationError(f"unknown {what} category {name!r}; known categories: {known}")

    def resolve_one(self, name: str, what: str = "object") -> str:
        """The category a name refers to; the first one when the name is ambiguous."""
        return self.resolve(name, what)[0]


# ---------------------------------------------------------------------------------------
# The spec

_ON = re.compile(r"^\s*(?:(\d+)\s+)?(.+?)\s+(?:on|on top of|onto|in)\s+(.+?)\s*$")


def parse_on(text: str) -> tuple[str, str]:
    """("orange", "sofa") from "orange on sofa" or "an orange on the sofa"."""
    m = _ON.match(normalise_name(text))
    if not m:
        raise GenerationError(f"cannot read {text!r} as 'OBJECT on RECEPTACLE' (e.g. 'orange on sofa')")
    return normalise_name(m.group(2)), normalise_name(m.group(3))


class HouseSpec(BaseModel):
    """Everything a generated house is asked to be. All fields are optional conditions.

    ``rooms`` / ``room_options`` / ``n_rooms`` choose the room mix; ``area`` bounds the floor
    area (m^2); ``require`` lists furniture (or "X on Y" pairs) that must exist;
    ``require_on`` small objects that must rest on a receptacle category; ``object_counts``
    exact counts per category; ``density`` the mean number of small objects per receptacle
    surface (at most ``max_per_surface``); ``min_user_distance`` the least distance between
    the agent and user spawns (metres). Doors are open while a house is built and checked;
    ``door_openness`` is then given to every door leaf (0 closed, 1 open).
    """

    model_config = ConfigDict(extra="forbid")

    name: str | None = None
    rooms: list[str] | None = None
    room_options: list[list[str]] | None = None
    n_rooms: int | None = Field(default=None, ge=1, le=12)
    area: tuple[float, float] | None = None
    require: list[str] = Field(default_factory=list)
    require_on: list[tuple[str, str]] = Field(default_factory=list)
    object_counts: dict[str, int] = Field(default_factory=dict)
    density: float = Field(default=2.0, ge=0.0)
    max_per_surface: int = Field(default=3, ge=0)
    min_user_distance: float = Field(default=1.5, ge=0.0)
    user: bool = True
    wall_height: float = Field(default=3.0, ge=2.2, le=6.0)
    cell_size: tuple[float, float] = (2.0, 2.6)
    door_openness: float = Field(default=1.0, ge=0.0, le=1.0)
    windows: bool = True
    max_attempts: int = Field(default=20, ge=1)
    time_limit: float = Field(default=20.0, gt=0.0)

    @field_validator("rooms", mode="before")
    @classmethod
    def _rooms(cls, v: Any) -> Any:
        if isinstance(v, str):
            return parse_rooms(v)
        if v is not None and not isinstance(v, (list, tuple)):
            raise ValueError(f"rooms must list room types ('kitchen, bedroom' or a list), got {v!r}; "
                             "a number of rooms is n_rooms")
        return normalise_room_types(list(v)) if v is not None else None

    @field_validator("room_options", mode="before")
    @classmethod
    def _room_options(cls, v: Any) -> Any:
        if v is None:
            return None
        return [parse_rooms(o) if isinstance(o, str) else normalise_room_types(list(o)) for o in v]

    @field_validator("require", mode="before")
    @classmethod
    def _require(cls, v: Any) -> Any:
        return [v] if isinstance(v, str) else v

    @field_validator("require_on", mode="before")
    @classmethod
    def _require_on(cls, v: Any) -> Any:
        single_pair = isinstance(v, tuple) and len(v) == 2 and all(isinstance(x, str) for x in v)
        if isinstance(v, str) or single_pair:
            v = [v]
        return [parse_on(x) if isinstance(x, str) else tuple(x) for x in v]

    @field_validator("area")
    @classmethod
    def _area(cls, v: tuple[float, float] | None) -> tuple[float, float] | None:
        if v is not None and not (0 < v[0] <= v[1]):
            raise ValueError("area must be (min, max) with 0 < min <= max (square metres)")
        return v

    @field_validator("cell_size")
    @classmethod
    def _cell(cls, v: tuple[float, float]) -> tuple[float, float]:
        if not (1.5 <= v[0] <= v[1] <= 6.0):
            raise ValueError("cell_size must be (min, max) metres with 1.5 <= min <= max <= 6")
        return v

    @field_validator("object_counts")
    @classmethod
    def _counts(cls, v: dict[str, int]) -> dict[str, int]:
        for k, n in v.items():
            if n < 0:
                raise ValueError(f"object_counts[{k!r}] must be >= 0")
        return v

    @model_validator(mode="after")
    def _rooms_vs_count(self) -> HouseSpec:
        if self.rooms is not None and self.n_rooms is not None and len(self.rooms) > self.n_rooms:
            raise ValueError(f"n_rooms={self.n_rooms} but {len(self.rooms)} rooms were listed: {self.rooms}")
        return self

    def split_require(self) -> tuple[list[str], list[tuple[str, str]]]:
        """``require`` entries as (furniture names, extra "X on Y" pairs)."""
        names, pairs = [], []
        for item in self.require:
            if re.search(r"\s(on|onto|on top of)\s", f" {normalise_name(item)} "):
                pairs.append(parse_on(item))
            else:
                names.append(item)
        return names, pairs


#: The keyword arguments ``generate_house`` accepts (the spec's fields).
CONDITION_NAMES = tuple(HouseSpec.model_fields)


def make_spec(base: HouseSpec | None, conditions: dict[str, Any]) -> HouseSpec:
    """``base`` updated with the keyword conditions (``None`` values are ignored).

    Unknown keywords raise ``TypeError``; bad values raise :class:`GenerationError`.
    """
    unknown = [k for k in conditions if k not in HouseSpec.model_fields]
    if unknown:
        raise TypeError(f"generate_house() got unknown condition(s) {', '.join(map(repr, unknown))}; "
                        f"known: {', '.join(CONDITION_NAMES)}")
    data = base.model_dump(exclude_unset=True) if base is not None else {}
    given = {k: v for k, v in conditions.items() if v is not None}
    if "rooms" in given:
        data.pop("room_options", None)
    data.update(given)
    try:
        return HouseSpec.model_validate(data)
    except ValidationError as err:
        problems = "; ".join(f"{'.'.join(map(str, e['loc'])) or 'spec'}: {e['msg']}" for e in err.errors())
        raise GenerationError(f"invalid house conditions: {problems}") from None
    except ValueError as err:
        raise GenerationError(str(err)) from None

"""The plan's schema: :class:`ScenePlan` and its parts (pydantic models, version
:data:`PLAN_VERSION`), the relations' thresholds, :func:`load_plan`, and what the solver
returns (:class:`SolvedScene`, :class:`SolveReport`). The plan format is described in
:mod:`legent_gym.world.generation.plan`."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Literal

from pydantic import BaseModel, ConfigDict, Field, field_validator, model_validator

from legent_gym.world.scene import Scene

PLAN_VERSION = 1
RelationKind = Literal["near", "far", "against_wall", "middle", "facing", "in_front_of", "left_of", "right_of"]
#: Relations that name another object of the room.
TARGETED = frozenset({"near", "far", "facing", "in_front_of", "left_of", "right_of"})

#: Thresholds of the relations, as measured in the result (metres, degrees).
NEAR_GAP = 1.0  #: near: the footprints at most this far apart
FAR_DISTANCE = 2.5  #: far: the centres at least this far apart
WALL_CONTACT = 0.1  #: against_wall: the footprint at most this far from a wall face
MIDDLE_CLEARANCE = 0.5  #: middle: the footprint at least this far from every wall face
FACING_ANGLE = 30.0  #: facing: the front within this angle of the direction to the target
FRONT_ANGLE = 35.0  #: in_front_of: within this angle of the target's front direction...
SIDE_ANGLE = 50.0  #: left_of / right_of: within this angle of the target's left / right...
BESIDE_GAP = 1.5  #: ...and the footprints at most this far apart

MAX_OBJECTS = 160  #: objects (copies counted) in one plan


class Relation(BaseModel):
    """One soft relation of an object: ``kind``, and ``target`` (another object's name in
    the same room) for the kinds that relate two objects."""

    model_config = ConfigDict(extra="forbid")
    kind: RelationKind
    target: str | None = None

    @model_validator(mode="after")
    def _target(self) -> Relation:
        if self.kind in TARGETED and not self.target:
            raise ValueError(f"relation {self.kind!r} needs a target")
        if self.kind not in TARGETED and self.target:
            raise ValueError(f"relation {self.kind!r} takes no target")
        return self


class PlannedObject(BaseModel):
    """Objects of one kind in a room: ``name`` (unique in the room; what relations and
    ``on`` refer to), ``asset`` (a library category or a name for one; default: ``name``),
    ``count``, ``on`` (the object it stands on) and ``relations``."""

    model_config = ConfigDict(extra="forbid")
    name: str = Field(min_length=1, max_length=60)
    asset: str | None = Field(default=None, max_length=60)
    count: int = Field(default=1, ge=1, le=12)
    on: str | None = None
    relations: list[Relation] = Field(default_factory=list, max_length=8)


class PlannedRoom(BaseModel):
    """A room: ``name`` (unique in the plan), ``type`` (bedroom, living room, kitchen,
    bathroom, dining room, office, hallway, or a word for one), rough ``size`` in m^2."""

    model_config = ConfigDict(extra="forbid")
    name: str = Field(min_length=1, max_length=60)
    type: str = Field(min_length=1, max_length=40)
    size: float | None = Field(default=None, ge=3.0, le=60.0)
    objects: list[PlannedObject] = Field(default_factory=list, max_length=40)

    @model_validator(mode="after")
    def _names(self) -> PlannedRoom:
        names = [o.name for o in self.objects]
        dupes = sorted({n for n in names if names.count(n) > 1})
        if dupes:
            raise ValueError(f"object names repeat in room {self.name!r}: {', '.join(dupes)}")
        for o in self.objects:
            refs = [r.target for r in o.relations if r.target] + ([o.on] if o.on else [])
            for ref in refs:
                if ref not in names:
                    raise ValueError(f"object {o.name!r} in room {self.name!r} refers to {ref!r}, which the room "
                                     f"does not list (objects: {', '.join(names)})")
                if ref == o.name:
                    raise ValueError(f"object {o.name!r} in room {self.name!r} refers to itself")
        return self


class ScenePlan(BaseModel):
    """A house plan (see the module docstring and docs/llm.md)."""

    model_config = ConfigDict(extra="forbid")
    version: Literal[1] = 1
    name: str | None = Field(default=None, max_length=80)
    rooms: list[PlannedRoom] = Field(min_length=1, max_length=8)
    doors: list[tuple[str, str]] = Field(default_factory=list, max_length=28)

    @field_validator("rooms")
    @classmethod
    def _unique(cls, rooms: list[PlannedRoom]) -> list[PlannedRoom]:
        names = [r.name for r in rooms]
        dupes = sorted({n for n in names if names.count(n) > 1})
        if dupes:
            raise ValueError(f"room names repeat: {', '.join(dupes)}")
        return rooms

    @model_validator(mode="after")
    def _doors(self) -> ScenePlan:
        total = sum(o.count for r in self.rooms for o in r.objects)
        if total > MAX_OBJECTS:
            raise ValueError(f"the plan asks for {total} objects; at most {MAX_OBJECTS}")
        names = {r.name for r in self.rooms}
        for a, b in self.doors:
            for n in (a, b):
                if n not in names:
                    raise ValueError(f"door between {a!r} and {b!r}: no room {n!r} (rooms: {', '.join(sorted(names))})")
            if a == b:
                raise ValueError(f"door between {a!r} and itself")
        return self


@dataclass
class SolveReport:
    """What the solver did with a plan besides building it."""

    #: plan name -> library category it was mapped to (names that are no category).
    mapped: dict[str, str] = field(default_factory=dict)
    #: Dropped names and other changes to the plan.
    warnings: list[str] = field(default_factory=list)
    #: Everything asked for that the result lacks: objects, doors, relations (measured).
    unmet: list[str] = field(default_factory=list)
    #: "room/object" -> the scene object id of each copy (None: that copy was not placed).
    objects: dict[str, list[int | None]] = field(default_factory=dict)
    seconds: float = 0.0

    def lines(self) -> list[str]:
        out = [f"mapped {k!r} to the library category {v!r}" for k, v in self.mapped.items()]
        out += [f"warning: {w}" for w in self.warnings]
        out += [f"unmet: {u}" for u in self.unmet]
        return out


@dataclass
class SolvedScene:
    scene: Scene
    report: SolveReport


def load_plan(data: Any) -> ScenePlan:
    """A :class:`ScenePlan` from a dict (or a plan); ``pydantic.ValidationError`` if invalid."""
    return data if isinstance(data, ScenePlan) else ScenePlan.model_validate(data)

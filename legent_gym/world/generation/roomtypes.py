"""Room types: their sizes on the floor-plan grid, names, and what people call them."""

from __future__ import annotations

import re
from dataclasses import dataclass


@dataclass(frozen=True)
class RoomType:
    name: str  #: what people call it
    cells: tuple[int, int]  #: target size range, in grid cells (inclusive)
    #: A public room can hold the front door and links rooms (a hallway, a living room).
    public: bool = False
    #: Rooms narrower than two cells feel like corridors; penalised in the floor plan.
    wide: bool = True


ROOM_TYPES: dict[str, RoomType] = {
    "bedroom": RoomType("bedroom", (2, 4)),
    "living_room": RoomType("living room", (3, 6), public=True),
    "kitchen": RoomType("kitchen", (2, 3), public=True, wide=False),
    "bathroom": RoomType("bathroom", (1, 2), wide=False),
    "dining_room": RoomType("dining room", (2, 3), public=True),
    "office": RoomType("office", (2, 3)),
    "hallway": RoomType("hallway", (2, 3), public=True, wide=False),
}

#: Words (singular, lower case) that name a room type.
ROOM_WORDS: dict[str, str] = {
    "bedroom": "bedroom", "bed": "bedroom", "br": "bedroom", "bed room": "bedroom",
    "sleeping room": "bedroom", "guest room": "bedroom",
    "living room": "living_room", "living": "living_room", "lounge": "living_room",
    "sitting room": "living_room", "livingroom": "living_room", "living_room": "living_room",
    "family room": "living_room",
    "kitchen": "kitchen",
    "bathroom": "bathroom", "bath": "bathroom", "ba": "bathroom", "restroom": "bathroom",
    "washroom": "bathroom", "toilet": "bathroom", "wc": "bathroom", "bath room": "bathroom",
    "dining room": "dining_room", "dining": "dining_room", "dining_room": "dining_room",
    "diningroom": "dining_room",
    "office": "office", "study": "office", "home office": "office", "workroom": "office",
    "hallway": "hallway", "hall": "hallway", "corridor": "hallway", "entrance": "hallway",
    "entryway": "hallway", "foyer": "hallway",
}

_NUMBER_WORDS = {"one": 1, "a": 1, "an": 1, "single": 1, "two": 2, "three": 3, "four": 4,
                 "five": 5, "six": 6, "seven": 7, "eight": 8}
_FILLER = {"the", "and", "with", "plus", "room", "rooms", "house", "home", "apartment", "flat",
           "of", "in", "some", "bedded", "sized"}


def singular(word: str) -> str:
    """A plural English noun made singular (good enough for room and object names)."""
    if word.endswith("ies") and len(word) > 4:
        return word[:-3] + "y"
    if word.endswith(("ches", "shes", "xes", "sses", "toes")):
        return word[:-2]
    if word.endswith("s") and not word.endswith("ss") and len(word) > 2:
        return word[:-1]
    return word


def room_type_of(word: str) -> str | None:
    """The room type a word or phrase names ("Living Room", "baths"), else None."""
    w = " ".join(word.lower().replace("_", " ").replace("-", " ").split())
    if w.replace(" ", "_") in ROOM_TYPES:
        return w.replace(" ", "_")
    if w in ROOM_WORDS:
        return ROOM_WORDS[w]
    s = " ".join(singular(p) for p in w.split())
    return ROOM_WORDS.get(s)


def parse_rooms(text: str) -> list[str]:
    """Room types from a short description: "bedroom + living room", "2 bed 1 bath",
    "kitchen, living room, bathroom". Raises ``ValueError`` naming an unknown word."""
    tokens = re.findall(r"[a-z]+|\d+", text.lower().replace("_", " "))
    rooms: list[str] = []
    count: int | None = None
    i = 0
    while i < len(tokens):
        tok = tokens[i]
        if tok.isdigit() or (tok in _NUMBER_WORDS and i + 1 < len(tokens) and _is_room_start(tokens, i + 1)):
            count = int(tok) if tok.isdigit() else _NUMBER_WORDS[tok]
            i += 1
            continue
        two = " ".join(tokens[i:i + 2])
        if len(tokens) > i + 1 and (pair := room_type_of(two)) is not None and " " in two:
            rtype, i = pair, i + 2
        elif (single := room_type_of(tok)) is not None:
            rtype, i = single, i + 1
        elif tok in _FILLER or tok in _NUMBER_WORDS:
            i += 1
            continue
        else:
            known = ", ".join(sorted(ROOM_TYPES))
            raise ValueError(f"unknown room word {tok!r} in {text!r}; known room types: {known}")
        rooms.extend([rtype] * (1 if count is None else count))
        count = None
    if not rooms:
        raise ValueError(f"no room type in {text!r}; known room types: {', '.join(sorted(ROOM_TYPES))}")
    return rooms


def _is_room_start(tokens: list[str], i: int) -> bool:
    two = " ".join(tokens[i:i + 2])
    return room_type_of(tokens[i]) is not None or room_type_of(two) is not None


def normalise_room_types(rooms: list[str]) -> list[str]:
    """Map each entry (a type or a name) to its room type; raise ``ValueError`` if unknown."""
    out = []
    for r in rooms:
        rtype = room_type_of(r)
        if rtype is None:
            raise ValueError(f"unknown room type {r!r}; known room types: {', '.join(sorted(ROOM_TYPES))}")
        out.append(rtype)
    return out

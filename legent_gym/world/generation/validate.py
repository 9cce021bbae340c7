"""Is a house usable? :func:`check_house` lists what is wrong with a scene (generated or
written by hand); an empty list means the house passes.

Checked: rooms linked through doors; agent and user spawns on walkable floor and connected;
every room, every floor piece of furniture and every receptacle holding objects reachable
from the agent spawn (a standing point within reach, no wall between); nothing
interpenetrating (furniture footprints pairwise, furniture against walls, objects sharing a
surface); small objects inside a receptacle of what they rest on; the squares in front of
doors free of furniture; furniture inside the house.
"""

from __future__ import annotations

from itertools import combinations

import numpy as np

from legent_gym.world.assets import registry
from legent_gym.world.assets.gltf import scene_asset_model
from legent_gym.world.geometry import (
    bounding_box,
    boxes_overlap,
    door_keepout_squares,
    is_floor_furniture,
    overlap_matrix,
    penetration,
    points_in_polygon,
    points_in_rect,
    rect_corners,
    wall_boxes,
    yaw_of,
)
from legent_gym.world.navigation import NavGrid
from legent_gym.world.scene import ObjectInstance, Scene

#: Penetration (metres) tolerated before two shapes count as overlapping.
TOLERANCE = 1e-3


def check_house(scene: Scene, navgrid: NavGrid | None = None, *, reach: float = 1.0) -> list[str]:
    """Problems that make ``scene`` unusable, as sentences; ``[]`` if none.

    ``navgrid`` (built from this scene) is reused when given; ``reach`` is how far (metres)
    the agent reaches from where it stands."""
    nav = navgrid if navgrid is not None else NavGrid.from_scene(scene)
    feet = nav.footprints_for(scene)
    names = {o.id: f"object {o.id} ({o.asset})" for o in scene.objects}
    rests = resting_places(scene, feet)
    problems = check_doors_link_rooms(scene)
    problems += check_spawns(scene, nav)
    component = nav.component(scene.agent.position) if nav.is_walkable(scene.agent.position) else 0
    if component:
        problems += check_rooms_reachable(scene, nav, component)
        problems += check_objects_reachable(scene, nav, component, feet, names, reach, rests)
    problems += check_furniture_overlaps(scene, feet, names)
    problems += check_furniture_walls(scene, feet, names)
    problems += check_door_clearance(scene, feet, names)
    problems += check_surfaces(scene, feet, names, rests)
    problems += check_inside_house(scene, feet, names)
    return problems


# ---------------------------------------------------------------------------------------


def check_doors_link_rooms(scene: Scene) -> list[str]:
    parent = {r.id: r.id for r in scene.rooms}

    def find(x: str) -> str:
        while parent[x] != x:
            x = parent[x]
        return x

    for door in scene.doors:
        rooms = [r for r in door.connects if r in parent]
        for a, b in zip(rooms, rooms[1:]):
            parent[find(a)] = find(b)
    groups: dict[str, list[str]] = {}
    for r in scene.rooms:
        groups.setdefault(find(r.id), []).append(r.id)
    if len(groups) <= 1:
        return []
    parts = "; ".join(", ".join(g) for g in groups.values())
    return [f"rooms are not all linked by doors: separate groups {parts}"]


def check_spawns(scene: Scene, nav: NavGrid) -> list[str]:
    out = []
    if not nav.is_walkable(scene.agent.position):
        out.append(f"agent spawn {tuple(scene.agent.position)} is not on walkable floor")
    if scene.user is not None:
        if not nav.is_walkable(scene.user.position):
            out.append(f"user spawn {tuple(scene.user.position)} is not on walkable floor")
        elif not out and not nav.reachable(scene.agent.position, scene.user.position):
            out.append("user spawn cannot be reached from the agent spawn")
    return out


def check_rooms_reachable(scene: Scene, nav: NavGrid, component: int) -> list[str]:
    out = []
    for room in scene.rooms:
        mask = np.zeros(nav.shape, dtype=bool)
        nav.raster.fill_polygon(mask, np.asarray(room.polygon))
        if not (mask & (nav.labels == component)).any():
            out.append(f"room {room.id} has no walkable floor reachable from the agent spawn")
    return out


def resting_places(scene: Scene, feet: dict[int, np.ndarray]) -> dict[int, tuple[int, np.ndarray] | None]:
    """:func:`find_receptacle` of every object resting on another one of the scene, by
    object id (the checks below share it)."""
    by_id: dict[int, ObjectInstance] = {}
    for o in scene.objects:
        by_id.setdefault(o.id, o)  # the first of an id, as Scene.object finds it
    surfaces: dict[int, list[tuple[int, float, np.ndarray]]] = {}  # a shelf of books asks for the same ones
    out = {}
    for obj in scene.objects:
        if obj.on is None or obj.on not in by_id:
            continue
        support = by_id[obj.on]
        if support.id not in surfaces:
            surfaces[support.id] = receptacle_surfaces(scene, support)
        out[obj.id] = _resting_on(surfaces[support.id], obj, feet.get(obj.id))
    return out


def receptacle_surfaces(scene: Scene, support: ObjectInstance) -> list[tuple[int, float, np.ndarray]]:
    """(receptacle index, height, world corners) of each base-link receptacle of ``support``."""
    if not registry.has(support.asset) and all(a.id != support.asset for a in scene.assets):
        return []
    model = scene_asset_model(scene, support.asset, support.variant)
    s = np.asarray(support.scale)
    out = []
    for k, rec in enumerate(model.receptacles):
        if rec.link != "base":
            continue
        c, h = np.asarray(rec.center) * s[:2], np.asarray(rec.half_size) * s[:2]
        corners = rect_corners(support.position, (c[0] - h[0], c[1] - h[1], c[0] + h[0], c[1] + h[1]),
                               yaw_of(support))
        out.append((k, support.position[2] + rec.height * s[2], corners))
    return out


def _resting_on(surfaces: list[tuple[int, float, np.ndarray]], obj: ObjectInstance,
                footprint: np.ndarray | None) -> tuple[int, np.ndarray] | None:
    best = None
    for k, top, corners in surfaces:
        if abs(obj.position[2] - top) > 0.01:
            continue
        centre = footprint.mean(axis=0) if footprint is not None else np.asarray(obj.position[:2])
        if points_in_rect(centre[None, :], corners, TOLERANCE).all():
            return k, corners
        best = best or (k, corners)
    return best


def check_objects_reachable(scene: Scene, nav: NavGrid, component: int, feet: dict[int, np.ndarray],
                            names: dict[int, str], reach: float,
                            rests: dict[int, tuple[int, np.ndarray] | None] | None = None) -> list[str]:
    """Floor furniture, and every receptacle something rests on, need a standing point.
    ``rests``: :func:`resting_places`, if already found."""
    rests = resting_places(scene, feet) if rests is None else rests
    out = []
    for obj in scene.objects:
        if is_floor_furniture(obj) and obj.id in feet and not nav.can_reach(feet[obj.id], reach, component):
            out.append(f"{names[obj.id]} cannot be reached from the agent spawn")
    seen = set()
    for obj in scene.objects:
        if obj.on is None or obj.on not in names:
            continue
        found = rests[obj.id]
        if found is None or (obj.on, found[0]) in seen:
            continue
        seen.add((obj.on, found[0]))
        if not nav.can_reach(found[1], reach, component):
            out.append(f"receptacle {found[0]} of {names[obj.on]} holds objects but cannot be reached")
    return out


def find_receptacle(scene: Scene, support: ObjectInstance, obj: ObjectInstance,
                    footprint: np.ndarray | None) -> tuple[int, np.ndarray] | None:
    """(receptacle index, world corners) of the base-link receptacle of ``support`` that
    ``obj`` rests on: the one at its height holding the object's footprint centre."""
    return _resting_on(receptacle_surfaces(scene, support), obj, footprint)


# ---------------------------------------------------------------------------------------
# Overlaps (separating-axis test on rectangles given by their corners)


def check_furniture_overlaps(scene: Scene, feet: dict[int, np.ndarray], names: dict[int, str]) -> list[str]:
    floor = [o.id for o in scene.objects if is_floor_furniture(o) and o.id in feet]
    boxes = {i: bounding_box(feet[i]) for i in floor}
    out = []
    for i, j in combinations(floor, 2):
        if boxes_overlap(boxes[i], boxes[j]) and penetration(feet[i], feet[j]) > TOLERANCE:
            out.append(f"{names[i]} and {names[j]} overlap")
    return out


def check_furniture_walls(scene: Scene, feet: dict[int, np.ndarray], names: dict[int, str]) -> list[str]:
    walls = [(wid, c, bounding_box(c)) for wid, c in wall_boxes(scene)]
    out = []
    for obj in scene.objects:
        if not is_floor_furniture(obj) or obj.id not in feet:
            continue
        box = bounding_box(feet[obj.id])
        for wid, corners, wbox in walls:
            if boxes_overlap(box, wbox) and penetration(feet[obj.id], corners) > TOLERANCE:
                out.append(f"{names[obj.id]} goes into wall {wid}")
                break
    return out


def check_door_clearance(scene: Scene, feet: dict[int, np.ndarray], names: dict[int, str]) -> list[str]:
    walls = {w.id: w for w in scene.walls}
    floor = [o.id for o in scene.objects if is_floor_furniture(o) and o.id in feet]
    boxes = {i: bounding_box(feet[i]) for i in floor}
    out = []
    for door in scene.doors:
        wall = walls.get(door.wall)
        if wall is None:
            continue
        for sq in door_keepout_squares(wall, door):
            square = bounding_box(sq)
            for i in floor:
                if boxes_overlap(square, boxes[i]) and penetration(sq, feet[i]) > TOLERANCE:
                    out.append(f"{names[i]} blocks the space in front of {door.id}")
    return out


def check_surfaces(scene: Scene, feet: dict[int, np.ndarray], names: dict[int, str],
                   rests: dict[int, tuple[int, np.ndarray] | None] | None = None) -> list[str]:
    """Objects resting on something lie inside one of its receptacles, apart from each other.
    ``rests``: :func:`resting_places`, if already found."""
    rests = resting_places(scene, feet) if rests is None else rests
    out = []
    by_surface: dict[tuple[int, int], list[int]] = {}
    ids = {o.id for o in scene.objects}
    for obj in scene.objects:
        if obj.on is None or obj.on not in ids or obj.id not in feet:
            continue
        found = rests[obj.id]
        if found is None or not points_in_rect(feet[obj.id], found[1], TOLERANCE).all():
            out.append(f"{names[obj.id]} is not inside a receptacle of {names[obj.on]}")
            continue
        by_surface.setdefault((obj.on, found[0]), []).append(obj.id)
    for (host, _), members in by_surface.items():
        if len(members) < 2:
            continue
        # Only pairs whose bounding boxes overlap can interpenetrate (a row of books touches
        # nothing but its neighbours' boxes, and those only at their gaps).
        boxes = np.array([bounding_box(feet[i]) for i in members])
        near = overlap_matrix(boxes, boxes)
        for a, b in zip(*np.nonzero(np.triu(near, 1)), strict=True):
            i, j = members[int(a)], members[int(b)]
            if penetration(feet[i], feet[j]) > TOLERANCE:
                out.append(f"{names[i]} and {names[j]} overlap on {names[host]}")
    return out


def check_inside_house(scene: Scene, feet: dict[int, np.ndarray], names: dict[int, str]) -> list[str]:
    polys = [np.asarray(r.polygon) for r in scene.rooms]
    # Floor furniture, coverings and what hangs on walls (resting on nothing, never moving).
    floor = [obj for obj in scene.objects if obj.kind != "interactable" and obj.on is None and obj.id in feet]
    if not floor:
        return []
    # Every footprint's corners, drawn a little in, tested against each room at once.
    shrunk = np.concatenate([feet[obj.id] + (feet[obj.id].mean(axis=0) - feet[obj.id]) * 1e-3 for obj in floor])
    inside = np.zeros(len(shrunk), dtype=bool)
    for poly in polys:
        inside |= points_in_polygon(shrunk, poly)
    every = np.all(inside.reshape(len(floor), -1), axis=1)
    return [f"{names[obj.id]} is not inside the house" for obj, ok in zip(floor, every.tolist()) if not ok]

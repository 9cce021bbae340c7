"""Write the hand-laid example houses in ``examples/scenes/``.

The layouts (rooms, walls, doors, every piece of furniture and where it stands) are chosen
by hand below; only the filling of shelves and tables with small objects is a loop, so the
two-room house carries more than 80 objects. Run it again after changing the assets:

    python examples/make_example_scenes.py
"""

from __future__ import annotations

import math
from pathlib import Path

import legent_gym  # noqa: F401
from legent_gym.world.assets import registry
from legent_gym.world.scene import save_scene, validate_scene

OUT = Path(__file__).resolve().parent / "scenes"
SMALL = ["apple", "orange", "banana", "cola_can", "mug", "cup", "bowl", "plate", "bottle", "book",
         "vase", "laptop", "remote", "phone", "toy", "pear", "tomato"]


def wall(wid, start, end, rooms):
    return {"id": wid, "start": list(start), "end": list(end), "height": 3.0, "thickness": 0.1, "rooms": rooms}


def furniture(objects, asset, x, y, yaw, room, variant=0):
    objects.append({"id": len(objects), "asset": asset, "variant": variant, "position": [x, y, 0.0],
                    "rotation": [0.0, 0.0, float(yaw)], "kind": "static", "room": room})
    return objects[-1]


def fill_surfaces(objects, per_surface=3, start=0, skip=()):
    """Put up to ``per_surface`` small objects in a row along each base-link receptacle."""
    k = start
    for host in list(objects):
        if host["asset"] in skip:
            continue
        model = registry.make(host["asset"], host["variant"])
        yaw = math.radians(host["rotation"][2])
        c, s = math.cos(yaw), math.sin(yaw)
        for rec in model.receptacles:
            if rec.link != "base" or rec.clearance < 0.12:
                continue
            slots = _slots(rec, per_surface)
            for lx, ly in slots:
                item = SMALL[k % len(SMALL)]
                size = registry.make(item, k).size
                if max(size[0], size[1]) > 2 * min(rec.half_size) + 0.02 or size[2] > rec.clearance:
                    k += 1
                    continue
                x = host["position"][0] + c * lx - s * ly
                y = host["position"][1] + s * lx + c * ly
                objects.append({"id": len(objects), "asset": item, "variant": k, "kind": "interactable",
                                "position": [round(x, 4), round(y, 4), round(rec.height, 4)],
                                "rotation": [0.0, 0.0, float((k * 37) % 360)], "on": host["id"],
                                "room": host["room"]})
                k += 1
    return k


def _slots(rec, n):
    """Up to n points spread along the longer side of a receptacle, 0.25 m apart or more."""
    hx, hy = rec.half_size
    along_x = hx >= hy
    half = hx if along_x else hy
    count = max(1, min(n, int((2 * half) // 0.25)))
    pts = []
    for i in range(count):
        t = -half + (2 * half) * (i + 0.5) / count
        pts.append((rec.center[0] + t, rec.center[1]) if along_x else (rec.center[0], rec.center[1] + t))
    return pts


def one_room():
    objects = []
    # Yaw 0 faces an asset's front to +y, 90 to -x, 180 to -y, 270 to +x.
    furniture(objects, "bed", 1.7, 2.85, 180, "bedroom", 1)  # head against the north wall
    furniture(objects, "nightstand", 0.35, 3.7, 180, "bedroom", 2)
    furniture(objects, "wardrobe", 3.5, 0.4, 0, "bedroom", 3)
    furniture(objects, "dresser", 3.7, 3.7, 180, "bedroom", 4)
    furniture(objects, "plant", 0.35, 0.35, 0, "bedroom", 5)
    fill_surfaces(objects)
    return {
        "name": "one room (bedroom)",
        "rooms": [{"id": "bedroom", "type": "bedroom", "name": "bedroom",
                   "polygon": [[0, 0], [4.5, 0], [4.5, 4], [0, 4]],
                   "floor": {"material": "wood", "rgba": [0.62, 0.48, 0.33, 1]},
                   "wall": {"material": "paint", "rgba": [0.88, 0.86, 0.8, 1]}}],
        "walls": [wall("w_s", (0, 0), (4.5, 0), ["bedroom", "exterior"]),
                  wall("w_e", (4.5, 0), (4.5, 4), ["bedroom", "exterior"]),
                  wall("w_n", (4.5, 4), (0, 4), ["bedroom", "exterior"]),
                  wall("w_w", (0, 4), (0, 0), ["bedroom", "exterior"])],
        "doors": [{"id": "front", "wall": "w_s", "offset": 2.2, "width": 0.9, "openness": 0.0,
                   "connects": ["bedroom", "exterior"]}],
        "objects": objects,
        "agent": {"position": [3.3, 2.0], "yaw": 180.0},
        "user": {"position": [1.0, 1.2], "yaw": 45.0},
        "lights": [{"position": [2.25, 2.0, 2.8], "diffuse": [0.7, 0.7, 0.65]}],
    }


def two_room_furnished():
    objects = []
    b, lv = "bedroom", "living_room"
    # Bedroom: x in [0, 5], y in [0, 5]. Front of every asset faces +y in its own frame;
    # yaw turns it: 0 faces +y (north), 90 faces -x, 180 faces -y, 270 faces +x.
    furniture(objects, "bed", 2.5, 3.85, 180, b, 1)
    furniture(objects, "nightstand", 1.1, 4.7, 180, b, 2)
    furniture(objects, "nightstand", 3.9, 4.7, 180, b, 3)
    furniture(objects, "wardrobe", 0.4, 2.0, 270, b, 4)
    furniture(objects, "dresser", 2.2, 0.35, 0, b, 5)
    furniture(objects, "desk", 4.3, 1.5, 90, b, 6)
    furniture(objects, "chair", 3.6, 1.5, 270, b, 7)
    furniture(objects, "bookshelf", 3.6, 0.25, 0, b, 8)
    furniture(objects, "plant", 0.35, 0.35, 0, b, 9)
    furniture(objects, "floor_lamp", 4.65, 4.65, 0, b, 10)
    furniture(objects, "side_table", 0.4, 4.6, 0, b, 11)
    furniture(objects, "side_table", 4.6, 3.8, 0, b, 26)
    # Living room: x in [5, 11], y in [0, 5].
    furniture(objects, "sofa", 8.0, 4.45, 180, lv, 12)
    furniture(objects, "coffee_table", 8.0, 3.2, 0, lv, 13)
    tv_stand = furniture(objects, "tv_stand", 8.0, 0.3, 0, lv, 14)
    furniture(objects, "armchair", 10.3, 3.2, 90, lv, 15)
    furniture(objects, "side_table", 6.3, 4.6, 0, lv, 16)
    furniture(objects, "side_table", 9.6, 4.6, 0, lv, 17)
    furniture(objects, "dining_table", 6.6, 1.9, 0, lv, 18)
    furniture(objects, "chair", 6.6, 0.95, 0, lv, 19)
    furniture(objects, "chair", 6.6, 2.85, 180, lv, 20)
    furniture(objects, "bookshelf", 10.75, 1.4, 90, lv, 21)
    furniture(objects, "kitchen_counter", 9.9, 0.35, 0, lv, 22)
    furniture(objects, "plant", 5.4, 4.6, 0, lv, 23)
    furniture(objects, "fridge", 5.45, 0.4, 0, lv, 24)
    stand_top = max(r.height for r in registry.make("tv_stand", 14).receptacles)
    objects.append({"id": len(objects), "asset": "tv", "variant": 25, "kind": "static",
                    "position": [tv_stand["position"][0], tv_stand["position"][1], round(stand_top, 4)],
                    "rotation": [0.0, 0.0, 0.0], "on": tv_stand["id"], "room": lv})
    fill_surfaces(objects, skip=("tv_stand",))
    return {
        "name": "two rooms, furnished (bedroom + living room)",
        "rooms": [
            {"id": b, "type": "bedroom", "name": "bedroom", "polygon": [[0, 0], [5, 0], [5, 5], [0, 5]],
             "floor": {"material": "wood", "rgba": [0.6, 0.45, 0.3, 1]},
             "wall": {"material": "paint", "rgba": [0.85, 0.82, 0.9, 1]}},
            {"id": lv, "type": "living_room", "name": "living room", "polygon": [[5, 0], [11, 0], [11, 5], [5, 5]],
             "floor": {"material": "tile", "rgba": [0.75, 0.72, 0.66, 1]},
             "wall": {"material": "paint", "rgba": [0.9, 0.88, 0.78, 1]}},
        ],
        "walls": [
            wall("w_s1", (0, 0), (5, 0), [b, "exterior"]), wall("w_s2", (5, 0), (11, 0), [lv, "exterior"]),
            wall("w_e", (11, 0), (11, 5), [lv, "exterior"]),
            wall("w_n2", (11, 5), (5, 5), [lv, "exterior"]), wall("w_n1", (5, 5), (0, 5), [b, "exterior"]),
            wall("w_w", (0, 5), (0, 0), [b, "exterior"]),
            wall("w_mid", (5, 0), (5, 5), [b, lv]),
        ],
        "doors": [
            {"id": "inner", "wall": "w_mid", "offset": 3.0, "width": 0.9, "hinge": "start", "swing": "left",
             "openness": 1.0, "connects": [b, lv]},
            {"id": "front", "wall": "w_n2", "offset": 0.6, "width": 0.95, "openness": 0.0,
             "connects": [lv, "exterior"]},
        ],
        "windows": [{"id": "win_b", "wall": "w_w", "offset": 3.4, "width": 1.2, "height": 1.2, "sill": 0.9},
                    {"id": "win_l", "wall": "w_e", "offset": 2.4, "width": 1.4, "height": 1.2, "sill": 0.9}],
        "objects": objects,
        "agent": {"position": [2.0, 2.2], "yaw": 0.0},
        "user": {"position": [8.6, 2.3], "yaw": 180.0},
        "lights": [{"position": [2.5, 2.5, 2.8], "diffuse": [0.6, 0.6, 0.55]},
                   {"position": [8.0, 2.5, 2.8], "diffuse": [0.6, 0.6, 0.55]}],
    }


def main() -> None:
    for name, make in (("one_room", one_room), ("two_room_furnished", two_room_furnished)):
        scene = validate_scene(make())
        save_scene(scene, OUT / f"{name}.json")
        print(f"wrote {OUT / name}.json: {len(scene.objects)} objects")


if __name__ == "__main__":
    main()

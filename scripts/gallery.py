"""Pictures of generated homes for docs/gallery.md: one room of each type, seen from inside
at eye level in both render profiles, and the top-down map of one house.

    python scripts/gallery.py [--out docs/images/gallery] [--size 448] [--seed 0]

Each room type is shown in the first Apartment house from ``--seed`` up that has one, without
the people (each episode puts them elsewhere), from the spot near a corner whose small preview
shows the most of its furniture and the least of other rooms, door leaves and close-ups. Seeds
are fixed and nothing is random: the same command gives the same pictures.
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

import cv2
import numpy as np

from legent_gym.utils.atomic import atomic_write_bytes
from legent_gym.world.builder import World, build_world
from legent_gym.world.generation import generate_house
from legent_gym.world.geometry import inside_polygon, polygon_centroid
from legent_gym.world.render import FREE_FOVY, FreeCamera, Renderer
from legent_gym.world.scene import Room, Scene, Spawn
from legent_gym.world.topdown_map import save_topdown_map

PRESET = "Apartment"
ROOM_TYPES = ("living_room", "kitchen", "bedroom", "bathroom", "dining_room", "office")
SEEDS_TRIED = 50  # the first few seeds have every type; this only bounds the search
LOOK_HEIGHT = 0.6  # metres: below a table top, so the floor and the furniture fill the frame
ELEVATION = -25.0  # degrees: a person's eyes looking a little down
TOWARD_CORNER = 0.65  # how far from the centroid towards a corner the camera stands
TURNS = (0.0, -15.0, 15.0)  # degrees beside the centroid: a little aside may miss a doorway
PREVIEW = 64  # pixels: enough to tell what a view shows, cheap to render for every candidate
NEAR = 1.5  # metres: what is closer than this to the lens fills the picture
JPEG = [cv2.IMWRITE_JPEG_QUALITY, 85]  # about 15 KB a picture: the repository stays small


def _views(room: Room) -> list[FreeCamera]:
    """Candidate eye-level views of the room from inside it."""
    polygon = np.asarray(room.polygon, dtype=float)
    centroid = polygon_centroid(polygon)
    views = []
    for corner in polygon:
        spot = centroid + TOWARD_CORNER * (corner - centroid)
        if not inside_polygon(spot[0], spot[1], polygon):  # past an L-shaped room's inner corner
            continue
        (dx, dy), reach = centroid - spot, math.dist(centroid, spot)
        for turn in TURNS:
            azimuth = math.atan2(dy, dx) + math.radians(turn)
            x, y = spot + reach * np.array([math.cos(azimuth), math.sin(azimuth)])
            views.append(FreeCamera((float(x), float(y), LOOK_HEIGHT),
                                    distance=reach / math.cos(math.radians(ELEVATION)),
                                    azimuth=math.degrees(azimuth),  # the free camera looks along it
                                    elevation=ELEVATION))
    return views


def _plan_points(view: FreeCamera, depth: np.ndarray) -> np.ndarray:
    """(H, W, 2): where on the plan (x, y) each pixel of a depth image from ``view`` is."""
    az, el = math.radians(view.azimuth), math.radians(view.elevation)
    forward = np.array([math.cos(el) * math.cos(az), math.cos(el) * math.sin(az), math.sin(el)])
    right = np.array([math.sin(az), -math.cos(az), 0.0])
    (h, w), half = depth.shape, math.tan(math.radians(FREE_FOVY) / 2)  # of the picture's height
    across = (2 * (np.arange(w) + 0.5) / w - 1) * half * w / h
    down = (1 - 2 * (np.arange(h) + 0.5) / h) * half
    rays = forward + across[None, :, None] * right + down[:, None, None] * np.cross(right, forward)
    eye = np.asarray(view.lookat) - view.distance * forward
    return (eye + depth[..., None] * rays)[..., :2]


def _best_view(world: World, room: Room) -> FreeCamera:
    """The candidate view whose preview shows the most pieces of the room's furniture (a
    whole one counts more), less what shows other rooms (through a doorway) and door
    leaves, and what stands close in front of the lens or fills the picture."""
    furniture = [o.id for o in world.scene.objects if o.room == room.id and o.kind == "static"]
    others = [np.asarray(r.polygon) for r in world.scene.rooms if r.id != room.id]
    # The floor may come close: it is under the lens (the flat floors' geom, and a geom per
    # patterned floor).
    floors = [g for g in range(world.model.ngeom) if world.model.geom(g).name.split("_")[0] == "floors"]
    renderer = Renderer(world, PREVIEW, PREVIEW, "fast")

    def score(view: FreeCamera) -> float:
        geoms, depth = renderer.geom_ids(view), renderer.depth(view)
        ids, xy = world.geom_segment_lookup(geoms), _plan_points(view, depth)
        elsewhere = np.isin(geoms, list(world.geom_door))
        for polygon in others:
            elsewhere |= inside_polygon(xy[..., 0], xy[..., 1], polygon)
        shares = np.array([(ids == i).mean() for i in furniture])
        cut = np.isin(furniture, np.concatenate([ids[:, 0], ids[:, -1]]))  # at the picture's side
        pieces = float(((shares > 0.01) * np.where(cut, 0.5, 1.0)).sum())
        near = float(((depth < NEAR) & ~np.isin(geoms, floors)).mean())
        big = max(0.0, float(shares.max(initial=0)) - 0.3)  # one piece over 30%: a close-up
        return pieces - 8 * float(elsewhere.mean()) - 10 * (near + big)

    views = _views(room)
    scores = [score(view) for view in views]
    renderer.close()
    return views[int(np.argmax(scores))]  # ties: the first


def _find_rooms(seeds: range) -> dict[str, tuple[int, Scene, Room]]:
    """Room type -> (seed, house, room): the first house of ``seeds`` that has it."""
    found: dict[str, tuple[int, Scene, Room]] = {}
    for seed in seeds:
        scene = generate_house(seed, PRESET)
        for room in scene.rooms:
            found.setdefault(room.type, (seed, scene, room))
        if all(t in found for t in ROOM_TYPES):
            break
    return found


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default="docs/images/gallery")
    parser.add_argument("--size", type=int, default=448)
    parser.add_argument("--seed", type=int, default=0, help="the first house seed tried")
    args = parser.parse_args(argv)
    out, seeds = Path(args.out), range(args.seed, args.seed + SEEDS_TRIED)

    found = _find_rooms(seeds)
    for room_type in ROOM_TYPES:
        if room_type not in found:
            print(f"skipped {room_type}: no {PRESET} house of seeds {seeds.start} to {seeds[-1]} has one")
            continue
        seed, scene, room = found[room_type]
        # Without the people: the agent stands far outside; with no user, its avatar is parked.
        nobody = {"agent": Spawn(position=(-100.0, -100.0)), "user": None}
        world = build_world(scene.model_copy(update=nobody))
        view = _best_view(world, room)
        for profile in ("fast", "pretty"):
            renderer = Renderer(world, args.size, args.size, profile)
            ok, jpeg = cv2.imencode(".jpg", cv2.cvtColor(renderer.rgb(view), cv2.COLOR_RGB2BGR), JPEG)
            renderer.close()
            path = out / f"{room_type}_{profile}.jpg"
            if not ok:
                raise OSError(f"could not encode a JPEG for {path}")
            atomic_write_bytes(path, jpeg.tobytes())  # an interrupted run leaves no half-written file
            print(f"wrote {path} ({PRESET} seed {seed}, {room.name})")

    path = out / "map.png"
    save_topdown_map(generate_house(args.seed, PRESET), path)  # its default size: labels need it
    print(f"wrote {path} ({PRESET} seed {args.seed}, top-down map)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

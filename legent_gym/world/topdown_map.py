"""A top-down map of a scene drawn with OpenCV: floors, walls, doors, furniture, objects,
spawns and an optional path. Works from the scene data alone (no renderer)."""

from __future__ import annotations

import math
import os
import tempfile
from collections.abc import Mapping, Sequence
from pathlib import Path

import cv2
import numpy as np

from legent_gym.world.assets import registry
from legent_gym.world.geometry import (
    door_hinge_point,
    door_passable,
    door_swing_normal,
    is_floor_furniture,
    object_footprint,
    opening_span,
    wall_frame,
    wall_solid_spans,
)
from legent_gym.world.navigation import NavGrid
from legent_gym.world.scene import Scene

BACKGROUND = (245, 245, 245)
WALL = (60, 60, 60)
WINDOW = (120, 180, 230)
DOOR = (150, 90, 40)
FURNITURE = (175, 150, 120)
FURNITURE_EDGE = (90, 70, 50)
SMALL = (200, 60, 60)
AGENT = (40, 110, 220)
USER = (40, 170, 70)
PATH = (230, 120, 20)
LABEL = (30, 30, 30)
FONT = cv2.FONT_HERSHEY_SIMPLEX


class _View:
    """World metres -> image pixels (y flipped so +y points up)."""

    def __init__(self, scene: Scene, size: int, pad_px: int = 16):
        (x0, y0), (x1, y1) = scene.bounds()
        span = max(x1 - x0, y1 - y0, 1e-6)
        self.scale = (size - 2 * pad_px) / span
        self.w = int(math.ceil((x1 - x0) * self.scale)) + 2 * pad_px
        self.h = int(math.ceil((y1 - y0) * self.scale)) + 2 * pad_px
        self.x0, self.y1, self.pad = x0, y1, pad_px

    def px(self, pts) -> np.ndarray:
        p = np.asarray(pts, dtype=np.float64).reshape(-1, 2)
        u = (p[:, 0] - self.x0) * self.scale + self.pad
        v = (self.y1 - p[:, 1]) * self.scale + self.pad
        return np.round(np.column_stack([u, v])).astype(np.int32)

    def pt(self, xy) -> tuple[int, int]:
        u, v = self.px(xy)[0]
        return int(u), int(v)


def _rgb(rgba: Sequence[float]) -> tuple[int, int, int]:
    r, g, b = (int(round(255 * c)) for c in rgba[:3])
    return r, g, b


def _label(img: np.ndarray, text: str, at: tuple[int, int], scale: float) -> None:
    (tw, th), _ = cv2.getTextSize(text, FONT, scale, 1)
    org = (int(at[0] - tw / 2), int(at[1] + th / 2))
    cv2.putText(img, text, org, FONT, scale, (255, 255, 255), 3, cv2.LINE_AA)
    cv2.putText(img, text, org, FONT, scale, LABEL, 1, cv2.LINE_AA)


def _asset_name(asset_id: str) -> str:
    if registry.has(asset_id):
        return registry.describe(asset_id).names[0]
    return asset_id.replace("_", " ")


def draw_topdown_map(scene: Scene, *, size: int = 800, path: Sequence[Sequence[float]] | None = None,
                     navgrid: NavGrid | None = None, labels: bool = True,
                     people: Mapping[str, Sequence[float]] | None = None) -> np.ndarray:
    """An RGB image (H, W, 3) uint8 of the scene seen from above; its longer side is about
    ``size`` pixels. ``path``: points to draw as a polyline; ``navgrid``: walkable cells are
    tinted; ``people``: ``{"agent": (x, y, yaw), "user": (x, y, yaw)}`` where to draw the
    people (default: their spawns in the scene), each as a person seen from above
    (shoulders, head, nose) with an arrow along the heading."""
    view = _View(scene, size)
    img = np.full((view.h, view.w, 3), BACKGROUND, dtype=np.uint8)
    for room in scene.rooms:
        cv2.fillPoly(img, [view.px(room.polygon)], _rgb(room.floor.rgba))
    if navgrid is not None:
        _tint_walkable(img, view, navgrid)
    _draw_walls(img, view, scene)
    _draw_objects(img, view, scene, labels)
    if labels:
        for room in scene.rooms:
            c = np.asarray(room.polygon).mean(axis=0)
            _label(img, room.name, view.pt(c), 0.5)
    if path is not None and len(path) >= 2:
        cv2.polylines(img, [view.px(path)], False, PATH, 2, cv2.LINE_AA)
        for p in path:
            cv2.circle(img, view.pt(p), 3, PATH, -1, cv2.LINE_AA)
    if people is None:
        people = {name: (*spawn.position, spawn.yaw) for name, spawn in (("agent", scene.agent), ("user", scene.user))
                  if spawn is not None}
    _draw_people(img, view, people)
    return img


def _tint_walkable(img: np.ndarray, view: _View, nav: NavGrid) -> None:
    rows, cols = np.nonzero(nav.walkable)
    if len(rows) == 0:
        return
    xs = nav.origin[0] + (cols + 0.5) * nav.resolution
    ys = nav.origin[1] + (rows + 0.5) * nav.resolution
    p = view.px(np.column_stack([xs, ys]))
    ok = (p[:, 0] >= 0) & (p[:, 0] < view.w) & (p[:, 1] >= 0) & (p[:, 1] < view.h)
    mask = np.zeros(img.shape[:2], dtype=np.uint8)
    r = max(1, int(round(nav.resolution * view.scale / 2)))
    for u, v in p[ok]:
        mask[max(0, v - r):v + r + 1, max(0, u - r):u + r + 1] = 1
    sel = mask.astype(bool)
    img[sel] = (0.7 * img[sel] + 0.3 * np.array([120, 220, 120])).astype(np.uint8)


def _draw_walls(img: np.ndarray, view: _View, scene: Scene) -> None:
    thick = max(2, int(round(0.1 * view.scale)))
    for wall in scene.walls:
        start, u, _, _ = wall_frame(wall)
        doors = [d for d in scene.doors if d.wall == wall.id]
        for a, b in wall_solid_spans(wall, doors):
            cv2.line(img, view.pt(start + u * a), view.pt(start + u * b), WALL, thick, cv2.LINE_AA)
        for win in scene.windows:
            if win.wall == wall.id:
                a, b = opening_span(win)
                cv2.line(img, view.pt(start + u * a), view.pt(start + u * b), WINDOW, max(1, thick // 2), cv2.LINE_AA)
        for door in doors:
            _draw_door(img, view, wall, door, thick)


def _draw_door(img, view, wall, door, thick) -> None:
    start, u, _, _ = wall_frame(wall)
    lo, hi = opening_span(door)
    a, b = start + u * lo, start + u * hi
    if not door_passable(door):  # closed: a leaf across the opening
        cv2.line(img, view.pt(a), view.pt(b), DOOR, max(2, thick // 2), cv2.LINE_AA)
        return
    if not door.leaf:
        return
    hinge = door_hinge_point(wall, door)
    n = door_swing_normal(wall, door)
    angle = door.openness * math.pi / 2
    closed_dir = (b - a) / door.width * (1 if door.hinge == "start" else -1)
    leaf_dir = closed_dir * math.cos(angle) + n * math.sin(angle)
    cv2.line(img, view.pt(hinge), view.pt(hinge + leaf_dir * door.width), DOOR, 2, cv2.LINE_AA)
    arc = [hinge + door.width * (closed_dir * math.cos(t) + n * math.sin(t)) for t in np.linspace(0, angle, 12)]
    cv2.polylines(img, [view.px(arc)], False, DOOR, 1, cv2.LINE_AA)


def _draw_objects(img: np.ndarray, view: _View, scene: Scene, labels: bool) -> None:
    # Furniture (and static pieces standing on it, like a tv) as rectangles; the rest as dots.
    floor = [o for o in scene.objects if is_floor_furniture(o) or o.kind == "static"]
    drawn = {o.id for o in floor}
    for obj in floor:
        fp = object_footprint(scene, obj)
        if fp is None:
            continue
        poly = view.px(fp)
        cv2.fillPoly(img, [poly], FURNITURE if obj.on is None else (150, 130, 160))
        cv2.polylines(img, [poly], True, FURNITURE_EDGE, 1, cv2.LINE_AA)
        # A tick on the front edge (+y of the asset) shows which way it faces.
        front = (fp[2] + fp[3]) / 2
        centre = fp.mean(axis=0)
        cv2.line(img, view.pt(centre), view.pt(centre + (front - centre) * 0.8), FURNITURE_EDGE, 1, cv2.LINE_AA)
    if labels:
        for obj in floor:
            fp = object_footprint(scene, obj)
            if fp is not None:
                _label(img, _asset_name(obj.asset), view.pt(fp.mean(axis=0)), 0.35)
    for obj in scene.objects:
        if obj.id in drawn:
            continue
        p = view.pt(obj.position[:2])
        cv2.circle(img, p, 4, SMALL, -1, cv2.LINE_AA)
        if labels:
            _label(img, _asset_name(obj.asset), (p[0], p[1] - 8), 0.3)


def _draw_people(img: np.ndarray, view: _View, people: Mapping[str, Sequence[float]]) -> None:
    """Each person from above: an ellipse across the shoulders, the head, a nose, and an
    arrow along the heading."""
    for name, pose in people.items():
        colour = AGENT if name == "agent" else USER
        x, y, yaw_deg = float(pose[0]), float(pose[1]), float(pose[2])
        yaw = math.radians(yaw_deg)
        forward, left = np.array([math.cos(yaw), math.sin(yaw)]), np.array([-math.sin(yaw), math.cos(yaw)])
        centre = np.array([x, y])
        shoulders = [centre + 0.22 * left * math.cos(a) + 0.11 * forward * math.sin(a)
                     for a in np.linspace(0, 2 * math.pi, 24, endpoint=False)]
        cv2.fillPoly(img, [view.px(shoulders)], colour, cv2.LINE_AA)
        cv2.circle(img, view.pt(centre), max(2, int(round(0.1 * view.scale))), (40, 40, 40), -1, cv2.LINE_AA)
        cv2.circle(img, view.pt(centre + 0.1 * forward), max(1, int(round(0.03 * view.scale))), (40, 40, 40), -1,
                   cv2.LINE_AA)
        cv2.arrowedLine(img, view.pt(centre + 0.15 * forward), view.pt(centre + 0.6 * forward), colour, 2,
                        cv2.LINE_AA, tipLength=0.35)
        r = max(4, int(round(0.25 * view.scale)))
        p = view.pt(centre)
        _label(img, name, (p[0], p[1] + r + 8), 0.4)


def save_topdown_map(scene: Scene, path_png: str | os.PathLike, **kw) -> None:
    """Draw the map (see :func:`draw_topdown_map`) and write it as PNG, atomically."""
    path = Path(path_png)
    path.parent.mkdir(parents=True, exist_ok=True)
    img = draw_topdown_map(scene, **kw)
    ok, buf = cv2.imencode(".png", cv2.cvtColor(img, cv2.COLOR_RGB2BGR))
    if not ok:
        raise OSError(f"could not encode a PNG for {path}")
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(buf.tobytes())
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise

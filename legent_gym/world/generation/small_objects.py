"""Small objects on receptacle surfaces: required ones first, exact counts, then a random
sprinkling at the requested density (at most ``max_per_surface`` per surface).

A surface is one receptacle of a placed piece (only receptacles on the ``base`` link: a
drawer's inside moves with the drawer). Objects lie fully inside the receptacle's
rectangle, turned by the furniture's yaw plus a small random yaw, without overlapping each
other or a piece standing there (a tv), and no taller than the receptacle's clearance.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from legent_gym.world.assets import registry
from legent_gym.world.assets.model import Receptacle
from legent_gym.world.generation.conditions import Catalog
from legent_gym.world.generation.furnish import Placed, PlacementFailed
from legent_gym.world.geometry import (
    QUARTER_TURNS,
    local_footprint,
    rect_corners,
    turned_rect,
)

#: Furniture category -> small-object categories that plausibly rest on it.
PLAUSIBLE: dict[str, tuple[str, ...]] = {
    "kitchen_counter": ("apple", "orange", "banana", "pear", "tomato", "mug", "cup", "bowl", "plate",
                        "bottle", "cola_can", "lemon", "potato", "bread", "kettle", "cooking_pot", "frying_pan",
                        "cutting_board", "jar", "teapot", "milk_carton", "wine_glass"),
    "dining_table": ("plate", "bowl", "cup", "mug", "apple", "orange", "banana", "pear", "vase", "bottle",
                     "cola_can", "wine_glass", "bread", "teapot", "jar", "lemon", "candle"),
    "coffee_table": ("remote", "book", "mug", "cup", "vase", "cola_can", "apple", "orange", "banana",
                     "laptop", "phone", "bowl", "candle", "game_controller", "tissue_box", "figurine",
                     "potted_plant", "notebook", "tablet"),
    "side_table": ("book", "remote", "phone", "mug", "vase", "cup", "cola_can", "alarm_clock", "desk_lamp",
                   "candle", "picture_frame", "tissue_box", "potted_plant"),
    "desk": ("laptop", "book", "mug", "phone", "cup", "cola_can", "bottle", "pen", "notebook", "stapler",
             "scissors", "keyboard", "computer_mouse", "tablet", "desk_lamp", "alarm_clock", "potted_plant"),
    "nightstand": ("book", "phone", "cup", "remote", "bottle", "alarm_clock", "desk_lamp", "tissue_box",
                   "candle", "picture_frame"),
    "dresser": ("vase", "book", "toy", "remote", "phone", "bottle", "picture_frame", "candle", "figurine",
                "basket", "towel", "potted_plant"),
    "bookshelf": ("book", "vase", "toy", "figurine", "picture_frame", "basket", "cardboard_box", "potted_plant",
                  "candle"),
    "tv_stand": ("remote", "vase", "book", "toy", "game_controller", "figurine", "picture_frame", "potted_plant"),
    "sofa": ("remote", "phone", "toy", "book", "orange", "apple", "banana", "cola_can", "pillow",
             "game_controller", "tablet", "notebook"),
    "armchair": ("book", "phone", "remote", "toy", "pillow", "tablet"),
    "chair": ("book", "toy", "phone", "pillow"),
    "bed": ("book", "toy", "phone", "laptop", "pillow", "towel", "tablet", "notebook"),
    "sink": ("bottle", "cup", "soap", "shampoo", "towel", "toilet_paper"),
    "bathtub": ("bottle", "toy", "shampoo", "soap", "towel"),
    "fridge": ("bottle", "bowl", "milk_carton", "jar"),
    "stove": ("kettle", "cooking_pot", "frying_pan", "teapot"),
    "microwave": ("bowl", "plate", "mug", "cup"),
    "dishwasher": ("plate", "bowl", "cup", "mug", "wine_glass", "bottle"),
    "kitchen_island": ("apple", "orange", "banana", "pear", "lemon", "bread", "bowl", "plate", "mug", "cup",
                       "cutting_board", "jar", "bottle", "wine_glass", "teapot", "vase", "laptop", "phone"),
    "pantry_cabinet": ("jar", "bottle", "cola_can", "potato", "bread", "milk_carton", "bowl", "plate", "basket"),
    "washing_machine": ("towel", "basket", "soap", "shampoo", "bottle", "toilet_paper"),
    "dryer": ("towel", "basket", "soap", "bottle", "toilet_paper"),
    "vanity": ("soap", "shampoo", "towel", "toilet_paper", "cup", "bottle", "candle"),
    "radiator": ("towel", "book", "candle", "potted_plant"),
    "ottoman": ("book", "remote", "pillow", "tablet", "game_controller", "phone", "notebook"),
    "bench": ("pillow", "book", "basket", "cardboard_box", "towel", "phone"),
    "stool": ("book", "pillow", "phone", "towel", "mug"),
    "office_chair": ("pillow", "book", "phone", "tablet"),
    "filing_cabinet": ("notebook", "pen", "stapler", "scissors", "book", "cardboard_box", "desk_lamp",
                       "potted_plant", "alarm_clock"),
    "storage_cabinet": ("book", "vase", "basket", "cardboard_box", "figurine", "picture_frame", "candle",
                        "potted_plant", "toy", "towel", "bottle"),
    "shoe_rack": ("basket", "cardboard_box", "toy"),
    "sideboard": ("vase", "candle", "picture_frame", "bowl", "bottle", "wine_glass", "figurine", "plate",
                  "potted_plant", "book"),
    "console_table": ("vase", "candle", "picture_frame", "alarm_clock", "phone", "book", "figurine",
                      "potted_plant", "basket"),
    "piano": ("picture_frame", "candle", "vase", "figurine", "book"),
    "chest": ("pillow", "basket", "cardboard_box", "book", "towel", "toy"),
    "fireplace": ("candle", "picture_frame", "figurine", "vase", "alarm_clock", "potted_plant"),
    "aquarium": ("figurine", "potted_plant", "book"),
    "grandfather_clock": ("figurine", "vase", "candle"),
    "toilet": ("toilet_paper", "book", "towel", "soap", "candle"),
}
#: Kinds a sprinkled object is drawn from, one after another, before its place is left empty.
SPRINKLE_KINDS = 3
#: Largest random yaw added to the furniture's, degrees.
MAX_JITTER_YAW = 15.0
#: Gap between objects on one surface, metres.
OBJECT_GAP = 0.02


@dataclass
class Surface:
    piece: int
    index: int  #: receptacle index in the piece's model
    rec: Receptacle
    occupied: list[np.ndarray] = field(default_factory=list)  #: rects in the piece's frame
    count: int = 0  #: small objects on it


@dataclass
class SmallPlaced:
    category: str
    asset: str
    variant: int
    x: float
    y: float
    z: float
    yaw: float
    support: int
    receptacle: int


def open_receptacle(model, rec: Receptacle) -> bool:
    """A receptacle one can put things on without opening anything: on the base link (a
    drawer's inside moves with the drawer), and not behind hinged doors (a fridge's shelves)
    unless it is the top. Behind doors: the closed doors span its whole width (a tv stand's
    open middle shelf between two closed sides is open). The doors' height is not looked at,
    so a surface right above doors (a vanity's counter and basin) counts as behind them, as
    it did when any door closed every surface but the top."""
    if rec.link != "base":
        return False
    if rec.height >= float(model.size[2]) - 0.05:
        return True
    spans = sorted(_closed_x_span(link) for link in model.links
                   if link.joint is not None and link.joint.kind == "hinge")
    x, reach = rec.center[0] - rec.half_size[0], rec.center[0] + rec.half_size[0]
    for a, b in spans:  # sweep the doors' union (gaps of 2 cm bridged) from the left edge
        if a - 0.01 > x:
            break
        x = max(x, b + 0.01)
    return x < reach


def _closed_x_span(link) -> tuple[float, float]:
    """The x extent of a link in its model's frame, at joint value 0."""
    x0 = min(float(p.vertices[:, 0].min()) for p in link.parts) + float(link.pos[0])
    x1 = max(float(p.vertices[:, 0].max()) for p in link.parts) + float(link.pos[0])
    return x0, x1


def surfaces_of(pieces: list[Placed]) -> list[Surface]:
    """Every open receptacle of every piece, with what already stands on it."""
    out = []
    for i, p in enumerate(pieces):
        for k, rec in enumerate(p.model.receptacles):
            if not open_receptacle(p.model, rec):
                continue
            s = Surface(i, k, rec)
            for q in pieces:
                if q.support == i and q.receptacle == k:
                    s.occupied.append(_in_frame(p, q))
            out.append(s)
    return out


def _in_frame(base: Placed, item: Placed) -> np.ndarray:
    """Footprint of ``item`` in the frame of ``base`` (both quarter-turned)."""
    d = QUARTER_TURNS[(-base.q) % 4] @ np.array([item.x - base.x, item.y - base.y])
    return np.concatenate([d, d]) + turned_rect(local_footprint(item.model), (item.q - base.q) % 4)


def receptacle_corners(piece: Placed, rec: Receptacle) -> np.ndarray:
    """World corners (4, 2) of a receptacle rectangle, where the scene puts it (the piece's
    position rounded as the scene writes it): the very corners the house's check computes,
    so the navigation grid answers both from one reach query."""
    c, h = np.asarray(rec.center), np.asarray(rec.half_size)
    return rect_corners((round(piece.x, 4), round(piece.y, 4)), (c[0] - h[0], c[1] - h[1], c[0] + h[0], c[1] + h[1]),
                        round(piece.yaw_deg, 4))


class SmallObjectPlacer:
    def __init__(self, pieces: list[Placed], catalog: Catalog, rng: np.random.Generator, *,
                 max_per_surface: int, reachable: Callable[[Placed, Receptacle], bool]):
        self.pieces = pieces
        self.catalog = catalog
        self.rng = rng
        self.max = max_per_surface
        self.surfaces = [s for s in surfaces_of(pieces) if reachable(pieces[s.piece], s.rec)]
        self.placed: list[SmallPlaced] = []

    def count(self, category: str) -> int:
        return sum(p.category == category for p in self.placed)

    def put(self, surface: Surface, category: str, tries: int = 3) -> bool:
        """Put one object of ``category`` on a surface; False if it does not fit."""
        if surface.count >= self.max or category not in self.catalog.by_category:
            return False
        ids = self.catalog.by_category[category]
        for _ in range(tries):
            asset = ids[int(self.rng.integers(len(ids)))]
            variant = int(self.rng.integers(registry.GENERATED_VARIANTS))
            model = registry.make(asset, variant)
            if model.size[2] > surface.rec.clearance:
                continue
            jitter = float(self.rng.uniform(-MAX_JITTER_YAW, MAX_JITTER_YAW))
            pos = self._spot(surface, local_footprint(model), jitter)
            if pos is None:
                continue
            self._commit(surface, category, asset, variant, pos, jitter, local_footprint(model))
            return True
        return False

    def _spot(self, surface: Surface, local: np.ndarray, jitter: float, samples: int = 8) -> np.ndarray | None:
        """A free origin (in the piece's frame) for an object turned by ``jitter`` degrees."""
        rot = _yaw_matrix(jitter)
        corners = np.array([[local[0], local[1]], [local[2], local[1]], [local[2], local[3]], [local[0], local[3]]])
        turned = corners @ rot.T
        lo, hi = turned.min(axis=0), turned.max(axis=0)
        c, h = np.asarray(surface.rec.center), np.asarray(surface.rec.half_size)
        margin = 0.005
        pmin, pmax = c - h + margin - lo, c + h - margin - hi
        if (pmax < pmin).any():
            return None
        # All the samples at once, the first one clear of what the surface holds wins.
        ps = self.rng.uniform(pmin, pmax, (samples, 2))
        if not surface.occupied:
            return ps[0]
        boxes = np.concatenate([ps + (lo - OBJECT_GAP), ps + (hi + OBJECT_GAP)], axis=1)
        taken = np.array(surface.occupied)
        clear = ~((boxes[:, None, 0] < taken[None, :, 2]) & (taken[None, :, 0] < boxes[:, None, 2])
                  & (boxes[:, None, 1] < taken[None, :, 3]) & (taken[None, :, 1] < boxes[:, None, 3])).any(axis=1)
        free = np.flatnonzero(clear)
        return ps[free[0]] if len(free) else None

    def _commit(self, surface, category, asset, variant, pos, jitter, local) -> None:
        base = self.pieces[surface.piece]
        world = QUARTER_TURNS[base.q] @ pos + np.array([base.x, base.y])
        yaw = (base.yaw_deg + jitter) % 360.0
        self.placed.append(SmallPlaced(category, asset, variant, float(world[0]), float(world[1]),
                                       float(base.z + surface.rec.height), yaw, surface.piece, surface.index))
        turned = np.array([[local[0], local[1]], [local[2], local[3]], [local[0], local[3]], [local[2], local[1]]])
        turned = turned @ _yaw_matrix(jitter).T
        surface.occupied.append(np.concatenate([pos + turned.min(axis=0), pos + turned.max(axis=0)]))
        surface.count += 1

    def put_on_category(self, category: str, receptacles: list[str]) -> bool:
        """Put one object on any reachable surface of the given furniture categories."""
        cands = [s for s in self.surfaces if self.pieces[s.piece].category in receptacles]
        return any(self.put(cands[k], category) for k in self.rng.permutation(len(cands)).tolist())

    def put_anywhere(self, category: str) -> bool:
        """Put one object on a plausible surface if possible, else on any surface."""
        plausible = [s for s in self.surfaces if category in PLAUSIBLE.get(self.pieces[s.piece].category, ())]
        rest = [s for s in self.surfaces if s not in plausible]
        for group in (plausible, rest):
            for k in self.rng.permutation(len(group)).tolist():
                if self.put(group[k], category):
                    return True
        return False

    def sprinkle(self, density: float, exclude: set[str]) -> None:
        """Random objects: per surface a binomial count with mean ``density`` times the share
        of the surface that nothing stands on yet (a shelf half full of books holds half as
        many)."""
        small = [c for c in self.catalog.categories if self.catalog.is_small(c) and c not in exclude]
        if not small or self.max == 0:
            return
        p = min(1.0, density / self.max)
        for s in self.surfaces:
            taken = sum(float((o[2] - o[0]) * (o[3] - o[1])) for o in s.occupied) / (4 * s.rec.half_size[0] * s.rec.half_size[1])
            want = int(self.rng.binomial(self.max, p * max(0.0, 1.0 - taken))) - s.count
            options = [c for c in PLAUSIBLE.get(self.pieces[s.piece].category, tuple(small)) if c in small] or small
            for _ in range(max(0, want)):
                # A kind too big for what is left of the surface gives way to another kind;
                # when none fits, the surface is as full as it gets (a shelf of books).
                if not any(self.put(s, options[int(self.rng.integers(len(options)))], tries=2)
                           for _ in range(SPRINKLE_KINDS)):
                    break


def _yaw_matrix(deg: float) -> np.ndarray:
    a = np.radians(deg)
    return np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])


def place_small_objects(pieces: list[Placed], catalog: Catalog, rng: np.random.Generator, *,
                        require_on: list[tuple[str, list[str], str]], counts: dict[str, int],
                        density: float, max_per_surface: int,
                        reachable: Callable[[Placed, Receptacle], bool]) -> list[SmallPlaced]:
    """All small objects of a house. ``require_on``: (object category, receptacle
    categories, quoted condition text for errors); ``counts``: exact count per small category.

    Raises :class:`PlacementFailed` with the condition's label when one cannot be met."""
    placer = SmallObjectPlacer(pieces, catalog, rng, max_per_surface=max_per_surface, reachable=reachable)
    for obj, recs, label in require_on:
        if not placer.put_on_category(obj, recs):
            have = [s for s in placer.surfaces if pieces[s.piece].category in recs]
            why = (f"no reachable {' or '.join(recs)} surface in this house" if not have
                   else f"no {' or '.join(recs)} surface with room for it (at most {max_per_surface} per surface)")
            raise PlacementFailed(f"cannot place {label}: {why}")
    for cat in sorted(counts):
        while placer.count(cat) < counts[cat]:
            if not placer.put_anywhere(cat):
                raise PlacementFailed(f"cannot place {counts[cat]} {cat!r} (object_counts): "
                                      f"found room for {placer.count(cat)}")
    placer.sprinkle(density, exclude=set(counts))
    return placer.placed

"""The built-in asset library: frame convention, sizes, budgets, annotations and articulation.

Every check runs on variants 0..9 of every built-in asset; models come from the registry
(cached), except the determinism check, which calls the uncached maker twice.
"""

from __future__ import annotations

from typing import get_args

import numpy as np
import pytest
from scipy.spatial import ConvexHull

import legent_gym.world.assets  # noqa: F401  (registers the library)
from legent_gym.world.assets import registry
from legent_gym.world.assets.library.common import MATERIALS, ROOM_TYPES
from legent_gym.world.assets.model import AssetModel, Part, Placement
from tests.world import sizes_appliances, sizes_bath_decor, sizes_fittings, sizes_living
from tests.world.sizes_decor import SIZES as DECOR_SIZES
from tests.world.sizes_kitchenware import SIZES as KITCHENWARE_SIZES
from tests.world.sizes_office_bath import SIZES as OFFICE_BATH_SIZES

VARIANTS = range(10)

#: (min size, max size) of the bounding box (x, y, z), metres: what such things measure.
FURNITURE = {
    "bed": ((1.4, 1.9, 0.8), (2.05, 2.25, 1.35)),
    "sofa": ((1.55, 0.75, 0.7), (2.45, 1.05, 1.0)),
    "armchair": ((0.65, 0.7, 0.7), (1.0, 1.05, 1.0)),
    "dining_table": ((1.2, 0.75, 0.7), (2.0, 1.0, 0.8)),
    "coffee_table": ((0.9, 0.5, 0.35), (1.3, 0.7, 0.5)),
    "desk": ((1.0, 0.55, 0.7), (1.6, 0.8, 0.8)),
    "chair": ((0.38, 0.4, 0.75), (0.55, 0.55, 1.05)),
    "bookshelf": ((0.6, 0.25, 1.2), (1.2, 0.4, 2.0)),
    "wardrobe": ((0.8, 0.5, 1.8), (1.6, 0.7, 2.2)),
    "dresser": ((0.8, 0.42, 0.75), (1.55, 0.6, 1.1)),
    "nightstand": ((0.4, 0.35, 0.5), (0.65, 0.5, 0.65)),
    "fridge": ((0.6, 0.6, 1.5), (0.9, 0.8, 1.9)),
    "kitchen_counter": ((0.8, 0.55, 0.85), (2.0, 0.66, 0.95)),
    "sink": ((0.6, 0.5, 0.82), (1.2, 0.66, 1.25)),
    "toilet": ((0.35, 0.55, 0.65), (0.46, 0.8, 0.9)),
    "bathtub": ((1.5, 0.7, 0.5), (1.8, 0.8, 0.75)),
    "tv_stand": ((1.0, 0.35, 0.4), (1.8, 0.52, 0.6)),
    "tv": ((0.7, 0.15, 0.45), (1.5, 0.3, 1.0)),
    "plant": ((0.2, 0.2, 0.3), (1.0, 1.0, 2.0)),
    "side_table": ((0.38, 0.33, 0.45), (0.6, 0.6, 0.65)),
    "floor_lamp": ((0.25, 0.25, 1.4), (0.5, 0.5, 1.8)),
    "wall_picture": ((0.4, 0.003, 0.24), (1.2, 0.06, 1.0)),
    **sizes_appliances.SIZES,
    **sizes_living.SIZES,
    **sizes_bath_decor.SIZES,
    **sizes_fittings.SIZES,
}
OBJECTS = {
    "apple": ((0.06, 0.06, 0.055), (0.095, 0.095, 0.1)),
    "orange": ((0.06, 0.06, 0.055), (0.095, 0.095, 0.1)),
    "tomato": ((0.045, 0.045, 0.035), (0.085, 0.085, 0.075)),
    "pear": ((0.055, 0.055, 0.09), (0.085, 0.085, 0.14)),
    "banana": ((0.15, 0.025, 0.02), (0.25, 0.08, 0.05)),
    "cola_can": ((0.06, 0.06, 0.11), (0.07, 0.07, 0.13)),
    "mug": ((0.07, 0.07, 0.08), (0.13, 0.1, 0.1)),
    "cup": ((0.05, 0.05, 0.07), (0.1, 0.1, 0.13)),
    "bowl": ((0.1, 0.1, 0.04), (0.2, 0.2, 0.09)),
    "plate": ((0.18, 0.18, 0.01), (0.3, 0.3, 0.03)),
    "bottle": ((0.05, 0.05, 0.18), (0.09, 0.09, 0.3)),
    "book": ((0.12, 0.18, 0.01), (0.22, 0.3, 0.06)),
    "vase": ((0.08, 0.08, 0.1), (0.2, 0.2, 0.35)),
    "laptop": ((0.28, 0.2, 0.15), (0.4, 0.36, 0.28)),
    "remote": ((0.03, 0.13, 0.012), (0.06, 0.23, 0.03)),
    "phone": ((0.06, 0.13, 0.006), (0.085, 0.17, 0.012)),
    "toy": ((0.04, 0.04, 0.03), (0.2, 0.2, 0.25)),
    **KITCHENWARE_SIZES,
    **DECOR_SIZES,
    **OFFICE_BATH_SIZES,
}
FURNITURE_TRIANGLES, OBJECT_TRIANGLES = 400, 160
#: Moving links: the joint kind of each articulated asset, or the kinds (a tuple) of one whose
#: variants have doors and drawers (each kind on some of them).
ARTICULATED: dict[str, str | tuple[str, ...]] = {
    "wardrobe": "hinge", "fridge": "hinge", "dresser": "slide", "nightstand": "slide",
    "kitchen_counter": ("hinge", "slide"), "desk": "slide", "tv_stand": ("hinge", "slide"),
    **sizes_appliances.ARTICULATED, **sizes_living.ARTICULATED, **sizes_bath_decor.ARTICULATED}
#: Articulated assets some of whose variants have nothing that moves (a desk on four legs,
#: a tv stand with open shelves).
SOMETIMES_STATIC = {"desk", "tv_stand", *sizes_living.SOMETIMES_STATIC}
#: Names a Where-Is answer may use, by asset.
EXPECTED_NAMES = {
    "sofa": {"sofa", "couch"},
    "cola_can": {"cola", "cola can", "soda can", "can"},
    "dining_table": {"table", "dining table"},
    "kitchen_counter": {"countertop", "counter", "kitchen counter"},
    "tv": {"tv", "television"},
    "remote": {"remote", "remote control"},
    "toy": {"toy"},
    "fridge": {"fridge", "refrigerator"},
}
#: Assets that must offer a place to put things, and which receptacles.
EXPECTED_RECEPTACLES = {
    "bed": 1, "sofa": 1, "dining_table": 1, "coffee_table": 1, "desk": 1, "bookshelf": 3,
    "dresser": 4, "nightstand": 2, "kitchen_counter": 3, "sink": 1, "tv_stand": 2, "side_table": 1,
    **sizes_appliances.EXPECTED_RECEPTACLES, **sizes_living.EXPECTED_RECEPTACLES,
    **sizes_bath_decor.EXPECTED_RECEPTACLES,
}

BUILTIN = registry.asset_ids(builtin=True)


def _models(asset_id: str) -> list[AssetModel]:
    return [registry.make(asset_id, v) for v in VARIANTS]


def _link_parts(model: AssetModel, link: str) -> list[Part]:
    """A link's parts in the asset frame (joints at zero)."""
    lk = model.link(link)
    return [Part(p.vertices + np.asarray(lk.pos), p.faces, p.rgba, p.collision, material=p.material)
            for p in lk.parts]


def _up_faces_z(parts: list[Part], xy: np.ndarray) -> np.ndarray:
    """Heights of the upward-facing collision triangles of ``parts`` right above or below ``xy``."""
    zs = []
    for p in parts:
        if p.collision == "none":
            continue
        tri = p.vertices[p.faces]
        n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
        norm = np.linalg.norm(n, axis=1)
        t = tri[(norm > 1e-12) & (n[:, 2] > 0.99 * np.maximum(norm, 1e-12))]
        a, e1, e2 = t[:, 0], t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]
        d = xy - a[:, :2]
        den = e1[:, 0] * e2[:, 1] - e2[:, 0] * e1[:, 1]
        u = (d[:, 0] * e2[:, 1] - e2[:, 0] * d[:, 1]) / den
        w = (e1[:, 0] * d[:, 1] - d[:, 0] * e1[:, 1]) / den
        inside = (u >= -1e-6) & (w >= -1e-6) & (u + w <= 1 + 1e-6)
        zs.append((a[:, 2] + u * e1[:, 2] + w * e2[:, 2])[inside])
    return np.concatenate(zs) if zs else np.zeros(0)


def _centroid(parts: list[Part]) -> np.ndarray:
    """Volume centroid of closed parts (tetrahedra from the origin)."""
    tri = np.concatenate([p.vertices[p.faces] for p in parts])
    vol = np.einsum("ij,ij->i", tri[:, 0], np.cross(tri[:, 1], tri[:, 2])) / 6.0
    return (vol[:, None] * tri.sum(axis=1) / 4.0).sum(axis=0) / vol.sum()


# ---------------------------------------------------------------------------------------


def test_every_listed_asset_is_registered():
    assert set(FURNITURE) | set(OBJECTS) == set(BUILTIN)
    assert len(BUILTIN) >= 100, "the built-in library has at least 100 types"
    assert len(OBJECTS) == 50 and sum(registry.describe(a).pickupable for a in BUILTIN) >= 50
    assert set(BUILTIN) <= set(FURNITURE) | set(OBJECTS), "a new built-in needs a size range here"


@pytest.mark.parametrize("asset_id", BUILTIN)
def test_asset_frame(asset_id):
    for m in _models(asset_id):
        lo, hi = m.bounds()
        assert lo[2] == pytest.approx(0.0, abs=1e-9)
        assert abs(lo[0] + hi[0]) / 2 < 1e-3 and abs(lo[1] + hi[1]) / 2 < 1e-3
        assert m.asset_id == asset_id and m.category == asset_id


@pytest.mark.parametrize("asset_id", BUILTIN)
def test_size_is_plausible(asset_id):
    lo, hi = {**FURNITURE, **OBJECTS}[asset_id]
    for m in _models(asset_id):
        assert np.all(m.size >= np.asarray(lo) - 1e-6) and np.all(m.size <= np.asarray(hi) + 1e-6), m.size


@pytest.mark.parametrize("asset_id", BUILTIN)
def test_triangle_budget(asset_id):
    budget = OBJECT_TRIANGLES if asset_id in OBJECTS else FURNITURE_TRIANGLES
    assert max(m.triangle_count() for m in _models(asset_id)) < budget


@pytest.mark.parametrize("asset_id", BUILTIN)
def test_parts_are_closed_outward_meshes(asset_id):
    for m in _models(asset_id):
        for link in m.links:
            for p in link.parts:
                assert np.all(np.isfinite(p.vertices))
                assert p.faces.min() >= 0 and p.faces.max() < len(p.vertices)
                edges = np.concatenate([p.faces[:, [0, 1]], p.faces[:, [1, 2]], p.faces[:, [2, 0]]])
                fwd = {tuple(e) for e in edges.tolist()}
                assert len(fwd) == len(edges), "an edge is used twice in the same direction"
                assert all((b, a) in fwd for a, b in fwd), "the mesh is not closed"
                tri = p.vertices[p.faces]
                assert np.einsum("ij,ij->i", tri[:, 0], np.cross(tri[:, 1], tri[:, 2])).sum() > 0
                assert p.collision in ("box", "hull", "none")
                assert p.material in MATERIALS
                assert all(0.0 <= c <= 1.0 for c in p.rgba) and len(p.rgba) == 4


@pytest.mark.parametrize("asset_id", BUILTIN)
def test_variant_is_deterministic(asset_id):
    make = registry.make.__wrapped__  # uncached
    for v in (0, 7):
        a, b = make(asset_id, v), make(asset_id, v)
        assert [lk.name for lk in a.links] == [lk.name for lk in b.links]
        for la, lb in zip(a.links, b.links):
            assert la.pos == lb.pos and la.joint == lb.joint
            for pa, pb in zip(la.parts, lb.parts, strict=True):
                assert np.array_equal(pa.vertices, pb.vertices) and np.array_equal(pa.faces, pb.faces)
                assert pa.rgba == pb.rgba
        assert a.receptacles == b.receptacles and a.names == b.names and a.mass == b.mass


@pytest.mark.parametrize("asset_id", BUILTIN)
def test_variants_differ(asset_id):
    def signature(m: AssetModel):
        colours = tuple(tuple(np.round(p.rgba, 3)) for lk in m.links for p in lk.parts)
        return tuple(np.round(m.size, 3)), colours

    assert len({signature(m) for m in _models(asset_id)}) >= 8


@pytest.mark.parametrize("asset_id", BUILTIN)
def test_annotations(asset_id):
    canonical = {m.names[0] for m in _models(asset_id)}
    assert len(canonical) == 1, "the canonical name must not depend on the variant"
    for m in _models(asset_id):
        assert m.names and all(n and n == n.lower() and n.strip() == n for n in m.names)
        assert len(set(m.names)) == len(m.names)
        assert set(m.rooms) <= ROOM_TYPES
        assert m.placement in get_args(Placement)
        assert m.front_clearance >= 0 and m.mass > 0
        assert EXPECTED_NAMES.get(asset_id, set()) <= set(m.names)


@pytest.mark.parametrize("asset_id", sorted(OBJECTS))
def test_small_objects_are_pickupable(asset_id):
    for m in _models(asset_id):
        assert m.pickupable and m.placement == "surface"
        assert np.all(m.size < 0.6) and 0.005 < m.mass < 5.0
        assert len(m.links) == 1 and not m.receptacles


@pytest.mark.parametrize("asset_id", sorted(OBJECTS))
def test_small_objects_rest_stably(asset_id):
    # The centre of mass projects well inside the footprint the object stands on.
    for m in _models(asset_id):
        solid = [p for p in m.base.parts if p.collision != "none"]
        pts = np.concatenate([p.vertices for p in solid])
        support = pts[pts[:, 2] < 1e-3][:, :2]
        hull = ConvexHull(support)
        com = _centroid(solid)[:2]
        # Signed distance from the centre of mass in to the support polygon's nearest edge.
        margin = -np.max(hull.equations[:, :2] @ com + hull.equations[:, 2])
        assert margin > 0.005, f"variant tips over: centre of mass {margin * 1000:.1f} mm inside"


@pytest.mark.parametrize("asset_id", sorted(FURNITURE))
def test_furniture_is_static_and_annotated(asset_id):
    for m in _models(asset_id):
        assert not m.pickupable
        assert m.rooms, "furniture names the rooms it belongs in"
        if asset_id in EXPECTED_RECEPTACLES:
            assert len(m.receptacles) >= EXPECTED_RECEPTACLES[asset_id]


@pytest.mark.parametrize("asset_id", [a for a in BUILTIN if a in FURNITURE])
def test_receptacles_lie_on_geometry(asset_id):
    for m in _models(asset_id):
        lo, hi = m.bounds()
        assert len({r.name for r in m.receptacles}) == len(m.receptacles)
        for r in m.receptacles:
            link = m.link(r.link)
            off = np.asarray(link.pos)
            cx, cy, z = r.center[0] + off[0], r.center[1] + off[1], r.height + off[2]
            hx, hy = r.half_size
            assert hx > 0.04 and hy > 0.04 and r.clearance > 0.05, r
            corners = np.array([[cx + sx * hx, cy + sy * hy] for sx in (-1, 1) for sy in (-1, 1)])
            assert np.all(corners >= lo[:2] - 1e-9) and np.all(corners <= hi[:2] + 1e-9), r
            parts = _link_parts(m, r.link)
            for xy in [np.array([cx, cy]), *corners]:
                zs = _up_faces_z(parts, xy)
                assert np.any(np.abs(zs - z) < 2e-3), f"{r.name}: no surface at z={z:.3f} under {xy}"
            # Nothing solid of the same link in the free space above the rectangle.
            top = z + min(r.clearance, 1.0) - 3e-3
            for p in parts:
                if p.collision == "none":
                    continue
                plo, phi = p.bounds()
                overlap = (plo[0] < cx + hx and phi[0] > cx - hx and plo[1] < cy + hy and phi[1] > cy - hy
                           and plo[2] < top and phi[2] > z + 3e-3)
                assert not overlap, f"{r.name}: a part occupies the space above it"


@pytest.mark.parametrize("asset_id", sorted(FURNITURE))
def test_articulation(asset_id):
    declared = ARTICULATED.get(asset_id)
    kinds = {declared} if isinstance(declared, str) else set(declared or ())
    seen = set()
    for m in _models(asset_id):
        moving = m.links[1:]
        assert m.links[0].name == "base" and m.base.joint is None
        if not kinds:
            assert not moving
            continue
        if asset_id not in SOMETIMES_STATIC:
            assert moving, "articulated assets move their doors/drawers as separate links"
        base_hi = np.concatenate([p.vertices for p in m.base.parts]).max(axis=0)
        for link in moving:
            j = link.joint
            assert j is not None and j.kind in kinds
            seen.add(j.kind)
            assert j.range[0] == 0.0 < j.range[1]
            assert len(link.parts) >= 2, "a door or drawer has its handle"
            v = np.concatenate([p.vertices for p in link.parts])
            if j.kind == "hinge":
                assert j.axis in ((0.0, 0.0, 1.0), (0.0, 0.0, -1.0)) and j.range[1] <= np.pi
                assert v[:, 0].min() >= -1e-9 or v[:, 0].max() <= 1e-9, "the hinge is on an edge"
                assert min(abs(v[:, 0].min()), abs(v[:, 0].max())) < 1e-6
                a = 0.3 * np.sign(j.axis[2])
                rotated_y = np.sin(a) * v[:, 0] + np.cos(a) * v[:, 1]
                assert rotated_y.mean() > v[:, 1].mean(), "doors swing toward +y"
            else:
                assert j.axis == (0.0, 1.0, 0.0) and j.range[1] < m.size[1]
                assert link.pos[1] + v[:, 1].max() >= base_hi[1] - 0.03, "drawer fronts face +y"
                inner = [r for r in m.receptacles if r.link == link.name]
                assert len(inner) == 1 and inner[0].clearance < link.parts[0].bounds()[1][2]
    assert seen == kinds, f"the variants have {sorted(seen)}, the table says {sorted(kinds)}"

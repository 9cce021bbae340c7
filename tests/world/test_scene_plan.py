"""Scene plans and their solver (legent_gym.world.generation.plan): example plans whose
relations are measured in the resulting scene, random plans from hypothesis, unknown
names, speed, and `legent-gym generate --plan`."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from legent_gym.cli import main
from legent_gym.world.assets import registry
from legent_gym.world.generation import GenerationError, check_house
from legent_gym.world.generation.conditions import Catalog
from legent_gym.world.generation.plan import (
    FACING_ANGLE,
    FAR_DISTANCE,
    NEAR_GAP,
    SIDE_ANGLE,
    WALL_CONTACT,
    ScenePlan,
    solve_plan,
)
from legent_gym.world.geometry import inset_polygon, local_footprint, turned_rect
from legent_gym.world.scene import Scene, load_scene

PLANS = Path(__file__).resolve().parents[2] / "examples" / "plans"
CATALOG = Catalog.from_registry()


def _plan(name: str) -> dict:
    return json.loads((PLANS / f"{name}.json").read_text())


# -- measuring a scene, independently of the solver ------------------------------------------


def _footprint(obj) -> np.ndarray:
    model = registry.make(obj.asset, obj.variant)
    q = round(obj.rotation[2] / 90.0) % 4
    return np.array([obj.position[0], obj.position[1]] * 2) + turned_rect(local_footprint(model), q)


def _gap(a: np.ndarray, b: np.ndarray) -> float:
    return math.hypot(max(b[0] - a[2], a[0] - b[2], 0.0), max(b[1] - a[3], a[1] - b[3], 0.0))


def _centre(r: np.ndarray) -> np.ndarray:
    return np.array([(r[0] + r[2]) / 2, (r[1] + r[3]) / 2])


def _front(yaw: float) -> np.ndarray:
    a = math.radians(yaw)
    return np.array([-math.sin(a), math.cos(a)])


def _angle(u: np.ndarray, v: np.ndarray) -> float:
    return math.degrees(math.acos(float(np.clip(u @ v / np.linalg.norm(v), -1, 1))))


def _wall_gap(scene: Scene, obj, rect: np.ndarray) -> float:
    room = next(r for r in scene.rooms if r.id == obj.room)
    inner = inset_polygon(np.asarray(room.polygon, dtype=float), 0.05)  # the wall faces (walls 0.1 m thick)
    gaps = []
    for k in range(len(inner)):
        p0, p1 = inner[k], inner[(k + 1) % len(inner)]
        seg = np.array([min(p0[0], p1[0]), min(p0[1], p1[1]), max(p0[0], p1[0]), max(p0[1], p1[1])])
        gaps.append(_gap(rect, seg))
    return min(gaps)


def margin(scene: Scene, kind: str, obj, target) -> float:
    """How far a relation is from its threshold, measured on the scene's objects
    (footprints, yaws, walls): > 0 where it holds, < 0 where it fails."""
    rect = _footprint(obj)
    if kind == "against_wall":
        return WALL_CONTACT - _wall_gap(scene, obj, rect)
    if kind == "middle":
        return _wall_gap(scene, obj, rect) - 0.5
    trect = _footprint(target)
    c, tc = _centre(rect), _centre(trect)
    if kind == "near":
        return NEAR_GAP - _gap(rect, trect)
    if kind == "far":
        return float(np.linalg.norm(c - tc)) - FAR_DISTANCE
    if kind == "facing":
        return (FACING_ANGLE - _angle(_front(obj.rotation[2]), tc - c)) / 100.0
    turn = {"in_front_of": 0.0, "left_of": 90.0, "right_of": -90.0}[kind]
    limit = 35.0 if kind == "in_front_of" else SIDE_ANGLE
    return min((limit - _angle(_front(target.rotation[2] + turn), c - tc)) / 100.0, 1.5 - _gap(rect, trect))


def check_solution(plan: dict, solved) -> list[str]:
    """Every planned relation measured in the scene: those that fail must be reported as
    unmet, those reported must fail; every object id of the report is in its room."""
    scene, report = solved.scene, solved.report
    objs = {o.id: o for o in scene.objects}
    failing = []
    for room in plan["rooms"]:
        for o in room["objects"]:
            key = f"{room['name']}/{o['name']}"
            ids = report.objects.get(key, [])
            assert len(ids) in (0, o.get("count", 1))  # one entry per copy (none: dropped)
            for i in ids:
                assert i is None or objs[i].room is not None
            for k, i in enumerate(ids):
                if i is None:
                    assert any(u.startswith(f"{key}: ") for u in report.unmet)  # not placed: said so
                    continue
                if objs[i].on is not None:
                    continue
                for rel in o.get("relations", []):
                    targets = [objs[t] for t in report.objects.get(f"{room['name']}/{rel.get('target')}", [])
                               if t is not None and objs[t].on is None]
                    if rel.get("target") and not targets:
                        continue
                    best = max(margin(scene, rel["kind"], objs[i], t) for t in (targets or [None]))
                    ok = best > 0
                    what = f"{key} #{k + 1} {rel['kind']}" + (f" {rel['target']}" if rel.get("target") else "")
                    reported = any(u.startswith(what + ":") for u in report.unmet)
                    if abs(best) < 2e-3:  # on the threshold: the scene's positions are rounded to 0.1 mm
                        continue
                    assert ok != reported, f"{what}: measured {'held' if ok else 'failed'}, report {report.unmet}"
                    if not ok:
                        failing.append(what)
    return failing


# -- the example plans -----------------------------------------------------------------------


def relation_margins(plan: dict, solved) -> dict[str, float]:
    """Each planned relation of each placed floor copy, measured in the scene alone (see
    :func:`margin`): "room/object #copy kind target" -> the margin of the best target."""
    scene, objects = solved.scene, solved.report.objects
    objs = {o.id: o for o in scene.objects}
    out = {}
    for room in plan["rooms"]:
        for o in room["objects"]:
            for k, i in enumerate(objects[f"{room['name']}/{o['name']}"]):
                if objs[i].on is not None:
                    continue
                for rel in o.get("relations", []):
                    targets = [objs[t] for t in objects.get(f"{room['name']}/{rel.get('target')}", [])
                               if objs[t].on is None] if rel.get("target") else [None]
                    assert targets, f"{room['name']}/{o['name']}: target {rel['target']} not on the floor"
                    what = f"{room['name']}/{o['name']} #{k + 1} {rel['kind']} {rel.get('target') or ''}".rstrip()
                    out[what] = max(margin(scene, rel["kind"], objs[i], t) for t in targets)
    return out


EXAMPLE_PLANS = sorted(p.stem for p in PLANS.glob("*.json"))


@pytest.mark.parametrize("seed", range(5))
@pytest.mark.parametrize("name", EXAMPLE_PLANS)
def test_example_plans_relations_hold_in_the_result(name, seed):
    plan = _plan(name)
    solved = solve_plan(plan, seed, CATALOG)
    assert solved.report.unmet == [] and solved.report.warnings == []
    assert check_house(solved.scene) == []
    assert check_solution(plan, solved) == []
    # Measured in the scene: distances, facing angles and wall contact all within their
    # thresholds (to the scene's 0.1 mm rounding of positions).
    margins = relation_margins(plan, solved)
    assert len(margins) == sum(o.get("count", 1) * len(o.get("relations", []))
                               for r in plan["rooms"] for o in r["objects"])
    assert {k: v for k, v in margins.items() if v < -2e-3} == {}
    # Every planned object is there, as many as planned, on what the plan says.
    objs = {o.id: o for o in solved.scene.objects}
    for room in plan["rooms"]:
        for o in room["objects"]:
            ids = solved.report.objects[f"{room['name']}/{o['name']}"]
            assert len(ids) == o.get("count", 1) and None not in ids
            assert {objs[i].room for i in ids} <= {r.id for r in solved.scene.rooms}
            if o.get("on"):
                supports = solved.report.objects[f"{room['name']}/{o['on']}"]
                assert all(objs[i].on in supports for i in ids)


@pytest.mark.parametrize("name", ["small_flat", "four_rooms", "four_rooms_dense", "office"])
def test_example_plans_report_exactly_what_is_unmet(name):
    plan = _plan(name)
    for seed in (1, 2):
        solved = solve_plan(plan, seed, CATALOG)
        assert check_house(solved.scene) == []
        check_solution(plan, solved)


def test_same_plan_and_seed_give_the_same_scene():
    plan = _plan("office")
    a, b = solve_plan(plan, 5, CATALOG), solve_plan(plan, 5, CATALOG)
    assert a.scene.to_json() == b.scene.to_json() and a.report.unmet == b.report.unmet


def test_requested_doors_link_the_rooms():
    plan = _plan("four_rooms")
    scene = solve_plan(plan, 0, CATALOG).scene
    ids = {r.name.split(" ")[0]: r.id for r in scene.rooms}
    links = {frozenset(d.connects) for d in scene.doors}
    assert frozenset({ids["living"], ids["kitchen"]}) in links
    assert frozenset({ids["bedroom"], ids["bathroom"]}) in links


def test_four_room_plan_of_forty_objects_solves():
    # Its speed is measured by `python benchmarks/generation.py --plans` (docs/llm.md).
    plan = _plan("four_rooms_dense")
    assert len(plan["rooms"]) == 4 and sum(o.get("count", 1) for r in plan["rooms"] for o in r["objects"]) == 37
    for seed in range(3):
        solved = solve_plan(plan, seed, CATALOG)
        assert len(solved.scene.objects) >= 36 and check_house(solved.scene) == []
        check_solution(plan, solved)


# -- names -----------------------------------------------------------------------------------


def test_unknown_names_map_to_the_nearest_category_or_are_dropped():
    plan = {"rooms": [{"name": "lounge", "type": "sitting room", "objects": [
        {"name": "couch", "asset": "big leather couch", "relations": [{"kind": "against_wall"}]},
        {"name": "seat", "asset": "armchiar"},
        {"name": "rocket", "asset": "spaceship"},
        {"name": "lamp", "asset": "floor_lamp", "relations": [{"kind": "near", "target": "rocket"}]}]}]}
    solved = solve_plan(plan, 0, CATALOG)
    assert solved.report.mapped == {"big leather couch": "sofa", "armchiar": "armchair"}
    assert any("dropped lounge/rocket: 'spaceship'" in w for w in solved.report.warnings)
    assert "lounge/lamp near rocket: the target was dropped" in solved.report.unmet
    cats = {registry.describe(o.asset).category for o in solved.scene.objects}
    assert {"sofa", "armchair", "floor_lamp"} <= cats


def test_impossible_relations_and_objects_are_reported():
    plan = {"rooms": [{"name": "bath", "type": "bathroom", "size": 5, "objects": [
        {"name": "wardrobe", "count": 6},
        {"name": "toilet", "relations": [{"kind": "far", "target": "sink"}, {"kind": "middle"}]},
        {"name": "sink"}]}]}
    solved = solve_plan(plan, 0, CATALOG)
    assert check_house(solved.scene) == []
    assert any("no room for a wardrobe" in u for u in solved.report.unmet)
    check_solution(plan, solved)


@pytest.mark.parametrize("bad, match", [
    ({"rooms": []}, "rooms"),
    ({"rooms": [{"name": "a", "type": "kitchen", "objects": [{"name": "x", "on": "y"}]}]}, "refers to 'y'"),
    ({"rooms": [{"name": "a", "type": "kitchen"}], "doors": [["a", "b"]]}, "no room 'b'"),
    ({"rooms": [{"name": "a", "type": "kitchen", "objects": [{"name": "x", "relations": [{"kind": "near"}]}]}]},
     "needs a target"),
    ({"version": 2, "rooms": [{"name": "a", "type": "kitchen"}]}, "version"),
    ({"rooms": [{"name": f"r{k}", "type": "kitchen", "objects": [{"name": f"o{j}", "asset": "apple", "count": 12}
                                                                 for j in range(2)]} for k in range(7)]},
     "asks for 168 objects; at most 160"),
])
def test_invalid_plans_are_refused(bad, match):
    with pytest.raises(ValueError, match=match):
        ScenePlan.model_validate(bad)


# -- random plans ----------------------------------------------------------------------------

FURNITURE = ["sofa", "bed", "chair", "desk", "dresser", "bookshelf", "plant", "side_table", "coffee_table",
             "nightstand", "armchair", "floor_lamp", "fridge", "kitchen_counter", "toilet", "sink", "wardrobe",
             "dining_table", "tv_stand", "couch", "big bed", "hovercraft"]
SMALL = ["apple", "mug", "book", "phone", "vase", "remote", "cup", "banana"]
KINDS = ["near", "far", "against_wall", "middle", "facing", "in_front_of", "left_of", "right_of"]
ROOMS = ["bedroom", "living room", "kitchen", "bathroom", "office", "dining room", "hallway", "studio"]


@st.composite
def random_plans(draw):
    n_rooms = draw(st.integers(1, 4))
    rooms = []
    for r in range(n_rooms):
        names = []
        objects = []
        for k in range(draw(st.integers(0, 6))):
            name = f"f{k}"
            rels = []
            for _ in range(draw(st.integers(0, 2))):
                kind = draw(st.sampled_from(KINDS))
                if kind in ("against_wall", "middle"):
                    rels.append({"kind": kind})
                elif names:
                    rels.append({"kind": kind, "target": draw(st.sampled_from(names))})
            objects.append({"name": name, "asset": draw(st.sampled_from(FURNITURE)),
                            "count": draw(st.integers(1, 2)), "relations": rels})
            names.append(name)
        for k in range(draw(st.integers(0, 3))):
            obj = {"name": f"s{k}", "asset": draw(st.sampled_from(SMALL))}
            if names and draw(st.booleans()):
                obj["on"] = draw(st.sampled_from(names))
            objects.append(obj)
        size = draw(st.one_of(st.none(), st.floats(5, 30)))
        rooms.append({"name": f"r{r}", "type": draw(st.sampled_from(ROOMS)), "size": size, "objects": objects})
    doors = []
    if n_rooms > 1:
        for _ in range(draw(st.integers(0, 2))):
            a, b = draw(st.lists(st.integers(0, n_rooms - 1), min_size=2, max_size=2, unique=True))
            doors.append([f"r{a}", f"r{b}"])
    return {"version": 1, "rooms": rooms, "doors": doors}


def _check_random(plan: dict, seed: int) -> None:
    try:
        solved = solve_plan(plan, seed, CATALOG)
    except GenerationError as err:  # a named condition, never anything else
        assert "no valid house for the plan" in str(err) and "last:" in str(err)
        return
    scene = Scene.model_validate_json(solved.scene.to_json())
    assert check_house(scene) == []  # valid: rooms linked, everything reachable, spawns walkable
    check_solution(plan, solved)


@settings(max_examples=20, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow])
@given(random_plans(), st.integers(0, 1000))
def test_random_plans_give_valid_houses_or_a_named_condition(plan, seed):
    _check_random(plan, seed)


@pytest.mark.slow
@settings(max_examples=100, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(random_plans(), st.integers(0, 10**6))
def test_random_plans_slow(plan, seed):
    _check_random(plan, seed)


# -- the command line ------------------------------------------------------------------------


def test_cli_generate_plan_writes_scene_and_map(tmp_path, capsys):
    out, png = tmp_path / "house.json", tmp_path / "house.png"
    rc = main(["generate", "--plan", str(PLANS / "small_flat.json"), "--seed", "0", "--out", str(out),
               "--map", str(png)])
    assert rc == 0
    scene = load_scene(out)
    assert check_house(scene) == [] and png.stat().st_size > 1000
    assert "wrote" in capsys.readouterr().out


def test_cli_generate_plan_prints_what_is_unmet(tmp_path, capsys):
    plan = tmp_path / "plan.json"
    plan.write_text(json.dumps({"rooms": [{"name": "a", "type": "bedroom", "objects": [
        {"name": "bed"}, {"name": "rocket", "asset": "spaceship"}]}]}))
    assert main(["generate", "--plan", str(plan), "--out", str(tmp_path / "h.json")]) == 0
    out = capsys.readouterr().out
    assert "warning: dropped a/rocket: 'spaceship'" in out


@pytest.mark.parametrize("text, match", [("{", "not JSON"), ('{"rooms": "many"}', "not a valid plan: rooms")])
def test_cli_generate_bad_plan_is_one_line(tmp_path, capsys, text, match):
    plan = tmp_path / "plan.json"
    plan.write_text(text)
    assert main(["generate", "--plan", str(plan), "--out", str(tmp_path / "h.json")]) == 2
    err = capsys.readouterr().err
    assert match in err and err.count("\n") == 1 and "Traceback" not in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["plan.json"]

"""`legent-gym asset annotate` on the Khronos glTF samples (tests/fixtures/gltf), with a real chat completions server
on 127.0.0.1 replaying a VLM's reply (tests/chat_server.py): geometry computed, semantics
from the reply, cached by file hash; the annotated asset is placed by the generator and
rendered in the env."""

from __future__ import annotations

import json
import warnings

import numpy as np
import pytest

from legent_gym.cli import main
from legent_gym.llm.annotation import SEMANTIC_FIELDS, AssetAnnotation, register_annotation
from legent_gym.world.assets import registry
from tests.chat_server import ReplayServer
from tests.conftest import GLTF_SAMPLES

SAMPLES = sorted(GLTF_SAMPLES.glob("*.gltf"))
REPLY = {"name": "Storage box", "category": "storage box", "description": "A plain closed box.", "pickable": False,
         "receptacle": True, "on_floor": True, "on_wall": False, "on_object": False, "materials": ["cardboard"],
         "mass": 3.0, "front_view": 1}


def _annotate(path, out, cache, *extra):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # flat samples warn about their collision box
        return main(["asset", "annotate", str(path), "--out", str(out), "--cache-dir", str(cache), *extra])


def _llm(url, timeout="20"):
    return ["--llm-base-url", url, "--model", "test-vlm", "--timeout", timeout, "--retries", "0"]


@pytest.mark.parametrize("sample", [p.name for p in SAMPLES])
def test_every_sample_is_annotated_from_four_views_and_cached(tmp_path, sample):
    path = GLTF_SAMPLES / sample
    with ReplayServer([("reply", json.dumps(REPLY))]) as server:
        assert _annotate(path, tmp_path / "a.json", tmp_path / "cache", *_llm(server.url)) == 0
        # The same file again: the cached annotation, no request.
        assert _annotate(path, tmp_path / "b.json", tmp_path / "cache", *_llm(server.url)) == 0
    assert len(server.requests) == 1
    content = server.requests[0]["body"]["messages"][0]["content"]
    images = [part["image_url"]["url"] for part in content if part["type"] == "image_url"]
    assert len(images) == 4 and all(url.startswith("data:image/png;base64,") for url in images)
    assert len(set(images)) >= 2  # the views differ
    a = AssetAnnotation.model_validate_json((tmp_path / "a.json").read_text())
    b = AssetAnnotation.model_validate_json((tmp_path / "b.json").read_text())
    assert a == b and a.semantics is not None and a.semantics.category == "storage_box"
    assert a.yaw == 270.0 and a.missing == []
    assert all(v >= 0 for v in a.geometry.size) and max(a.geometry.size) > 0


def test_the_box_geometry_is_measured(tmp_path):
    assert _annotate(GLTF_SAMPLES / "Box.gltf", tmp_path / "box.json", tmp_path / "cache") == 0
    a = AssetAnnotation.model_validate_json((tmp_path / "box.json").read_text())
    assert a.geometry.up_axis == "y" and a.geometry.stable
    assert a.geometry.size == pytest.approx((1.0, 1.0, 1.0), abs=1e-3)
    [top] = a.geometry.surfaces  # the cube's lid, rays on a 5 cm grid, 2 cm margin
    assert top.height == pytest.approx(1.0, abs=1e-3)
    assert top.half_size == pytest.approx((0.48, 0.48), abs=1e-3)
    assert a.semantics is None and a.missing == list(SEMANTIC_FIELDS)


def test_without_an_endpoint_the_geometry_is_written_and_the_rest_named(tmp_path, capsys):
    assert _annotate(GLTF_SAMPLES / "BoxTextured.gltf", tmp_path / "box.json", tmp_path / "cache") == 0
    out = capsys.readouterr().out
    assert "missing: name, category, description" in out and "give --llm-base-url and --model" in out


FAILURES = {
    "HTTP 500": ([("status", 500)], "failed 1 time(s) (last: HTTP 500)"),
    "not JSON twice": ([("reply", "A box."), ("reply", "Still a box.")], "sent an invalid Semantics twice"),
    "wrong types twice": ([("reply", json.dumps({**REPLY, "mass": "heavy"}))] * 2, "mass: Input should be"),
    "front view out of range": ([("reply", json.dumps({**REPLY, "front_view": 7}))] * 2, "front_view"),
}


@pytest.mark.parametrize("case", FAILURES)
def test_endpoint_failures_are_one_line_and_write_nothing(tmp_path, capsys, case):
    script, needle = FAILURES[case]
    with ReplayServer(script) as server:
        assert _annotate(GLTF_SAMPLES / "Box.gltf", tmp_path / "box.json", tmp_path / "cache",
                         *_llm(server.url)) == 2
    err = capsys.readouterr().err
    assert err.startswith("legent-gym: error: ") and err.count("\n") == 1 and needle in err, err
    assert not (tmp_path / "box.json").exists() and not list((tmp_path / "cache").glob("*.json"))


def test_the_annotated_asset_is_placed_by_the_generator_and_rendered(tmp_path):
    from legent_gym.envs.household import HouseholdEnv
    from legent_gym.world.generation import check_house
    from legent_gym.world.generation.plan import load_plan, solve_plan
    from legent_gym.world.render import Renderer

    with ReplayServer([("reply", json.dumps(REPLY))]) as server:
        assert _annotate(GLTF_SAMPLES / "Box.gltf", tmp_path / "box.json", tmp_path / "cache",
                         *_llm(server.url)) == 0
    asset_id = register_annotation(tmp_path / "box.json")
    try:
        assert asset_id == "storage_box" and registry.describe(asset_id).receptacles
        plan = load_plan({"version": 1, "rooms": [{"name": "living", "type": "living room", "size": 16, "objects": [
            {"name": "box", "asset": "storage box", "relations": [{"kind": "against_wall"}]},
            {"name": "apple", "on": "box"}, {"name": "sofa"}]}]})
        solved = solve_plan(plan, 0)
        scene = solved.scene
        assert check_house(scene) == [] and solved.report.unmet == []
        [box] = [o for o in scene.objects if o.asset == asset_id]
        assert [o.on for o in scene.objects if o.asset == "apple"] == [box.id]  # on the annotated surface
        # Built from the registry, as in the process that registered it (no entry).
        env = HouseholdEnv("ComeHere", scene=scene.model_copy(update={"assets": []}), width=32, height=32)
        env.reset(seed=0)
        world = env.episode.world
        assert world is not None
        renderer = Renderer(world, 96, 96)
        try:
            seen = renderer.segmentation("topdown")
        finally:
            renderer.close()
        assert (seen == box.id).sum() > 20  # the box is drawn
        assert np.asarray(env.render() if env.render_mode else env.episode.views()["rgb"]).std() > 0
        env.close()
    finally:
        registry.unregister(asset_id)


def test_the_front_view_turns_the_asset_and_its_surfaces(tmp_path):
    """A 0.8 (x) x 0.4 (depth) x 0.5 m table-like box: the VLM's front in view 1 turns it a
    quarter, so its width and depth swap, in the annotation and in the registered model."""
    import trimesh

    path = tmp_path / "crate.glb"
    # glTF frame: x width, y up, z depth (front +z).
    trimesh.creation.box((0.8, 0.5, 0.4)).export(path)
    with ReplayServer([("reply", json.dumps({**REPLY, "category": "crate", "front_view": 1}))]) as server:
        assert _annotate(path, tmp_path / "crate.json", tmp_path / "cache", *_llm(server.url)) == 0
    a = AssetAnnotation.model_validate_json((tmp_path / "crate.json").read_text())
    assert a.yaw == 270.0
    assert a.geometry.size == pytest.approx((0.4, 0.8, 0.5), abs=1e-3)
    [top] = a.geometry.surfaces
    assert top.height == pytest.approx(0.5, abs=1e-3) and top.half_size[1] > top.half_size[0]
    asset_id = register_annotation(tmp_path / "crate.json", "annotated_crate")
    try:
        lo, hi = registry.describe(asset_id).bounds()
        assert hi - lo == pytest.approx((0.4, 0.8, 0.5), abs=1e-3)
        assert registry.describe(asset_id).receptacles[0].height == pytest.approx(0.5, abs=1e-3)
    finally:
        registry.unregister(asset_id)
    # Without a VLM: not turned.
    assert _annotate(path, tmp_path / "plain.json", tmp_path / "other-cache") == 0
    plain = AssetAnnotation.model_validate_json((tmp_path / "plain.json").read_text())
    assert plain.yaw == 0.0 and plain.geometry.size == pytest.approx((0.8, 0.4, 0.5), abs=1e-3)


def test_an_annotated_asset_goes_from_the_cli_into_a_plan_a_scene_and_generated_tasks(tmp_path, capsys):
    """asset annotate -> generate --plan --asset -> tasks generate --asset: a task about the
    annotated box is kept (its code and the expert complete it)."""
    from legent_gym.world.scene import load_scene

    with ReplayServer([("reply", json.dumps(REPLY))]) as server:
        assert _annotate(GLTF_SAMPLES / "Box.gltf", tmp_path / "box.json", tmp_path / "cache", *_llm(server.url)) == 0
    plan = {"version": 1, "rooms": [{"name": "living", "type": "living room", "size": 16, "objects": [
        {"name": "box", "asset": "storage box", "relations": [{"kind": "against_wall"}]},
        {"name": "apple", "on": "sofa"}, {"name": "sofa"}]}]}
    (tmp_path / "plan.json").write_text(json.dumps(plan))
    try:
        assert main(["generate", "--plan", str(tmp_path / "plan.json"), "--asset", str(tmp_path / "box.json"),
                     "--seed", "0", "--out", str(tmp_path / "scene.json")]) == 0
        scene = load_scene(tmp_path / "scene.json")
        [box] = [o.id for o in scene.objects if o.asset == "storage_box"]
        [apple] = [o.id for o in scene.objects if o.asset == "apple"]
        task = {"kind": "put", "instruction": "Put the apple on the storage box.", "target": apple,
                "receptacle": box, "code": f"goto({apple}) target({apple}) interact() goto({box}) target({box}) "
                                           "interact()"}
        with ReplayServer([("reply", json.dumps({"tasks": [task]}))]) as server:
            assert main(["tasks", "generate", str(tmp_path / "scene.json"), "--asset", str(tmp_path / "box.json"),
                         "--n", "1", "--llm-base-url", server.url, "--model", "m", "--retries", "0",
                         "--out", str(tmp_path / "tasks.jsonl")]) == 0
        assert "storage box" in server.requests[0]["body"]["messages"][0]["content"]
        [record] = [json.loads(line) for line in (tmp_path / "tasks.jsonl").read_text().splitlines()[1:]]
        assert record["status"] == "kept", record
    finally:
        if registry.has("storage_box"):
            registry.unregister("storage_box")


# -- a scene that uses an annotated asset carries it -------------------------------------------

FRESH = r"""
import json, sys
import numpy as np
import gymnasium as gym
import legent_gym  # noqa: F401  (registers the envs)
from legent_gym.world.assets import registry
from legent_gym.world.render import Renderer
from legent_gym.world.scene import load_scene

path, box_id, apple_id = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
assert not registry.has("storage_box")  # nothing registered in this process
env = gym.make("Legent/ComeHere-OneRoom-v0", scene=path, width=32, height=32)
env.reset(seed=0)
world = env.unwrapped.episode.world
box = world.assets[box_id]
lo, hi = box.bounds()
renderer = Renderer(world, 96, 96)
try:
    seen = renderer.segmentation("topdown")
    rgb = renderer.rgb("topdown")
finally:
    renderer.close()
position = world.data.xpos[world.model.body(f"obj_{box_id}").id].tolist()
apple = world.data.xpos[world.model.body(f"obj_{apple_id}").id].tolist()
env.close()
print(json.dumps({"category": box.category, "size": (hi - lo).tolist(), "placement": box.placement,
                  "receptacles": [[*r.center, *r.half_size, r.height] for r in box.receptacles],
                  "pixels": int((seen == box_id).sum()), "rgb_mean": float(rgb.mean()), "position": position,
                  "apple": apple}))
"""


def _fresh(*args, cwd):
    import subprocess
    import sys

    done = subprocess.run([sys.executable, *args], capture_output=True, text=True, timeout=600, cwd=cwd)
    assert done.returncode == 0, done.stderr[-3000:]
    return done.stdout


@pytest.mark.parametrize("sample", ["Box.gltf", "crate.glb"])
def test_a_generated_scene_carries_its_annotated_asset_into_a_fresh_process(tmp_path, sample):
    """asset annotate -> generate --plan --asset -> the scene file alone, in a fresh python:
    the box is imported from the scene's own entry (turned, sized, its surface a receptacle),
    stands where the generator put it, renders the same, and an expert puts the apple on it
    (tasks generate with no --asset, in a fresh python). The sample Box.gltf, and a 0.8 x
    0.5 x 0.4 m crate whose front the VLM finds in view 1 (turned a quarter)."""
    from legent_gym.llm.annotation import AssetAnnotation
    from legent_gym.world.assets.gltf import scene_asset_model
    from legent_gym.world.render import Renderer
    from legent_gym.world.scene import load_scene

    if sample == "crate.glb":
        import trimesh

        source = tmp_path / "models" / "crate.glb"
        source.parent.mkdir()
        trimesh.creation.box((0.8, 0.5, 0.4)).export(source)  # glTF frame: y up
    else:
        source = GLTF_SAMPLES / sample
    with ReplayServer([("reply", json.dumps(REPLY))]) as server:
        assert _annotate(source, tmp_path / "box.json", tmp_path / "cache", *_llm(server.url)) == 0
    annotation = AssetAnnotation.model_validate_json((tmp_path / "box.json").read_text())
    plan = {"version": 1, "rooms": [{"name": "living", "type": "living room", "size": 16, "objects": [
        {"name": "box", "asset": "storage box", "relations": [{"kind": "against_wall"}]},
        {"name": "apple", "on": "sofa"}, {"name": "sofa"}]}]}
    (tmp_path / "plan.json").write_text(json.dumps(plan))
    out = tmp_path / "house" / "scene.json"
    out.parent.mkdir()
    try:
        assert main(["generate", "--plan", str(tmp_path / "plan.json"), "--asset", str(tmp_path / "box.json"),
                     "--seed", "0", "--out", str(out)]) == 0
        # The scene file: the entry carries the annotation; the glTF is copied beside it.
        data = json.loads(out.read_text())
        [entry] = data["assets"]
        assert entry["id"] == "storage_box" and entry["source"] == f"scene_assets/storage_box/{sample}"
        assert (out.parent / entry["source"]).read_bytes() == source.read_bytes()
        assert entry["yaw"] == annotation.yaw == 270 and entry["up_axis"] == annotation.geometry.up_axis
        assert entry["category"] == "storage_box" and entry["names"] == ["storage box"]
        assert entry["pickupable"] is False and entry["mass"] == 3.0 and entry["placement"] == "wall"
        assert [(r["center"], r["half_size"], r["height"]) for r in entry["receptacles"]] == \
            [(list(s.center), list(s.half_size), s.height) for s in annotation.geometry.surfaces]
        scene = load_scene(out)
        [box] = [o for o in scene.objects if o.asset == "storage_box"]
        [apple] = [o for o in scene.objects if o.asset == "apple"]
        # Here, where the asset is registered: the model and the render to compare with (the
        # entry builds the registered model).
        registered = registry.make("storage_box", box.variant)
        if sample == "crate.glb":  # turned a quarter: the width along y
            lo, hi = registered.bounds()
            assert hi - lo == pytest.approx((0.4, 0.8, 0.5), abs=1e-3)
        assert scene_asset_model(scene, "storage_box").bounds() == pytest.approx(registered.bounds(), abs=1e-9)
        from legent_gym.envs.household import HouseholdEnv

        # Built from the registry, as in the process that registered it (no entry).
        env = HouseholdEnv("ComeHere", scene=scene.model_copy(update={"assets": []}), width=32, height=32)
        env.reset(seed=0)
        world = env.episode.world
        renderer = Renderer(world, 96, 96)
        try:
            here_pixels = int((renderer.segmentation("topdown") == box.id).sum())
            here_rgb = float(renderer.rgb("topdown").mean())
        finally:
            renderer.close()
        here_position = world.data.xpos[world.model.body(f"obj_{box.id}").id].tolist()
        env.close()
    finally:
        registry.unregister("storage_box")

    # A fresh python with the scene file alone.
    there = json.loads(_fresh("-c", FRESH, str(out), str(box.id), str(apple.id), cwd=tmp_path).splitlines()[-1])
    lo, hi = registered.bounds()
    assert there["category"] == "storage_box" and there["placement"] == "wall"
    assert there["size"] == pytest.approx((hi - lo).tolist(), abs=1e-6)
    assert np.allclose(there["receptacles"], [[*r.center, *r.half_size, r.height] for r in registered.receptacles])
    assert len(there["receptacles"]) == len(annotation.geometry.surfaces) == 1
    assert there["position"] == pytest.approx(here_position, abs=1e-6)
    assert there["pixels"] == here_pixels > 20 and there["rgb_mean"] == pytest.approx(here_rgb, abs=1e-6)

    # An expert puts the apple on the box, in a fresh python, with no --asset.
    task = {"kind": "put", "instruction": "Put the apple on the storage box.", "target": apple.id,
            "receptacle": box.id, "code": f"goto({apple.id}) target({apple.id}) interact() goto({box.id}) "
                                          f"target({box.id}) interact()"}
    with ReplayServer([("reply", json.dumps({"tasks": [task]}))]) as server:
        _fresh("-m", "legent_gym.cli", "tasks", "generate", str(out), "--n", "1", "--llm-base-url", server.url,
               "--model", "m", "--retries", "0", "--out", str(tmp_path / "tasks.jsonl"), cwd=tmp_path)
    [record] = [json.loads(line) for line in (tmp_path / "tasks.jsonl").read_text().splitlines()[1:]]
    assert record["status"] == "kept", record


def test_imported_asset_entries_without_annotation_fields_keep_their_meaning():
    from pydantic import ValidationError

    from legent_gym.world.scene import ImportedAsset

    old = ImportedAsset.model_validate({"id": "chair", "source": "models/chair.glb", "size": [0.5, 0.5, 0.9]})
    assert old.yaw == 0 and old.placement is None and old.receptacles is None  # the importer's defaults
    with pytest.raises(ValidationError, match="yaw must be 0, 90, 180 or 270"):
        ImportedAsset.model_validate({"id": "chair", "source": "chair.glb", "yaw": 45})
    with pytest.raises(ValidationError, match="half_size"):
        ImportedAsset.model_validate({"id": "chair", "source": "chair.glb", "receptacles": [
            {"center": [0, 0], "half_size": [0, 0.2], "height": 0.4}]})

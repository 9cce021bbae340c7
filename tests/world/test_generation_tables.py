"""What the generator keeps or computes in bulk gives what it would compute each time: the
built-in assets' seed table (NumPy's SeedSequence), the catalog kept until the registry
changes, a model's kept footprint, and the house checks written for many objects at once."""

import zlib

import numpy as np
import pytest

from legent_gym.world.assets import registry
from legent_gym.world.assets.model import Link, box_part
from legent_gym.world.generation import generate_house
from legent_gym.world.generation.conditions import Catalog
from legent_gym.world.generation.validate import check_house
from legent_gym.world.scene import ObjectInstance


def _same(a, b) -> bool:
    """Field by field equality of models, parts and arrays (dtype and shape included)."""
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        return (isinstance(a, np.ndarray) and isinstance(b, np.ndarray) and a.dtype == b.dtype
                and a.shape == b.shape and np.array_equal(a, b))
    if isinstance(a, list | tuple):
        return type(a) is type(b) and len(a) == len(b) and all(_same(x, y) for x, y in zip(a, b))
    if hasattr(a, "__dataclass_fields__"):
        return type(a) is type(b) and all(_same(getattr(a, f), getattr(b, f)) for f in a.__dataclass_fields__)
    return a == b


@pytest.mark.parametrize("asset_id", ["sofa", "apple", "", "a user's asset"])
def test_seed_table_is_numpys_seed_sequence(asset_id):
    entropy = zlib.crc32(asset_id.encode())
    table = registry._seed_table(entropy, registry.VARIANTS)
    for variant in range(registry.VARIANTS):
        want = np.random.SeedSequence([entropy, variant]).generate_state(4, np.uint64)
        np.testing.assert_array_equal(table[variant], want)


def test_builtin_models_come_from_the_variant_generator():
    for asset_id in registry.asset_ids(builtin=True):
        for variant in (0, 7, registry.VARIANTS - 1, registry.VARIANTS, 123456):
            fast = registry._builtin_rng(asset_id, variant)
            slow = registry.variant_rng(asset_id, variant)
            assert fast.bit_generator.state == slow.bit_generator.state
            assert np.array_equal(fast.random(5), slow.random(5))
        factory = registry._ENTRIES[asset_id].factory
        for variant in (3, 998):
            made = registry.make.__wrapped__(asset_id, variant)
            assert _same(made, factory(registry.variant_rng(asset_id, variant))), (asset_id, variant)


def test_catalog_is_kept_until_the_registry_changes():
    first = Catalog.from_registry()
    assert Catalog.from_registry() is first
    registry.register("test-tables-crate", lambda rng: registry.make("dresser", 1))
    try:
        second = Catalog.from_registry()
        assert second is not first and "test-tables-crate" in second.models
    finally:
        registry.unregister("test-tables-crate")
    third = Catalog.from_registry()
    assert third is not second and "test-tables-crate" not in third.models


def test_footprint_follows_the_links():
    model = registry.make.__wrapped__("dresser", 4)
    bounds = model.bounds()
    np.testing.assert_array_equal(model.footprint(), [bounds[0, 0], bounds[0, 1], bounds[1, 0], bounds[1, 1]])
    model.footprint()[0] = 99.0  # a copy goes out
    assert model.footprint()[0] == bounds[0, 0]
    model.links = [Link("base", [box_part((0, 0, 0.5), (4.0, 2.0, 1.0))])]  # a new link list: fresh values
    np.testing.assert_array_equal(model.footprint(), [-2.0, -1.0, 2.0, 1.0])


def test_house_checks_name_each_bad_piece():
    scene = generate_house(5, "TwoRoom")
    assert check_house(scene) == []
    floor = [o for o in scene.objects if o.kind == "static" and o.on is None]
    moved = {floor[0].id: (50.0, 50.0), floor[-1].id: (-40.0, 3.0)}
    objects = [o.model_copy(update={"position": (*moved[o.id], o.position[2])}) if o.id in moved else o
               for o in scene.objects]
    problems = check_house(scene.model_copy(update={"objects": objects}))
    outside = [p for p in problems if "is not inside the house" in p]
    assert outside == [f"object {o.id} ({o.asset}) is not inside the house" for o in floor if o.id in moved]
    assert isinstance(objects[0], ObjectInstance)

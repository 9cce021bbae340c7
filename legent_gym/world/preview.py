"""Look at one asset on its own: a bare floor, the asset, and a camera fitted to it."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from legent_gym.world.assets import registry
from legent_gym.world.assets.gltf import load_imported_asset
from legent_gym.world.builder import World, build_world
from legent_gym.world.render import FreeCamera, Profile, Renderer
from legent_gym.world.scene import ImportedAsset, Scene, validate_scene


def preview_scene(asset_id: str, variant: int = 0, *, imported: ImportedAsset | None = None,
                  base_dir: Path | None = None, kind: str | None = None) -> Scene:
    """A scene with a 6 m x 6 m floor, no walls, and the asset at the origin."""
    if imported is None:
        pickupable = registry.describe(asset_id).pickupable
    else:
        pickupable = load_imported_asset(imported, base_dir or Path.cwd()).pickupable
    kind = kind or ("interactable" if pickupable else "static")
    data = {
        "name": f"preview of {asset_id}",
        "rooms": [{"id": "floor", "type": "preview", "name": "floor",
                   "polygon": [[-3, -3], [3, -3], [3, 3], [-3, 3]],
                   "floor": {"material": "plain", "rgba": [0.55, 0.57, 0.6, 1.0]}}],
        "assets": [imported.model_dump(mode="json")] if imported else [],
        "objects": [{"id": 0, "asset": asset_id, "variant": variant, "position": [0, 0, 0], "kind": kind}],
        "agent": {"position": [2.5, -2.5], "yaw": 135},
        "lights": [{"position": [1.5, -2.0, 4.0], "direction": [-0.3, 0.4, -1.0], "diffuse": [0.7, 0.7, 0.7],
                    "directional": True}],
    }
    scene = validate_scene(data, asset_known=registry.has if imported is None else None)
    if base_dir is not None:
        scene.base_dir = base_dir
    return scene


def fitted_camera(world: World, object_id: int = 0) -> FreeCamera:
    """A three-quarter front view that frames the object."""
    lo, hi = world.assets[object_id].bounds()
    centre = world.object_position(object_id) + (lo + hi) / 2
    radius = float(np.linalg.norm(hi - lo)) / 2
    distance = max(radius / math.tan(math.radians(22.5)) * 1.1, 0.3)
    # The asset's front faces +y; MuJoCo's azimuth 90 looks along +y, so 270 looks at the front.
    return FreeCamera(tuple(centre), distance, azimuth=240.0, elevation=-25.0)


def render_asset_preview(asset_id: str, variant: int = 0, *, size: int = 256, profile: Profile = "pretty",
                         imported: ImportedAsset | None = None, base_dir: Path | None = None) -> np.ndarray:
    world = build_world(preview_scene(asset_id, variant, imported=imported, base_dir=base_dir, kind="static"))
    renderer = Renderer(world, size, size, profile)
    try:
        return renderer.rgb(fitted_camera(world))
    finally:
        renderer.close()

"""View rays: what a line of sight from an eye meets first.

One ray test serves the body's ``look`` (what the image centre shows), the tasks'
visibility tests, the feasibility checks the task samplers and experts share, and the
experts' oracle, so they cannot disagree about what is in sight. A view ray meets the
house (walls, floors, doors) and the scene objects; it passes through the avatars (they are
in neither group) and, when asked, through one object (the one the agent holds, which
moves with the camera).
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

from legent_gym.world.builder import GROUP_HOUSE, GROUP_OBJECTS, World

#: The geom groups a view ray meets: the house and the scene objects.
VIEW_GROUPS = np.zeros(6, dtype=np.uint8)
VIEW_GROUPS[GROUP_HOUSE] = VIEW_GROUPS[GROUP_OBJECTS] = 1
VIEW_GROUPS.flags.writeable = False


@dataclass
class RayHit:
    """The first surface a view ray meets: ``distance`` along the ray (metres), the world
    ``point``, the scene object (``object_id``) or door (``door_id``) it belongs to (both
    None for house structure), and the MuJoCo ``geom`` (-1 when the hit was made up for an
    addressed target rather than cast)."""

    distance: float
    point: np.ndarray
    object_id: int | None = None
    door_id: str | None = None
    geom: int = -1


def cast_ray(world: World, origin, direction, exclude_object: int | None = None) -> RayHit | None:
    """The first house or object surface along the unit ``direction`` from ``origin``, or
    None; ``exclude_object`` (a scene object id) is passed through."""
    origin = np.asarray(origin, dtype=float)
    direction = np.asarray(direction, dtype=float)
    exclude = world.object_body[exclude_object] if exclude_object is not None else -1
    geomid = np.zeros(1, dtype=np.int32)
    dist = mujoco.mj_ray(world.model, world.data, origin, direction, VIEW_GROUPS, 1, exclude, geomid)
    if dist < 0:
        return None
    g = int(geomid[0])
    obj = int(world.geom_object[g])
    return RayHit(float(dist), origin + direction * dist, obj if obj >= 0 else None, world.geom_door.get(g), g)


def cast_rays(world: World, origin, directions: np.ndarray,
              exclude_object: int | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Many rays from one ``origin`` along unit ``directions`` (N, 3) at once: (distance
    along each, -1 where nothing is met; the scene object id met, -1 for none or house)."""
    origin = np.asarray(origin, dtype=float)
    exclude = world.object_body[exclude_object] if exclude_object is not None else -1
    n = len(directions)
    geomid = np.zeros(n, dtype=np.int32)
    dist = np.zeros(n)
    mujoco.mj_multiRay(world.model, world.data, origin, np.ascontiguousarray(directions, dtype=float).ravel(),
                       VIEW_GROUPS, 1, exclude, geomid, dist, None, n, mujoco.mjMAXVAL)
    return dist, np.where(dist >= 0, world.geom_object_lookup(geomid), -1)

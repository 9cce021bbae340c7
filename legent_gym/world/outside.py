"""The outside of a house: a ground and a sky, seen through windows and exterior doors.

Both are palette-coloured meshes the builder adds after everything else (so no other
element's id moves), in the ceilings' group (``GROUP_CEILING``, which no view ray meets),
colliding with nothing and carrying no object id (segmentation shows them as -1, as it
showed the black void before):

* the ground: one quad facing up, :data:`GROUND_DROP` below the floors' top surface (the
  floors are drawn as before), reaching the sky's walls;
* the sky: four walls :data:`SKY_DISTANCE` metres beyond the house's bounds and a lid
  :data:`SKY_HEIGHT` metres up, facing inward, drawn with an emissive material (they look
  unlit). The lid lies above the top-down camera (30 m over the floor), so the top-down view
  never sees it.

No plane geoms and no skybox texture: renderers keep reusing their contexts between houses.
"""

from __future__ import annotations

from functools import lru_cache

import mujoco
import numpy as np

from legent_gym.world.meshing import ColouredMesh, face_normals, to_rgb8

#: The static body that carries them (the model's last).
BODY = "outside"
#: How far beyond the house's bounds the sky's walls stand (metres).
SKY_DISTANCE = 30.0
#: The height of the sky's lid: above the top-down camera, which looks from 30 m up.
SKY_HEIGHT = 40.0
#: How far below the floors' top surface (z = 0) the ground lies (the floors' thickness).
GROUND_DROP = 0.05
SKY_RGB = (0.62, 0.78, 0.93)
GROUND_RGB = (0.38, 0.5, 0.27)
#: The ground's emission (the sky's is 1: its pixels are its colour, whatever the lights).
GROUND_GLOW = 0.5
#: The daylight: a directional light from the sky, slanting (so it reaches in through
#: windows), its diffuse colour and its strength before the style's scaling.
DAYLIGHT_DIRECTION = (-0.45, -0.3, -1.0)
DAYLIGHT_RGB = (1.0, 0.97, 0.9)
DAYLIGHT = 0.15


def _quads(corners: list[np.ndarray], inside: np.ndarray, rgb: tuple[float, float, float]) -> ColouredMesh:
    """Quads (four corners each, in order around the quad) as triangles whose front faces
    look toward ``inside``."""
    vertices: list[np.ndarray] = []
    faces: list[tuple[int, int, int]] = []
    for quad in corners:
        base = len(vertices)
        normal = np.cross(quad[1] - quad[0], quad[2] - quad[0])
        if np.dot(normal, inside - quad.mean(axis=0)) < 0:
            quad = quad[::-1]
        vertices.extend(quad)
        faces += [(base, base + 1, base + 2), (base, base + 2, base + 3)]
    v = np.array(vertices, dtype=np.float64)
    f = np.array(faces, dtype=np.int32)
    return ColouredMesh(v, f, face_normals(v, f), np.broadcast_to(to_rgb8(np.array(rgb)), (len(f), 3)).copy())


def _box(lo: tuple[float, float], hi: tuple[float, float]) -> tuple[float, float, float, float]:
    return lo[0] - SKY_DISTANCE, lo[1] - SKY_DISTANCE, hi[0] + SKY_DISTANCE, hi[1] + SKY_DISTANCE


@lru_cache(maxsize=64)
def ground_mesh(lo: tuple[float, float], hi: tuple[float, float], rgb=GROUND_RGB) -> ColouredMesh:
    """The ground under a house of bounds ``lo``-``hi``, out to the sky's walls."""
    x0, y0, x1, y1 = _box(lo, hi)
    z = -GROUND_DROP
    quad = np.array([(x0, y0, z), (x1, y0, z), (x1, y1, z), (x0, y1, z)], dtype=np.float64)
    return _quads([quad], np.array([(x0 + x1) / 2, (y0 + y1) / 2, z + 1.0]), rgb)


@lru_cache(maxsize=64)
def sky_mesh(lo: tuple[float, float], hi: tuple[float, float], rgb=SKY_RGB) -> ColouredMesh:
    """Four walls and a lid around a house of bounds ``lo``-``hi``, facing inward."""
    x0, y0, x1, y1 = _box(lo, hi)
    z0, z1 = -GROUND_DROP, SKY_HEIGHT
    c = [np.array(p, dtype=np.float64) for p in ((x0, y0), (x1, y0), (x1, y1), (x0, y1))]
    quads = [np.array([(*c[i], z0), (*c[(i + 1) % 4], z0), (*c[(i + 1) % 4], z1), (*c[i], z1)])
             for i in range(4)]
    quads.append(np.array([(*p, z1) for p in c]))
    return _quads(quads, np.array([(x0 + x1) / 2, (y0 + y1) / 2, (z0 + z1) / 2]), rgb)


def house_statistics(model: mujoco.MjModel, data: mujoco.MjData) -> None:
    """Set ``model.stat`` to what MuJoCo computes for the house without its outside: the
    sky would make the extent (the box around every body's position and every geom's
    bounding sphere, at ``qpos0``) eight times larger, and the renderer scales its near and
    far planes, fog and shadow box by it; the outside's body would count in the mean body
    size and mass. ``data`` is fresh (at ``qpos0``)."""
    mujoco.mj_kinematics(model, data)
    body = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, BODY)
    own = model.geom_bodyid == body
    radius = model.geom_rbound[~own][:, None]
    points = data.geom_xpos[~own]
    others = np.arange(1, model.nbody) != body
    # MuJoCo's box: every body's frame and centre of mass, joint anchor, site, and geom's
    # bounding sphere (a static body's centre of mass is that of its geoms, which for a rug
    # lying on the floor need not be its frame).
    corners = [data.xpos[1:][others], data.xipos[1:][others], data.xanchor, data.site_xpos]
    known = np.concatenate([c.reshape(-1, 3) for c in corners])
    lo = np.minimum((points - radius).min(axis=0), known.min(axis=0))
    hi = np.maximum((points + radius).max(axis=0), known.max(axis=0))
    # MuJoCo's mean body size and mass, less the outside's body (massless; its size the
    # farthest reach of its geoms from it).
    stat, others = model.stat, model.nbody - 2
    size = max(float((model.geom_rbound[own] + np.linalg.norm(data.geom_xpos[own] - data.xipos[body], axis=1)).max()),
               1e-5)
    stat.meansize = (stat.meansize * (others + 1) - size) / others
    stat.meanmass = stat.meanmass * (others + 1) / others
    stat.center[:] = (lo + hi) / 2
    stat.extent = max(float((hi - lo).max()), 2 * stat.meansize)

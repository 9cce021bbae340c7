"""Render speed of the ``fast`` profile against a naive build of the same scene.

    python benchmarks/render.py [--scene examples/scenes/two_room_furnished.json] [--frames 600]
    python benchmarks/render.py --profile pretty --sizes 96,448 --frames 60

Measures, on one core (the process is pinned to CPU 0):

* frames/s of egocentric RGB at 64, 96, 128 and 224 px with our build and ``fast`` profile
  (``--profile pretty``: the ``pretty`` profile, whose shadows and multisampling the stock
  renderer then draws too);
* the same build drawn by MuJoCo's own ``mujoco.Renderer`` with our settings (the same
  image, checked), which shows what our renderer's frame does beyond it (view culling,
  only the calls that changed);
* the same for a naive build of the same scene (one geom per part, plain colours, a plane
  floor, MuJoCo's default visual settings: shadows, multisampling, a 640x480 buffer),
  measured in the same run, and the ratio;
* building the scene (scene -> MjSpec -> compiled model) and creating a renderer for a new
  scene once the process's GL context exists.

Figures are medians over repeats; treat them as orders of magnitude on shared machines.
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import time
from collections.abc import Callable
from functools import partial
from pathlib import Path

from benchmarks_common import (
    StockRender,
    median_ms,
    pin_to_one_core,
    place_agent_camera,
    write_report,
)

import legent_gym  # noqa: F401  (sets MUJOCO_GL)
from legent_gym.world.builder import BuildOptions, build_world
from legent_gym.world.render import Renderer
from legent_gym.world.scene import load_scene

REPO = Path(__file__).resolve().parents[1]
DEFAULT_SCENE = REPO / "examples" / "scenes" / "two_room_furnished.json"


def frames_per_second(draw: Callable[[], object], world, frames: int, yaw_step: float = 7.0) -> float:
    """``draw()`` the agent's view of ``world`` while turning the agent (so views change
    as in an episode)."""
    x, y = world.scene.agent.position
    for i in range(20):  # warm-up
        place_agent_camera(world, x, y, i * yaw_step)
        draw()
    start = time.perf_counter()
    for i in range(frames):
        place_agent_camera(world, x, y, i * yaw_step)
        draw()
    return frames / (time.perf_counter() - start)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--scene", default=str(DEFAULT_SCENE))
    parser.add_argument("--frames", type=int, default=600)
    parser.add_argument("--sizes", default="64,96,128,224")
    parser.add_argument("--profile", choices=("fast", "pretty"), default="fast", help="our renderer's profile")
    parser.add_argument("--json", metavar="OUT", help="also write the figures to this JSON file")
    args = parser.parse_args(argv)
    load_before = os.getloadavg()[0]
    pin_to_one_core()

    scene = load_scene(args.scene)
    fast_world = build_world(scene)
    naive_world = build_world(scene, BuildOptions(naive=True))
    print(f"scene: {args.scene}: {len(scene.rooms)} rooms, {len(scene.objects)} objects")
    print(f"geoms drawn: ours {count_visual_geoms(fast_world)}, naive {count_visual_geoms(naive_world)}")

    build_ms = median_ms(lambda: build_world(scene), 20)
    Renderer(fast_world, 96, 96).rgb("agent")  # the process's GL context now exists

    def new_renderer() -> float:
        world = build_world(scene)
        start = time.perf_counter()
        r = Renderer(world, 96, 96)
        r._ensure()
        r.close()
        return (time.perf_counter() - start) * 1e3

    create_ms = statistics.median(new_renderer() for _ in range(10))

    print(f"\nour renderer's profile: {args.profile}")
    print(f"\n{'size':>6} {'ours fps':>10} {'stock fps':>10} {'ratio':>7} {'naive fps':>10} {'ratio':>7}")
    rows = {}
    for size in (int(s) for s in args.sizes.split(",")):
        renderer, naive_renderer = Renderer(fast_world, size, size, args.profile), NaiveRenderer(naive_world, size)
        ours = frames_per_second(partial(renderer.rgb, "agent"), fast_world, args.frames)
        stock = frames_per_second(StockRender(renderer).rgb, fast_world, args.frames)
        naive = frames_per_second(partial(naive_renderer.rgb, "agent"), naive_world, max(args.frames // 10, 30))
        print(f"{size:>6} {ours:>10.0f} {stock:>10.0f} {ours / stock:>6.2f}x {naive:>10.0f} {ours / naive:>6.1f}x")
        rows[str(size)] = {"ours_fps": ours, "stock_fps": stock, "naive_fps": naive}
    print(f"\nbuild (scene -> compiled model): {build_ms:.1f} ms median")
    print(f"renderer creation for a new scene (GL context reused): {create_ms:.1f} ms median")
    if args.json:
        rows["build"] = {"ms": build_ms}
        rows["renderer"] = {"ms": create_ms}
        write_report(args.json, args, rows, load_before)
    return 0


def count_visual_geoms(world) -> int:
    from legent_gym.world.builder import GROUP_COLLISION

    return int((world.model.geom_group != GROUP_COLLISION).sum())


class NaiveRenderer(Renderer):
    """A renderer that keeps the model's own visual settings and MuJoCo's default flags.

    On the naive build these are MuJoCo's defaults: 4096 px shadow maps, 4x multisampling,
    a 640x480 offscreen buffer, shadows, reflections and skybox on.
    """

    def __init__(self, world, size):
        super().__init__(world, size, size, "pretty")

    def _ensure(self):
        import mujoco

        from legent_gym.world.builder import GROUP_COLLISION
        from legent_gym.world.render import _shared_gl_context

        _shared_gl_context(self.width, self.height)
        if self._context is None:
            self._context = mujoco.MjrContext(self.world.model, mujoco.mjtFontScale.mjFONTSCALE_150)
            mujoco.mjr_setBuffer(mujoco.mjtFramebuffer.mjFB_OFFSCREEN, self._context)
            self._scene = mujoco.MjvScene(self.world.model, maxgeom=10000)
            self._option.geomgroup[GROUP_COLLISION] = 0


if __name__ == "__main__":
    sys.exit(main())

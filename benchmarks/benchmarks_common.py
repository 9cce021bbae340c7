"""Helpers shared by the benchmark scripts."""

from __future__ import annotations

import json
import os
import statistics
import time


def pin_to_one_core() -> None:
    """Measure on one core, as the project's figures are stated."""
    if hasattr(os, "sched_setaffinity"):
        os.sched_setaffinity(0, {sorted(os.sched_getaffinity(0))[0]})


def median_ms(fn, repeats: int) -> float:
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        fn()
        times.append((time.perf_counter() - start) * 1e3)
    return statistics.median(times)


def place_agent_camera(world, x: float, y: float, yaw: float, pitch: float = 0.0) -> None:
    """Put the agent's avatar and head camera at a pose, as a step must before it renders:
    mocap pose, kinematics and camera placement (``mj_camlight``; without it the camera
    keeps its old pose and every frame shows the same view)."""
    import mujoco  # not at the top: legent_gym must choose the GL backend before mujoco loads

    world.set_body_pose("agent", x, y, yaw, pitch)
    mujoco.mj_kinematics(world.model, world.data)
    mujoco.mj_camlight(world.model, world.data)


class StockRender:
    """The reference of the speed ratios: MuJoCo's own ``mujoco.Renderer`` drawing a legent
    renderer's view (same model, options, camera and flags: the same image, checked at
    construction), with nothing of ours in between."""

    def __init__(self, renderer, camera: str = "agent"):
        import numpy as np

        self.option, self.camera, flags = renderer.mujoco_settings(camera)
        self.data = renderer.world.data
        import mujoco

        from legent_gym.world.render import set_texture_filters

        self.stock = mujoco.Renderer(renderer.world.model, renderer.height, renderer.width)
        # Its textures sampled as ours are (it samples every texture trilinearly); it keeps
        # its GL and MuJoCo contexts in attributes of its own.
        self.stock._gl_context.make_current()
        set_texture_filters(self.stock._mjr_context, renderer.world.model, renderer.profile)
        self.stock.scene.flags[:] = flags
        if not np.array_equal(self.rgb(), renderer.rgb(camera)):
            raise RuntimeError("mujoco.Renderer draws another image than legent's renderer: not a fair reference")

    def rgb(self):
        self.stock.update_scene(self.data, self.camera, self.option)
        return self.stock.render()

    def close(self) -> None:
        self.stock.close()


def write_report(path: str, args, rows: dict, load_before: float) -> None:
    """Write a benchmark's figures as JSON (atomically): its arguments, its rows, and the
    machine's load average (1 minute) before and after, which ``baselines.figures`` shows
    beside the table."""
    from legent_gym.utils.atomic import atomic_write_text

    report = {"args": vars(args), "rows": rows,
              "machine": {"load_before": load_before, "load_after": os.getloadavg()[0]}}
    atomic_write_text(path, json.dumps(report, indent=1) + "\n")

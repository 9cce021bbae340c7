"""Pictures of the people for docs/people.md: the agent's view of the user at 2 m and 5 m,
a reach, and a handover.

    python scripts/people_pictures.py [--out docs/images/people] [--size 320]

Everything is built from a fixed scene (one long room with a table and an apple) and
rendered with the ``pretty`` profile, so the same command gives the same pictures.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import cv2
import numpy as np

from legent_gym.agent.body import Body
from legent_gym.world.builder import build_world
from legent_gym.world.render import FreeCamera, Renderer
from legent_gym.world.scene import validate_scene

ROOM = [[0, 0], [9, 0], [9, 4.5], [0, 4.5]]


def _scene(agent_x: float, user_x: float, seed: int = 3) -> dict:
    return {
        "seed": seed,
        "rooms": [{"id": "r", "type": "livingroom", "name": "living room", "polygon": ROOM}],
        "walls": [{"id": f"w{i}", "start": ROOM[i], "end": ROOM[(i + 1) % 4], "rooms": ["r"]} for i in range(4)],
        "objects": [
            {"id": 1, "asset": "kitchen_counter", "kind": "static", "position": [2.1, 1.0, 0.0]},
            {"id": 2, "asset": "apple", "kind": "interactable", "position": [2.1, 1.1, 0.95]},
            {"id": 3, "asset": "sofa", "kind": "static", "position": [8.3, 3.0, 0.0], "rotation": [0, 0, 180]},
        ],
        "agent": {"position": [agent_x, 2.2], "yaw": 0},
        "user": {"position": [user_x, 2.2], "yaw": 180},
    }


def _save(path: Path, image: np.ndarray) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    if not cv2.imwrite(str(path), cv2.cvtColor(image, cv2.COLOR_RGB2BGR)):
        raise OSError(f"could not write {path}")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default="docs/images/people")
    parser.add_argument("--size", type=int, default=320)
    args = parser.parse_args(argv)
    out, size = Path(args.out), args.size

    for distance in (2, 5):
        world = build_world(validate_scene(_scene(6.5 - distance, 6.5)))
        renderer = Renderer(world, size, size, "pretty")
        _save(out / f"agent_view_{distance}m.png", renderer.rgb("agent"))
        renderer.close()

    # A reach: the agent stands by the table and takes the apple; shown from the side.
    world = build_world(validate_scene(_scene(1.5, 6.5)))
    agent = Body(world, "agent", other="user", record_motion=True)
    agent.place(2.1, 1.95, -90.0, 30.0)
    agent.begin_batch()  # one step: its frames go from the stand to the apple in hand
    outcome = agent.grab(2)
    agent.end_batch()
    if not outcome.ok:
        raise RuntimeError(f"the picture's grab failed: {outcome.reason}")
    renderer = Renderer(world, size, size, "pretty")
    side = FreeCamera((2.1, 1.7, 0.9), 2.6, azimuth=200.0, elevation=-15.0)
    agent.show_motion(0.75)  # most of the way through the reach, before the hands close on it
    _save(out / "reach.png", renderer.rgb(side))
    agent.show_motion(1.0)
    _save(out / "carry.png", renderer.rgb(side))

    # A handover: carrying the apple up to the user, who faces the agent.
    agent.place(5.3, 2.2, 0.0)
    user = Body(world, "user", other="agent")
    user.place(6.5, 2.2, 180.0)
    agent.place(5.3, 2.2, 0.0)  # the user is now in front and near: the apple is held out
    _save(out / "handover.png", renderer.rgb(FreeCamera((5.9, 2.2, 1.0), 2.0, azimuth=240.0, elevation=-10.0)))
    _save(out / "agent_view_handover.png", renderer.rgb("agent"))
    renderer.close()
    print(f"wrote the pictures to {out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

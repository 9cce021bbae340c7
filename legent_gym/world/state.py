"""Put a built world back as it was built, without building it again.

Building a house (MuJoCo spec, compile, first forward pass) costs tens of milliseconds; a
house that serves several episodes is built once and restored between them. A
:class:`WorldState` holds everything an episode may change: the whole ``MjData`` (object
poses, door and drawer joints, velocities, solver warm start, time) and the model's
collision switches (a held object's collision geoms are off while it is carried).
:func:`restore` then leaves the world in exactly the state :func:`capture` saw, so an
episode in a restored world sees what it would see in a freshly built one.
"""

from __future__ import annotations

import copy
from dataclasses import dataclass

import mujoco
import numpy as np

from legent_gym.world.builder import World

#: The part of ``MjData`` a :class:`WorldState` may hold instead of a whole copy: all that
#: ``mj_forward`` does not compute (time, positions, velocities, activations, warm start,
#: controls, applied forces, mocap poses, equality switches, user and plugin data).
INTEGRATION = mujoco.mjtState.mjSTATE_INTEGRATION


@dataclass(frozen=True)
class WorldState:
    """A copy of a world's mutable state (see the module docstring): the whole ``data``, or
    (``data`` None) its ``integration`` state alone (``mj_getState`` of
    :data:`INTEGRATION`), which costs no ``MjData`` of its own; :func:`restore` of such a
    state leaves what ``mj_forward`` computes for the caller's next ``mj_forward``."""

    data: mujoco.MjData | None
    geom_contype: np.ndarray
    geom_conaffinity: np.ndarray
    integration: np.ndarray | None = None


def capture(world: World) -> WorldState:
    """The world's state now (a copy)."""
    return WorldState(copy.copy(world.data), world.model.geom_contype.copy(), world.model.geom_conaffinity.copy())


def restore(world: World, state: WorldState) -> None:
    """Put ``world`` back in ``state`` (taken from this world by :func:`capture`, or an
    integration state of its model: then call ``mj_forward`` before reading what it computes)."""
    if state.data is not None:
        mujoco.mj_copyData(world.data, world.model, state.data)
    else:
        assert state.integration is not None, "a WorldState holds its data or its integration state"
        mujoco.mj_setState(world.model, world.data, state.integration, INTEGRATION)
    world.model.geom_contype[:] = state.geom_contype
    world.model.geom_conaffinity[:] = state.geom_conaffinity

"""Where each episode's house comes from (:class:`HouseSource`), the house drawn
(:class:`HouseDraw`), a built house kept for reuse (:class:`House`) and one made ahead in a
background thread (:class:`HouseAhead`); :class:`~legent_gym.envs.episode.Episode` plays
its episodes in them and :mod:`legent_gym.envs.factory` ships them between processes."""

from __future__ import annotations

import contextlib
import copy
import os
import threading
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from legent_gym.tasks.base import Task
from legent_gym.world.builder import World
from legent_gym.world.generation import generate_house_with_grid
from legent_gym.world.generation.house import SpawnSampler
from legent_gym.world.navigation import NavGrid
from legent_gym.world.scene import Scene, load_scene
from legent_gym.world.state import WorldState

#: The nice value of the thread that makes the next house ahead: it runs when the process
#: would wait, not in place of its steps.
AHEAD_NICE = 19


@dataclass(frozen=True)
class HouseDraw:
    """One house the source chose: ``key`` names it (the same key, the same house),
    ``seed`` is its generation seed (None for a scene given or read from a file),
    ``spawns_drawn`` says its spawns are drawn per episode (a folder's houses)."""

    key: tuple
    seed: int | None
    #: () -> (Scene, its NavGrid.from_scene grid or None); called only when the house is not kept.
    load: Callable[[], tuple[Scene, NavGrid | None]] = field(compare=False)
    spawns_drawn: bool = False
    #: The source may give this house again (kept for that; a new random seed is not).
    repeats: bool = True
    #: () -> the bytes that make this house (a scene file's, or its generation's key): what
    #: names it in a store of built houses (:mod:`legent_gym.envs.house_store`); None for a
    #: house not stored (a new random seed, a scene given as an object).
    recipe: Callable[[], bytes] | None = field(default=None, compare=False)


class HouseSource:
    """Where each episode's house comes from, in this order of precedence: a fixed
    ``scene``, a ``houses`` folder of scene files (``legent-gym generate --count N
    --out-dir DIR``; one drawn at random each time), a ``house_pool`` of generation seeds
    cycled through, a fixed ``house_seed``, else a new seed of ``layout`` drawn from the
    episode's generator."""

    def __init__(self, layout: str, *, scene: Scene | None = None, house_seed: int | None = None,
                 house_pool: list[int] | None = None, houses: str | Path | None = None):
        self.layout = layout
        self.scene = scene
        self.house_seed = house_seed
        self.house_pool = list(house_pool) if house_pool else None
        self.pool_index = 0
        self.files: list[Path] | None = None
        if houses is not None and scene is None:
            folder = Path(houses)
            if not folder.is_dir():
                raise ValueError(f"houses={str(houses)!r} is not a folder (make one with "
                                 "`legent-gym generate --count N --out-dir DIR`)")
            self.files = sorted(folder.glob("*.json"))
            if not self.files:
                raise ValueError(f"houses folder {str(folder)!r} holds no *.json scene")

    @property
    def seed_fixed(self) -> bool:
        """A generation failure is the caller's to see (a fixed seed or a pool), not a
        reason to draw another house."""
        return self.files is None and (self.house_seed is not None or bool(self.house_pool))

    @property
    def house_fixed(self) -> bool:
        """Every episode is in the same house: a house with no goal is an error."""
        return self.scene is not None or (self.files is None and self.house_seed is not None and not self.house_pool)

    def peek(self, rng: np.random.Generator, task: Task) -> HouseDraw:
        """The house that ``draw(rng, task)`` would give now, moving neither ``rng`` nor
        this source."""
        return copy.copy(self).draw(copy.deepcopy(rng), task)

    def draw(self, rng: np.random.Generator, task: Task) -> HouseDraw:
        """The next house (its scene is made only if it is not kept already)."""
        if self.scene is not None:
            scene = self.scene
            return HouseDraw(("scene", id(scene)), None, lambda: (scene, None))
        if self.files is not None:
            path = self.files[int(rng.integers(len(self.files)))]
            return HouseDraw(("file", str(path)), None, lambda: (load_scene(path), None), spawns_drawn=True,
                             recipe=path.read_bytes)
        if self.house_pool:
            seed = self.house_pool[self.pool_index % len(self.house_pool)]
            self.pool_index += 1
        elif self.house_seed is not None:
            seed = self.house_seed
        else:
            seed = int(rng.integers(2**31 - 1))
        conditions = task.house_conditions(seed)
        key = ("seed", self.layout, seed, repr(sorted(conditions.items())))
        # The generator's own navigation grid of the house comes along (cheaper than a new one).
        return HouseDraw(key, seed, lambda: generate_house_with_grid(seed, self.layout, **conditions),
                         repeats=self.seed_fixed, recipe=(lambda: repr(key).encode()) if self.seed_fixed else None)


@dataclass
class House:
    """A built house kept for reuse: its scene, world, navigation grid and state as built."""

    draw: HouseDraw
    scene: Scene
    world: World
    nav: NavGrid
    built: WorldState
    #: The generation seed: the one drawn, or the one a folder's scene file records.
    seed: int | None
    #: Draws new spawns in this house (made at its first drawn spawns).
    spawns: SpawnSampler | None = None
    #: Episodes begun in this house since it was last drawn.
    episodes: int = 0
    #: The compiled model as built, as MuJoCo's binary (``Episode.keep_binaries``).
    binary: np.ndarray | None = None


class HouseAhead:
    """One house made in a background thread (see the module docstring): :meth:`take`
    waits for it and gives it, or raises what making it raised."""

    def __init__(self, draw: HouseDraw, make: Callable[[HouseDraw], House]):
        self.draw = draw
        self._make = make
        self._house: House | None = None
        self._error: BaseException | None = None
        self._thread = threading.Thread(target=self._run, name="legent-house-ahead")
        self._thread.start()

    def _run(self) -> None:
        with contextlib.suppress(AttributeError, OSError):
            # Linux gives each thread its own nice value (best effort elsewhere).
            os.setpriority(os.PRIO_PROCESS, threading.get_native_id(), AHEAD_NICE)
        try:
            self._house = self._make(self.draw)
        except BaseException as err:  # noqa: BLE001 - raised again in the thread that takes it
            self._error = err

    @property
    def done(self) -> bool:
        return not self._thread.is_alive()

    def wait(self) -> None:
        self._thread.join()

    def take(self) -> House:
        self.wait()
        if self._error is not None:
            raise self._error
        assert self._house is not None
        return self._house

"""Built houses on disk (``house_cache=DIR``): a house that a source gives again is built
once, by any process, and loaded by the others in a few milliseconds.

Building a house from its scene (the MuJoCo model made and compiled, the navigation grid
made) costs tens of milliseconds of CPU, most of a reset for a ``houses`` folder larger
than ``houses_kept`` (the env then builds each episode's house again). A :class:`HouseStore`
keeps each built house as two files named by a digest of what made it: the compiled model
as MuJoCo's binary (``<digest>.mjb``) and the rest as :mod:`pickle` (``<digest>.house``:
the scene, the state as built, the world's tables and the navigation grid, as episode
helpers ship them, :class:`~legent_gym.envs.factory.HousePayload`). Loading them is the
model read from its binary and a few arrays unpickled.

* **What is stored**: the houses of a ``houses`` folder, of a fixed ``house_seed`` and of a
  ``house_pool``. A new random seed each episode is not (it is never asked for again), nor
  a scene given as an object.
* **The digest** covers the scene file's bytes (or the layout, seed and the task's
  conditions of a generated house), the build options (image size included), the asset
  ids registered, and the versions of legent_gym, of its house generator
  (``GENERATOR_VERSION``), of its builder (``BUILD_VERSION``: what a scene builds into) and
  of MuJoCo: a changed scene file or an upgrade gives new
  names, never a stale house. A registered asset whose file changed
  under the same id is not seen: empty the folder then.
* **Safe to share**: every process of a vector env, its helpers and later runs may use one
  folder. Each file is written to a temporary name and renamed (two processes that build
  the same house write the same bytes; the last rename wins). The ``.house`` file is
  written last, so a house is found only once both files are whole.
* **A damaged file** (cut short, from another version) is reported with a warning naming
  it, and the house is built and stored again.
* The ``.house`` files are pickles, which run code when loaded: point ``house_cache`` only
  at folders you trust, as with any cache.
"""

from __future__ import annotations

import hashlib
import os
import pickle
import warnings
from pathlib import Path

import mujoco
import numpy as np

import legent_gym
from legent_gym.envs.factory import HousePayload
from legent_gym.envs.houses import House, HouseDraw
from legent_gym.utils.atomic import atomic_write_bytes
from legent_gym.world.assets import registry
from legent_gym.world.builder import BUILD_VERSION, BuildOptions
from legent_gym.world.generation import GENERATOR_VERSION

#: Changes whenever what a ``.house`` file holds changes.
STORE_FORMAT = 1


class HouseStore:
    """A folder of built houses (see the module docstring)."""

    def __init__(self, folder: str | os.PathLike, options: BuildOptions):
        self.folder = Path(folder)
        try:
            self.folder.mkdir(parents=True, exist_ok=True)
        except OSError as err:
            raise ValueError(f"house_cache={str(folder)!r} cannot be made a folder: {err}") from None
        if not os.access(self.folder, os.W_OK | os.X_OK):
            raise ValueError(f"house_cache={str(folder)!r} is not a folder this process may write to")
        self._context = repr((STORE_FORMAT, legent_gym.__version__, GENERATOR_VERSION, BUILD_VERSION,
                              mujoco.__version__, options)).encode()
        #: Houses loaded from the folder and houses built and stored in it by this process.
        self.loaded = 0
        self.stored = 0

    def __getstate__(self) -> dict:
        return {**self.__dict__, "loaded": 0, "stored": 0}

    def digest(self, draw: HouseDraw) -> str | None:
        """The file name stem of ``draw``'s house, or None for a house not stored."""
        if draw.recipe is None:
            return None
        made_of = hashlib.sha256(self._context)
        made_of.update(repr(registry.asset_ids()).encode())
        made_of.update(draw.recipe())
        return made_of.hexdigest()[:40]

    def load(self, draw: HouseDraw, with_binary: bool = False) -> House | None:
        """``draw``'s house from the folder (with its model's binary as ``House.binary``
        if ``with_binary``), or None when it is not there (or damaged)."""
        stem = self.digest(draw)
        if stem is None:
            return None
        house_file, model_file = self.folder / f"{stem}.house", self.folder / f"{stem}.mjb"
        try:
            blob = house_file.read_bytes()
        except FileNotFoundError:
            return None
        try:
            payload = pickle.loads(blob)
            if not isinstance(payload, HousePayload):
                raise TypeError(f"it holds a {type(payload).__name__}, not a house")
            payload.model_path = str(model_file)
            house = payload.to_house({})
            if with_binary:
                house.binary = np.fromfile(model_file, dtype=np.uint8)
        except Exception as err:  # noqa: BLE001 - any damage: say which file, build again
            warnings.warn(f"house_cache: {house_file} cannot be loaded ({type(err).__name__}: {err}); "
                          "building the house again", RuntimeWarning, stacklevel=2)
            return None
        house.draw = draw
        self.loaded += 1
        return house

    def save(self, house: House, binary: np.ndarray) -> None:
        """Store ``house`` (just built: ``binary`` is its model as built) unless its draw
        is not stored."""
        stem = self.digest(house.draw)
        if stem is None:
            return
        atomic_write_bytes(self.folder / f"{stem}.mjb", binary.tobytes(), durable=False)
        library_refs = {(obj.asset, obj.variant) for obj in house.scene.objects}  # made again on load
        payload = HousePayload.of(house, "", library_refs)  # the model's path is set on load
        atomic_write_bytes(self.folder / f"{stem}.house", pickle.dumps(payload, protocol=pickle.HIGHEST_PROTOCOL),
                           durable=False)
        self.stored += 1


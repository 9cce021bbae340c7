"""RL Baselines3 Zoo hyperparameters for the ``Legent/*`` ids, shipped with the package.

One YAML file per algorithm (``ppo.yml``), read by RL Zoo through a module of the same name
that holds its contents as ``hyperparams`` (RL Zoo's ``--conf-file`` takes a module)::

    python -m rl_zoo3.train --algo ppo --env Legent/ComeHere-OneRoom-v0 --gym-packages legent_gym \\
        --conf-file legent_gym.hyperparams.ppo -f logs

RL Zoo's own defaults (``MlpPolicy``, no wrapper) cannot run on these envs: their ``Text``
observations have no array shape, so its vector env dies allocating them (``TypeError:
'NoneType' object is not iterable``). ``python -m legent_gym.hyperparams ppo`` prints the
YAML file's path, to copy and edit (``--conf-file my_ppo.yml``).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import yaml

ALGOS: tuple[str, ...] = tuple(sorted(p.stem for p in Path(__file__).parent.glob("*.yml")))


def path(algo: str) -> Path:
    """The YAML file of ``algo``'s hyperparameters."""
    if algo not in ALGOS:
        raise ValueError(f"no hyperparameters for {algo!r}: legent_gym ships {list(ALGOS)}")
    return Path(__file__).parent / f"{algo}.yml"


def load(algo: str) -> dict[str, Any]:
    """``algo``'s hyperparameters as RL Zoo reads them: ``{"default": {...}}``."""
    with open(path(algo)) as f:
        return yaml.safe_load(f)


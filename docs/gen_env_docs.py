"""Write docs/envs/*.md from the environments' Markdown-sectioned docstrings.

    python docs/gen_env_docs.py
"""

from __future__ import annotations

import inspect
from pathlib import Path

import gymnasium as gym

import legent_gym
from legent_gym.atomic import atomic_write_text
from legent_gym.envs.registration import LAYOUTS, TASKS

OUT = Path(__file__).resolve().parent / "envs"


def page() -> str:
    env_class = gym.spec(legent_gym.ENV_IDS[0]).entry_point
    module, name = env_class.split(":")
    cls = getattr(__import__(module, fromlist=[name]), name)
    doc = inspect.cleandoc(cls.__doc__)
    ids = "\n".join(f"| `Legent/{t}-{layout}-v0` | {t} | {layout} | 25 |" for t in TASKS for layout in LAYOUTS)
    return (f"# Household environments\n\n"
            f"| id | task | layout | max steps |\n|---|---|---|---|\n{ids}\n\n"
            "Every id takes both action spaces: `gym.make(id)` (text) or "
            "`gym.make(id, action_type=\"continuous\")`.\n\n" + doc + "\n")


def main() -> None:
    atomic_write_text(OUT / "household.md", page())
    print(f"wrote {OUT / 'household.md'}")


if __name__ == "__main__":
    main()

"""Write docs/envs/*.md from the environments' Markdown-sectioned docstrings.

    python docs/gen_env_docs.py

``household.md``: the Gymnasium ids (``HouseholdEnv``); ``multiagent.md``: the PettingZoo
ids (``HouseholdParallelEnv``).
"""

from __future__ import annotations

import inspect
from pathlib import Path

import gymnasium as gym

import legent_gym
from legent_gym.envs.registration import ID_TABLE, SCENE_TASK_IDS
from legent_gym.experts import code_template
from legent_gym.tasks import MAX_ACTIONS, TASKS
from legent_gym.utils.atomic import atomic_write_text

OUT = Path(__file__).resolve().parent / "envs"


def page() -> str:
    env_class = gym.spec(legent_gym.ENV_IDS[0]).entry_point
    module, name = env_class.split(":")
    cls = getattr(__import__(module, fromlist=[name]), name)
    doc = inspect.cleandoc(cls.__doc__)
    ids = "\n".join(f"| `{env_id}` | {task} | {layout} | {MAX_ACTIONS} |" for env_id, task, layout in ID_TABLE)
    ids += "".join(f"\n| `{env_id}` | {task} (tasks from `tasks=`) | the `scene=` given | {MAX_ACTIONS} |"
                   for env_id, task in SCENE_TASK_IDS)
    return (f"# Household environments\n\n"
            f"| id | task | layout | max steps |\n|---|---|---|---|\n{ids}\n\n"
            "Every id takes both action spaces: `gym.make(id)` (text) or "
            "`gym.make(id, action_type=\"continuous\")`.\n\n" + tasks_table() + "\n\n" + doc + "\n")


def tasks_table() -> str:
    """The registered tasks, each as its class says: the paper's wording of its instruction,
    success (its module's docstring from "Success:"), the expert's code and its kinds of a
    tasks file."""
    rows = []
    for name, task in TASKS.items():
        module_doc = " ".join((inspect.getmodule(task).__doc__ or "").split())
        success = module_doc.split("Success: ", 1)[1] if "Success: " in module_doc else ""
        kinds = ", ".join(f"`{kind}`" for kind in task.kinds)
        rows.append(f"| {name} | {task.templates[0].format(a='A', b='B')} | {success} | "
                    f"`{code_template(task)}` | {kinds} |")
    return ("## Tasks\n\nEach task is one file of `legent_gym/tasks/` (docs/adding-a-task.md adds one).\n\n"
            "| task | instruction | success | expert code | tasks-file kinds |\n|---|---|---|---|---|\n"
            + "\n".join(rows))


def multiagent_page() -> str:
    from legent_gym.multiagent.household import HouseholdParallelEnv

    doc = inspect.cleandoc(HouseholdParallelEnv.__doc__)
    return ("# Multi-agent household environments (PettingZoo)\n\n"
            "The same ids as the single-agent envs, in PettingZoo's registry: "
            "`pettingzoo.make(\"parallel\", id)` or `pettingzoo.make(\"aec\", id)` after "
            f"`import legent_gym.multiagent`; `max_cycles` is {MAX_ACTIONS}.\n\n" + doc + "\n")


PAGES = {"household.md": page, "multiagent.md": multiagent_page}


def main() -> None:
    for name, make in PAGES.items():
        atomic_write_text(OUT / name, make())
        print(f"wrote {OUT / name}")


if __name__ == "__main__":
    main()

"""A task is one unit: a toy task defined in this file alone is registered, passes
:func:`legent_gym.testing.check_task` (check_env, determinism, the expert), gets env ids
and a kind of a tasks file; every built-in task passes the same checks; a broken task
fails them; and no code compares a task's name outside the task's own file."""

from __future__ import annotations

import inspect
import itertools
import re
from dataclasses import dataclass
from pathlib import Path

import gymnasium as gym
import pytest

import legent_gym
from legent_gym.envs.household import HouseholdEnv
from legent_gym.envs.registration import register_envs
from legent_gym.experts import Expert, code_template
from legent_gym.tasks import TASKS, Evaluation, Task, TaskInstance, register_task, task_of_kind
from legent_gym.tasks.common import COME_HERE_DISTANCE, fits, to_user
from legent_gym.tasks.custom import TaskSpec
from legent_gym.tasks.feasibility import user_leg
from legent_gym.testing import check_task, registered_task
from tests.conftest import EXAMPLES, REPO


@dataclass
class GreetGoal(TaskInstance):
    instruction: str

    def evaluate(self, ctx):
        near = ctx.agent.horizontal_distance(ctx.user.xy) < COME_HERE_DISTANCE
        greeted = any("hello" in text.lower() for text in ctx.speech)
        return Evaluation(near and greeted, bool(ctx.speech))  # speaking ends the episode

    def distance_left(self, ctx):
        return to_user(ctx)


class Greet(Task):
    """A toy task: come to the user and say hello."""

    name = "Greet"
    goal_type = GreetGoal
    templates = ("Come and say hello.", "Come over and greet me.")
    code = 'goto_user() speak("Hello!")'
    kinds = {"greet": "come to the user and say hello; no target"}

    def sample(self, ctx, rng):
        if not fits(user_leg(ctx), interactions=1):  # the walk and the greeting within the episode's actions
            return None
        return GreetGoal(self.word(rng))


class Mute(Greet):
    """A broken task: the expert's code never says hello."""

    name = "Mute"
    code = "goto_user()"
    kinds = {}


@dataclass
class SerialGoal(GreetGoal):
    serial: int = 0

    def evaluate(self, ctx):
        judged = super().evaluate(ctx)
        return Evaluation(judged.success, judged.ends, {"serial": self.serial})


class Fickle(Greet):
    """A broken task: its goals differ from one env to another for the same seed."""

    name = "Fickle"
    kinds = {}
    made = itertools.count()

    def __init__(self):
        self.serial = next(self.made)  # one per env: check_env's one env sees no difference

    def sample(self, ctx, rng):
        goal = super().sample(ctx, rng)
        return None if goal is None else SerialGoal(goal.instruction, self.serial)


def test_a_task_from_this_file_alone_passes_check_task():
    with registered_task(Greet):
        assert TASKS["Greet"] is Greet and task_of_kind("greet") is Greet
        actions = check_task(Greet, seeds=(0, 1))
        assert set(actions) == {0, 1} and all(1 <= n <= legent_gym.tasks.MAX_ACTIONS for n in actions.values())
        assert code_template(Greet) == 'goto_user() speak("Hello!")'
    assert "Greet" not in TASKS
    with pytest.raises(ValueError, match="unknown kind 'greet'"):
        task_of_kind("greet")


def test_a_registered_task_gets_env_ids_and_plays_a_tasks_files_kind():
    with registered_task(Greet):
        register_envs()  # what import legent_gym did for the built-in tasks
        env = gym.make("Legent/Greet-TwoRoom-v0", width=32, height=32)
        assert env.spec.max_episode_steps == legent_gym.tasks.MAX_ACTIONS
        obs, _ = env.reset(seed=3)
        assert obs["instruction"] in Greet.templates
        env.close()
        spec = TaskSpec(kind="greet", instruction="Hi there, come say hello.", code=code_template(Greet))
        custom = HouseholdEnv("Custom", scene=EXAMPLES / "two_room_furnished.json", tasks=[spec], width=32, height=32)
        custom.reset(seed=0)
        expert = Expert(custom)
        for _ in range(legent_gym.tasks.MAX_ACTIONS):
            _, _, terminated, _, info = custom.step(expert.action())
            if terminated:
                break
        assert info["success"] and custom.episode.require_goal().instruction == spec.instruction
        custom.close()
    assert "Legent/Greet-TwoRoom-v0" not in gym.registry


@pytest.mark.parametrize("name", list(TASKS))
def test_every_registered_task_passes_check_task(name):
    assert check_task(TASKS[name], seeds=(0,))


def test_check_task_fails_a_task_its_expert_cannot_complete():
    with registered_task(Mute), pytest.raises(AssertionError, match="did not complete Mute in seed 0"):
        check_task(Mute, seeds=(0,))


def test_check_task_fails_a_task_that_is_not_deterministic():
    with registered_task(Fickle), pytest.raises(AssertionError, match="not deterministic: seed 0, action 0: the two plays' first"):
        check_task(Fickle, seeds=(0,))


def test_check_task_refuses_a_task_that_is_not_registered():
    with pytest.raises(ValueError, match="Greet is not registered with layouts as 'Greet'"):
        check_task(Greet)


def test_registration_refuses_a_taken_name_or_kind_and_unknown_code_fields():
    with pytest.raises(ValueError, match="'ComeHere' is registered already"):
        register_task(type("ComeHere", (Greet,), {"name": "ComeHere", "kinds": {}}))
    with pytest.raises(ValueError, match="judges the kind 'come', which ComeHere judges already"):
        register_task(type("Again", (Greet,), {"name": "Again", "kinds": {"come": "again"}}))
    with pytest.raises(ValueError, match=r"code names \['c'\]"):
        register_task(type("Odd", (Greet,), {"name": "Odd", "kinds": {}, "code": "goto({c})"}))
    with pytest.raises(ValueError, match="must be an identifier"):
        register_task(type("Bad", (Greet,), {"name": "Bad-Name", "kinds": {}}))
    assert list(TASKS) == ["ComeHere", "GoTo", "PickUp", "BringMe", "WhereIs", "PutOn"]


def test_no_code_compares_a_task_name_outside_its_own_file():
    """Only a task's own file may compare against its name: everything else reads the class."""
    files = [p for folder in ("legent_gym", "baselines", "benchmarks") for p in (REPO / folder).rglob("*.py")]
    for name, task in TASKS.items():
        own = Path(inspect.getsourcefile(task)).resolve()
        quoted = f"[\"']{name}[\"'-]"
        compare = re.compile(rf"(==|!=|\bin\b|\bcase\b|startswith\(|endswith\()\s*\(?\s*[^\n]*{quoted}"
                             rf"|{quoted}[^\n]*\s(==|!=|in)\s")
        found = [f"{path.relative_to(REPO)}:{n}: {line.strip()}" for path in files if path.resolve() != own
                 for n, line in enumerate(path.read_text().splitlines(), 1) if compare.search(line)]
        assert not found, f"{name} compared by name:\n" + "\n".join(found)

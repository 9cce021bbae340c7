"""Tasks for a given scene, written by an LLM and kept only if they can be done.

``legent-gym tasks generate scene.json --n 20 --llm-base-url URL --model M --out
tasks.jsonl``: the LLM is shown the scene's object table (:data:`~legent_gym.llm.prompts.TASK_PROMPT`,
LEGENT's task creator's table: id, name, x, y, z) and writes tasks as JSON, each a kind,
an instruction, its objects and intermediate code (or, as a string, LEGENT's own form
``Task: ...; Plan: ...; Solution: ...``, whose kind and objects are read off the solution
by :func:`from_legent_text`). Each task is then checked, in order:

1. its fields (:class:`~legent_gym.tasks.custom.TaskSpec`: a known kind, the objects that
   kind needs);
2. its code: parsed by :func:`~legent_gym.experts.program.parse_program`, every id in the
   scene (:func:`~legent_gym.experts.program.check_program`);
3. its objects: in the scene; a target the kind's task picks up (its code starts by
   fetching it) can be picked up; and what the task's ``spec_problem`` asks (for
   ``where`` and ``exist``, the receptacle is what the target stands on; for ``put``, not
   where it stands already);
4. the env (``Legent/Custom-v0`` in the scene, from the scene's spawns): not done before
   any action; its code, run by :class:`~legent_gym.experts.ProgramExecutor`, succeeds as
   its kind judges within :data:`~legent_gym.tasks.MAX_ACTIONS` actions; and so does the
   task expert (:class:`~legent_gym.experts.Expert`), so that every kept task has expert
   demonstrations.

The tasks file (JSON lines, written atomically) has a header (format, scene name, the
scene's objects as ``[id, asset]`` pairs, prompt version, model) and one line per task:
``"status": "kept"`` with the actions its code and the expert took, or ``"status":
"rejected"`` with the ``reason``.
"""

from __future__ import annotations

import json
import re
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from pydantic import BaseModel, Field, ValidationError

from legent_gym.envs.household import HouseholdEnv
from legent_gym.errors import UserError
from legent_gym.experts import Expert, PlanningError, ProgramExecutor
from legent_gym.experts.program import ProgramError, check_program, parse_program
from legent_gym.llm.client import ChatClient, LLMError, describe_error
from legent_gym.llm.prompts import TASK_PROMPT_VERSION, task_messages
from legent_gym.tasks import MAX_ACTIONS
from legent_gym.tasks.custom import TASKS_FORMAT, TASKS_VERSION, TaskSpec
from legent_gym.utils.atomic import atomic_write_text
from legent_gym.world.scene import load_scene

#: The most tasks one request asks for.
MAX_TASKS = 100


class TaskReply(BaseModel):
    """The reply's shape; each task is checked on its own (a bad one is rejected, not re-asked)."""

    tasks: list[Any] = Field(min_length=1)


@dataclass
class Outcome:
    """The tasks file's lines: kept tasks and rejected ones, with their reasons."""

    header: dict[str, Any]
    records: list[dict[str, Any]] = field(default_factory=list)

    @property
    def kept(self) -> list[dict[str, Any]]:
        return [r for r in self.records if r["status"] == "kept"]

    @property
    def rejected(self) -> list[dict[str, Any]]:
        return [r for r in self.records if r["status"] == "rejected"]

    def text(self) -> str:
        return "".join(json.dumps(r) + "\n" for r in [self.header, *self.records])


def object_table(ctx: Any) -> str:
    """LEGENT's table of a scene's objects: ``id | name | x | y | z | on | pickable``."""
    lines = []
    for obj in ctx.scene.objects:
        x, y, z = (float(v) for v in ctx.object_centre(obj.id))
        on = "floor" if obj.on is None else f"{ctx.name_of(obj.on)} ({obj.on})"
        lines.append(f"{obj.id} | {ctx.name_of(obj.id)} | {x:.2f} | {y:.2f} | {z:.2f} | {on} | "
                     f"{'yes' if obj.kind == 'interactable' else 'no'}")
    return "\n".join(lines)


_LEGENT_TASK = re.compile(r"^\s*Task:\s*(?P<task>.+?)\s*;\s*Plan:\s*(?P<plan>.*?)\s*;\s*Solution:\s*(?P<code>.+?)\s*$",
                          re.DOTALL | re.IGNORECASE)


def from_legent_text(text: str, scene: Any) -> dict[str, Any]:
    """A task dict from LEGENT's ``Task: ...; Plan: ...; Solution: ...`` form, its kind and
    objects read off the solution's code; ``ValueError`` saying why not."""
    match = _LEGENT_TASK.match(text)
    if match is None:
        raise ValueError("neither a JSON object nor 'Task: ...; Plan: ...; Solution: ...'")
    code = match["code"]
    out: dict[str, Any] = {"instruction": match["task"], "code": code, "plan": match["plan"]}
    try:
        program = parse_program(code)
    except ProgramError as err:
        raise ValueError(f"code: {err}") from None
    names = [i.name for i in program]
    acts = [k for k, n in enumerate(names) if n in ("interact", "grab", "put")]
    objects = [(k, i.arg) for k, i in enumerate(program) if i.name in ("goto", "find", "target")]
    if "speak" in names and "find" in names:
        target = next(a for k, a in objects if program[k].name == "find")
        hosts = {o.id: o.on for o in scene.objects}
        out.update(kind="where", target=target, receptacle=hosts.get(target))
    elif acts:
        before = [a for k, a in objects if k < acts[0]]
        after = [a for k, a in objects if k > acts[0]]
        if not before:
            raise ValueError("code: nothing is approached before the first interaction")
        out["target"] = before[-1]
        if len(acts) > 1 and after:
            out.update(kind="put", receptacle=after[-1])
        else:
            out["kind"] = "bring" if "goto_user" in names[acts[0]:] else "take"
    elif names == ["goto_user"] or names == ["goto_user", "finish"]:
        out["kind"] = "come"
    elif objects and all(n in ("goto", "finish") for n in names):
        out.update(kind="goto", target=objects[-1][1])
    else:
        raise ValueError(f"cannot tell the kind of task from the solution {code!r}")
    return out


def _static_problem(spec: TaskSpec, ctx: Any) -> str | None:
    """Why the task's code or objects cannot be right in this scene (None: they can)."""
    try:
        program = parse_program(spec.code)
        check_program(program, [o.id for o in ctx.scene.objects], [d.id for d in ctx.scene.doors])
    except ProgramError as err:
        return f"code: {err}"
    ids = {o.id: o for o in ctx.scene.objects}
    task = spec.task
    for role in task.roles:
        if getattr(spec, role) not in ids:
            return f"{role} {getattr(spec, role)}: no object with that id in the scene"
    a = spec.target
    if task.fetches_target() and a is not None and ids[a].kind != "interactable":
        return f"target {a} ({ctx.name_of(a)}) cannot be picked up"
    return task.spec_problem(ctx, spec.target, spec.receptacle)


def _run(env: Any, index: int, policy: str, code: str) -> tuple[bool, int, str]:
    """Play task ``index`` of the env's Custom task with ``policy`` (``"code"``: the task's
    code; ``"expert"``: the task expert): (success, actions, why not)."""
    env.unwrapped.episode.task.next_index = index
    _, info = env.reset(seed=0)
    if info["success"]:
        return False, 0, "done before any action"
    actor = ProgramExecutor(env, code) if policy == "code" else Expert(env)
    last = ""
    for n in range(1, MAX_ACTIONS + 1):
        try:
            action = actor.action()
        except PlanningError as err:
            return False, n - 1, f"cannot be carried out: {err}"
        _, _, terminated, _, info = env.step(action)
        if info["success"]:
            return True, n, ""
        last = info.get("action_text", "")
        if terminated:
            return False, n, f"the episode ended without success after {n} action(s) (last: {last})"
    return False, MAX_ACTIONS, f"not done within {MAX_ACTIONS} actions"


def check_tasks(scene: Any, drafts: list[Any], *, header: dict[str, Any] | None = None) -> Outcome:
    """Check each draft (a dict as the LLM wrote it) in ``scene`` (see the module
    docstring): the kept tasks and the rejected ones with their reasons."""
    objects = [[o.id, o.asset] for o in scene.objects]
    outcome = Outcome({"format": TASKS_FORMAT, "version": TASKS_VERSION, "scene": scene.name,
                       "objects": objects, **(header or {})})
    specs: list[TaskSpec] = []
    slots: list[dict[str, Any] | None] = []  # a record, or None: to be run
    seen: set[tuple[str, str]] = set()
    env = None
    for draft in drafts:
        if isinstance(draft, str):
            try:
                draft = from_legent_text(draft, scene)
            except ValueError as err:
                slots.append({"status": "rejected", "reason": str(err), "reply": draft})
                continue
        if not isinstance(draft, dict):
            slots.append({"status": "rejected", "reason": "not a JSON object", "reply": draft})
            continue
        try:
            spec = TaskSpec.model_validate(draft)
        except ValidationError as err:
            slots.append({"status": "rejected", "reason": f"not a task: {describe_error(err)}", "reply": draft})
            continue
        key = (spec.kind, " ".join(spec.instruction.lower().split()))
        if key in seen:
            slots.append({"status": "rejected", "reason": "the same instruction twice", "reply": draft})
            continue
        seen.add(key)
        specs.append(spec)
        slots.append(None)
    if specs:
        env = HouseholdEnv("Custom", scene=scene, tasks=specs, width=32, height=32, distance_info=False,
                           task_options={"order": "sequential"})
        env.reset(seed=0)
    ctx = env.episode.require() if env is not None else None
    index = 0
    records: list[dict[str, Any]] = []
    for slot in slots:
        if slot is not None:
            records.append(slot)
            continue
        spec = specs[index]
        record: dict[str, Any] = {"kind": spec.kind, "instruction": spec.instruction, "target": spec.target,
                                  "receptacle": spec.receptacle, "code": spec.code}
        problem = _static_problem(spec, ctx)
        if problem is None:
            ok, actions, why = _run(env, index, "code", spec.code)
            if not ok:
                problem = f"its code fails: {why}"
            else:
                record["actions"] = actions
                ok, expert_actions, why = _run(env, index, "expert", spec.code)
                if not ok:
                    problem = f"the expert fails: {why}"
                record["expert_actions"] = expert_actions
        index += 1
        if problem is None:
            records.append({"status": "kept", **record})
        else:
            records.append({"status": "rejected", "reason": problem, **record})
    if env is not None:
        env.close()
    outcome.records = records
    return outcome


def generate_tasks(args: Any) -> int:
    """``legent-gym tasks generate`` (``args`` from the CLI); problems a user can cause raise
    :class:`~legent_gym.errors.UserError` with one line."""
    if not 1 <= args.n <= MAX_TASKS:
        raise UserError(f"--n must be between 1 and {MAX_TASKS}, got {args.n}")
    if not args.model:
        raise UserError("tasks generate needs --model (and --llm-base-url or $OPENAI_BASE_URL)")
    scene = load_scene(args.scene)
    started = time.perf_counter()
    # The object table is read in the built house (names, centres where they rest).
    probe = HouseholdEnv("Custom", scene=scene, tasks=[TaskSpec(kind="come", instruction="-", code="goto_user()")],
                         width=16, height=16, distance_info=False)
    probe.reset(seed=0)
    ctx = probe.episode.require()
    table = object_table(ctx)
    user = None if scene.user is None else tuple(scene.user.position)
    messages = task_messages(table, tuple(scene.agent.position), user, args.n)  # type: ignore[arg-type]
    probe.close()
    try:
        client = ChatClient(args.llm_base_url, model=args.model, timeout=args.timeout, max_retries=args.retries,
                            backoff=1.0, max_backoff=10.0)
        reply, _ = client.complete_model(messages, TaskReply, max_tokens=8192)
    except (LLMError, ValueError) as err:
        raise UserError(str(err)) from None
    drafts = reply.tasks[:args.n]
    outcome = check_tasks(scene, drafts, header={"prompt_version": TASK_PROMPT_VERSION, "model": args.model})
    for record in outcome.rejected:
        print(f"rejected: {record.get('instruction', record.get('reply'))!s:.80}: {record['reason']}")
    if len(reply.tasks) > args.n:
        print(f"note: the reply held {len(reply.tasks)} tasks; the first {args.n} were checked")
    atomic_write_text(Path(args.out), outcome.text())
    print(f"wrote {args.out} ({len(outcome.kept)} kept, {len(outcome.rejected)} rejected of {len(drafts)}; "
          f"{time.perf_counter() - started:.1f} s)")
    return 0

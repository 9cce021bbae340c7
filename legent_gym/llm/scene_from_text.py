"""A house from text: ``legent-gym generate --plan FILE`` or ``--prompt TEXT``.

:func:`plan_from_prompt` sends :data:`~legent_gym.llm.prompts.SCENE_PLAN_PROMPT` through
:class:`~legent_gym.llm.client.ChatClient` (JSON mode, the reply validated as a
:class:`~legent_gym.world.generation.plan.ScenePlan`, an invalid one sent back once with
the error); :func:`generate_scene` solves the plan and writes the plan beside the scene,
the scene and the map (each atomically, only after the house is built).
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from pydantic import ValidationError

from legent_gym.errors import UserError
from legent_gym.llm.client import ChatClient, LLMError, describe_error
from legent_gym.llm.prompts import scene_plan_messages
from legent_gym.utils.atomic import atomic_write_text
from legent_gym.world.generation.plan import ScenePlan, load_plan, solve_plan
from legent_gym.world.scene import save_scene
from legent_gym.world.topdown_map import save_topdown_map


def plan_from_prompt(client: Any, prompt: str) -> tuple[Any, str]:
    """The plan a chat model writes for ``prompt`` and its raw reply (see the module docstring)."""
    return client.complete_model(scene_plan_messages(prompt), ScenePlan, max_tokens=4096)


def plan_path_for(out: str | Path) -> Path:
    """Where the plan of a scene is saved: ``house.json`` -> ``house.plan.json``."""
    out = Path(out)
    return out.with_name(out.name.removesuffix(".json") + ".plan.json")


def generate_scene(args: Any) -> int:
    """``legent-gym generate --plan FILE`` or ``--prompt TEXT`` (``args`` from the CLI);
    problems a user can cause raise :class:`~legent_gym.errors.UserError` with one line."""
    if args.plan and args.prompt:
        raise UserError("give --plan FILE or --prompt TEXT, not both")
    if args.out is None:
        raise UserError("give --out FILE.json")
    if args.count != 1 or args.out_dir is not None:
        raise UserError("--plan and --prompt make one house: no --count or --out-dir")
    if args.plan:
        try:
            data = json.loads(Path(args.plan).read_text(encoding="utf-8"))
        except OSError as err:
            raise UserError(f"{args.plan}: {err.strerror or err}") from None
        except (json.JSONDecodeError, UnicodeDecodeError) as err:
            raise UserError(f"{args.plan}: not JSON: {err}") from None
        try:
            plan = load_plan(data)
        except ValidationError as err:
            raise UserError(f"{args.plan}: not a valid plan: {describe_error(err)}") from None
    else:
        if not args.prompt.strip():
            raise UserError("--prompt is empty")
        if not args.model:
            raise UserError("--prompt needs --model (and --llm-base-url or $OPENAI_BASE_URL)")
        try:
            client = ChatClient(args.llm_base_url, model=args.model, timeout=args.timeout, max_retries=args.retries,
                                backoff=1.0, max_backoff=10.0)
            plan, _ = plan_from_prompt(client, args.prompt)
        except (LLMError, ValueError) as err:
            raise UserError(str(err)) from None
    solved = solve_plan(plan, args.seed)
    for line in solved.report.lines():
        print(line)
    if args.prompt:
        plan_file = plan_path_for(args.out)
        atomic_write_text(plan_file, json.dumps(plan.model_dump(mode="json"), indent=1) + "\n")
        print(f"wrote {plan_file} (the plan; rebuild with --plan {plan_file} --seed {args.seed})")
    save_scene(solved.scene, args.out)
    scene = solved.scene
    print(f"wrote {args.out} ({len(scene.rooms)} rooms, {len(scene.objects)} objects; solved in "
          f"{solved.report.seconds * 1000:.0f} ms; {len(solved.report.unmet)} unmet)")
    if args.map:
        save_topdown_map(scene, args.map)
        print(f"wrote {args.map}")
    return 0

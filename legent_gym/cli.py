"""The ``legent-gym`` command line.

    legent-gym validate SCENE.json
    legent-gym render SCENE.json --view topdown|agent|user --out FILE.png [--size N] [--profile fast|pretty]
    legent-gym asset list
    legent-gym asset preview PATH.glb|ASSET_ID --out FILE.png [--size N] [--variant K]
    legent-gym asset annotate PATH.glb [--llm-base-url URL --model M] [--out asset.json] [--cache-dir DIR]
    legent-gym generate --preset TwoRoom --seed 3 --out house.json [--map house.png]
    legent-gym generate --preset TwoRoom --seed 0 --count 100 --out-dir houses/
    legent-gym generate --plan plan.json --seed 0 --out house.json [--map house.png] [--asset lamp.asset.json]
    legent-gym generate --prompt "a flat with a kitchen" --llm-base-url URL --model M [--timeout S] [--retries N] --out house.json
    legent-gym tasks generate SCENE.json --n 20 --llm-base-url URL --model M [--timeout S] [--retries N] --out tasks.jsonl [--asset A.asset.json]
    legent-gym collect ENV_ID --episodes N --out DIR [--format minari,legent,video] [--workers K] [--seed S]
        [--backend process|ray] [--ray-address auto|HOST:PORT]
    legent-gym play ENV_ID [--as user|agent] [--partner expert|random|llm] [--port P] [--size WxH] [--record DIR]

Errors a user can cause (a bad file, a bad argument) print one line on stderr, naming the
file and the problem, and exit 2; ``--debug`` (before or after the command) shows the
traceback instead.
"""

from __future__ import annotations

import argparse
import json
import sys
import warnings
from pathlib import Path

import cv2
from tqdm import tqdm

from legent_gym.data.collect import CollectConfig, CollectError, collect, describe
from legent_gym.errors import UserError
from legent_gym.llm.annotation import annotate_command, register_annotation_files
from legent_gym.llm.scene_from_text import generate_scene
from legent_gym.llm.task_generation import generate_tasks
from legent_gym.play.command import add_arguments as add_play_arguments
from legent_gym.play.command import run as run_play
from legent_gym.utils import gl_backend
from legent_gym.utils.atomic import atomic_write_bytes
from legent_gym.world.assets import registry
from legent_gym.world.assets.gltf import AssetImportError, load_gltf
from legent_gym.world.builder import SceneBuildError, build_world
from legent_gym.world.generation import GenerationError, generate_house
from legent_gym.world.preview import render_asset_preview
from legent_gym.world.render import Renderer
from legent_gym.world.scene import ImportedAsset, SceneError, load_scene, save_scene
from legent_gym.world.topdown_map import save_topdown_map

#: The largest image side ``--size`` may ask for (MuJoCo's offscreen buffer is that big).
MAX_IMAGE_SIZE = 8192


def _check_size(size: int) -> None:
    if not 1 <= size <= MAX_IMAGE_SIZE:
        raise UserError(f"--size must be between 1 and {MAX_IMAGE_SIZE} pixels, got {size}")


def _check_output(path: str) -> None:
    """Fail before the work if ``--out`` cannot be a file."""
    target = Path(path)
    if target.is_dir():
        raise UserError(f"{path}: --out is a directory, not a file")
    for parent in target.parents:
        if parent.exists():
            if not parent.is_dir():
                raise UserError(f"{path}: {parent} is a file, not a directory")
            break


def _write_png(path: str, image) -> None:
    ok, data = cv2.imencode(".png", image[..., ::-1])
    if not ok:
        raise UserError(f"could not encode PNG for {path}")
    atomic_write_bytes(path, data.tobytes())
    print(f"wrote {path}")


def cmd_validate(args) -> int:
    scene = load_scene(args.scene)
    print(f"{args.scene}: valid ({len(scene.rooms)} rooms, {len(scene.objects)} objects, {len(scene.doors)} doors)")
    return 0


def cmd_gl_info(args) -> int:
    for key, value in gl_backend.describe().items():
        print(f"{key}: {value}")
    return 0


def cmd_render(args) -> int:
    _check_size(args.size)
    _check_output(args.out)
    scene = load_scene(args.scene)
    if args.view == "user" and scene.user is None:
        raise UserError(f"{args.scene} has no user spawn: cannot render the user's view")
    world = build_world(scene)
    renderer = Renderer(world, args.size, args.size, args.profile)
    _write_png(args.out, renderer.rgb(args.view))
    return 0


def cmd_asset_list(args) -> int:
    for asset_id in registry.asset_ids():
        model = registry.describe(asset_id)
        size = " x ".join(f"{v:.2f}" for v in model.size)
        kind = "pickupable" if model.pickupable else model.placement
        print(f"{asset_id:16s} {kind:10s} {size} m  names: {', '.join(model.names)}")
    return 0


def cmd_asset_preview(args) -> int:
    _check_size(args.size)
    _check_output(args.out)
    if args.variant < 0:
        raise UserError(f"--variant must be >= 0, got {args.variant}")
    source = Path(args.asset)
    if source.suffix.lower() in (".glb", ".gltf"):
        load_gltf(source, up_axis=args.up_axis)  # fail early, with the importer's message
        imported = ImportedAsset(id="preview_asset", source=str(source.resolve()), up_axis=args.up_axis)
        image = render_asset_preview("preview_asset", size=args.size, profile=args.profile, imported=imported)
    else:
        if not registry.has(args.asset):
            raise UserError(f"{args.asset!r} is neither a .glb/.gltf file nor a built-in asset id "
                            "(see `legent-gym asset list`)")
        image = render_asset_preview(args.asset, args.variant, size=args.size, profile=args.profile)
    _write_png(args.out, image)
    return 0


def cmd_asset_annotate(args) -> int:
    if args.out:
        _check_output(args.out)
    return annotate_command(args)


def cmd_generate(args) -> int:
    if not 0 <= args.seed <= MAX_SEED:
        raise UserError(f"--seed must be between 0 and {MAX_SEED}, got {args.seed}")
    if args.asset:
        register_annotation_files(args.asset)
    if args.plan is not None or args.prompt is not None:
        for path in (args.out, args.map):
            if path:
                _check_output(path)
        return generate_scene(args)
    if args.count < 1:
        raise UserError(f"--count must be >= 1, got {args.count}")
    if args.seed + args.count - 1 > MAX_SEED:
        raise UserError(f"--seed + --count - 1 must be at most {MAX_SEED}")
    if args.count == 1 and args.out_dir is None:
        if args.out is None:
            raise UserError("give --out FILE.json (or --count N --out-dir DIR for a batch)")
        _check_output(args.out)
        if args.map:
            _check_output(args.map)
        scene = generate_house(args.seed, args.preset)
        save_scene(scene, args.out)
        print(f"wrote {args.out} ({len(scene.rooms)} rooms, {len(scene.objects)} objects)")
        if args.map:
            save_topdown_map(scene, args.map)
            print(f"wrote {args.map}")
        return 0
    if args.out_dir is None:
        raise UserError("a batch (--count > 1) needs --out-dir DIR")
    out_dir = Path(args.out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    for seed in tqdm(range(args.seed, args.seed + args.count), desc="houses", unit="house"):
        target = out_dir / f"{args.preset}_{seed:06d}.json"
        if target.exists():  # resumable: a finished house is written atomically, so it is whole
            continue
        save_scene(generate_house(seed, args.preset), target)
    print(f"{args.count} houses in {out_dir}")
    return 0


def cmd_tasks_generate(args) -> int:
    _check_output(args.out)
    register_annotation_files(args.asset)
    return generate_tasks(args)


#: The largest house seed (seeds are stored in the scene and seed numpy's generators).
MAX_SEED = 2**63 - 1


def parse_env_kwargs(text: str | None) -> dict:
    """``--env-kwargs``: further ``gym.make`` arguments as a JSON object (``{}`` for none),
    or a :class:`UserError` that says what is wrong with the text."""
    if not text:
        return {}
    try:
        env_kwargs = json.loads(text)
    except json.JSONDecodeError as err:
        raise UserError(f"--env-kwargs is not valid JSON: {err}") from None
    if not isinstance(env_kwargs, dict):
        raise UserError(f"--env-kwargs must be a JSON object, got {text!r}")
    return env_kwargs


def cmd_collect(args) -> int:
    env_kwargs = parse_env_kwargs(args.env_kwargs)
    for key, value in (("width", args.width), ("height", args.height), ("action_type", args.action_type),
                       ("max_episode_steps", args.max_steps), ("frames_per_step", args.frames_per_step)):
        if value is not None:
            env_kwargs[key] = value
    formats = tuple(f.strip() for f in args.format.split(",") if f.strip())
    config = CollectConfig(args.env_id, args.episodes, args.out, formats=formats, workers=args.workers,
                           seed=args.seed, env_kwargs=env_kwargs, policy=args.policy, window=args.window,
                           dataset_id=args.dataset_id, max_attempts=args.max_attempts, perturb=args.perturb,
                           find_strategy=args.find_strategy, backend=args.backend, ray_address=args.ray_address)
    print(describe(collect(config, show_progress=not args.quiet)))
    return 0


def cmd_play(args) -> int:
    return run_play(args)


def add_llm_arguments(parser: argparse.ArgumentParser) -> None:
    """The LLM flags every LLM command takes."""
    parser.add_argument("--llm-base-url", help="OpenAI-compatible endpoint (default: $OPENAI_BASE_URL)")
    parser.add_argument("--model", help="the chat model's name")
    parser.add_argument("--timeout", type=float, default=120.0, help="seconds per LLM request (default 120)")
    parser.add_argument("--retries", type=int, default=2, help="retries of a failed LLM request (default 2)")


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="legent-gym", description=__doc__.split("\n\n")[0])
    parser.add_argument("--debug", action="store_true", help="show the traceback of an error")
    # --debug after the command too; SUPPRESS keeps a subcommand from resetting the flag.
    common = argparse.ArgumentParser(add_help=False)
    common.add_argument("--debug", action="store_true", default=argparse.SUPPRESS,
                        help="show the traceback of an error")
    sub = parser.add_subparsers(dest="command", required=True)

    p = sub.add_parser("validate", parents=[common], help="check a scene file")
    p.add_argument("scene")
    p.set_defaults(func=cmd_validate)

    p = sub.add_parser("gl-info", parents=[common], help="what renders here: the OpenGL backend, the EGL device "
                       "and the vendor and renderer of a context (an NVIDIA GPU or Mesa's llvmpipe on the CPU)")
    p.set_defaults(func=cmd_gl_info)

    p = sub.add_parser("render", parents=[common], help="render a scene to PNG")
    p.add_argument("scene")
    p.add_argument("--view", choices=["topdown", "agent", "user"], default="topdown")
    p.add_argument("--out", required=True)
    p.add_argument("--size", type=int, default=512)
    p.add_argument("--profile", choices=["fast", "pretty"], default="pretty")
    p.set_defaults(func=cmd_render)

    asset = sub.add_parser("asset", parents=[common], help="list, preview or annotate assets").add_subparsers(dest="asset_command", required=True)
    p = asset.add_parser("list", help="list registered assets", parents=[common])
    p.set_defaults(func=cmd_asset_list)
    p = asset.add_parser("preview", parents=[common], help="render one asset (a built-in id or a .glb/.gltf file)")
    p.add_argument("asset")
    p.add_argument("--out", required=True)
    p.add_argument("--size", type=int, default=384)
    p.add_argument("--variant", type=int, default=0)
    p.add_argument("--up-axis", choices=["y", "z"], default="y")
    p.add_argument("--profile", choices=["fast", "pretty"], default="pretty")
    p.set_defaults(func=cmd_asset_preview)

    p = asset.add_parser("annotate", parents=[common], help="annotate a .glb/.gltf file: geometry computed, "
                                                           "semantics from a VLM (see docs/llm.md)")
    p.add_argument("asset")
    p.add_argument("--out", help="annotation JSON to write (default: beside the file, NAME.asset.json)")
    p.add_argument("--cache-dir", help="annotations cached by file hash (default: ~/.cache/legent-gym/annotations)")
    add_llm_arguments(p)
    p.set_defaults(func=cmd_asset_annotate)

    p = sub.add_parser("generate", parents=[common], help="generate houses procedurally")
    p.add_argument("--preset", default="TwoRoom")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--out", help="scene JSON to write (single house)")
    p.add_argument("--map", help="also write the top-down map PNG (single house)")
    p.add_argument("--count", type=int, default=1, help="number of houses (seeds seed..seed+count-1)")
    p.add_argument("--out-dir", help="directory for a batch")
    p.add_argument("--plan", help="build the house of a scene plan (JSON; see docs/llm.md) instead of a preset")
    p.add_argument("--prompt", help="ask an LLM for a plan of this description, build it, save the plan beside --out")
    p.add_argument("--asset", action="append", help="register this annotated asset first (legent-gym asset "
                                                    "annotate; repeatable): a plan may then name its category")
    add_llm_arguments(p)
    p.set_defaults(func=cmd_generate)

    tasks = sub.add_parser("tasks", parents=[common], help="tasks for a scene").add_subparsers(
        dest="tasks_command", required=True)
    p = tasks.add_parser("generate", parents=[common], help="ask an LLM for tasks in a scene; keep those the "
                                                            "experts complete (see docs/llm.md)")
    p.add_argument("scene")
    p.add_argument("--n", type=int, default=20, help="tasks to ask for (default 20)")
    p.add_argument("--asset", action="append", help="register this annotated asset first (a scene that uses it)")
    p.add_argument("--out", required=True, help="tasks file to write (JSON lines)")
    add_llm_arguments(p)
    p.set_defaults(func=cmd_tasks_generate)

    p = sub.add_parser("collect", parents=[common], help="record successful trajectories (of the expert by default)",
                       description="Record successful episodes of ENV_ID as Minari, LEGENT and video "
                                   "datasets; resumes what is in --out. See docs/datasets.md.")
    p.add_argument("env_id", help="e.g. Legent/ComeHere-OneRoom-v0")
    p.add_argument("--episodes", type=int, required=True, help="successful episodes wanted in all")
    p.add_argument("--out", required=True, help="output directory (resumed if it holds a collection)")
    p.add_argument("--format", default="minari,legent", help="comma-separated: minari, legent, video")
    p.add_argument("--workers", type=int, default=1, help="worker processes (with --backend ray: 2 K tasks in flight; a local Ray gets K CPUs)")
    p.add_argument("--backend", choices=["process", "ray"], default="process",
                   help="worker processes on this machine or Ray tasks (the scale extra); see docs/scale.md")
    p.add_argument("--ray-address", help="with --backend ray: 'auto' or HOST:PORT of a running Ray cluster "
                                         "(default: start a Ray on this machine)")
    p.add_argument("--seed", type=int, default=0, help="attempt k resets with seed S + k")
    p.add_argument("--policy", default="expert", help="'expert' or module:function, a callable (obs, info) -> action")
    p.add_argument("--width", type=int)
    p.add_argument("--height", type=int)
    p.add_argument("--action-type", choices=["text", "continuous"])
    p.add_argument("--max-steps", type=int, help="episode cap (the env's max_episode_steps)")
    p.add_argument("--frames-per-step", type=int,
                   help="with --format video: frames a step is shown in (people walk and reach between observations)")
    p.add_argument("--env-kwargs", help="JSON object of further gym.make arguments")
    p.add_argument("--window", type=int, default=6, help="images per interleaved.jsonl sample")
    p.add_argument("--dataset-id", help="Minari dataset id (default legent/<Task>-<Layout>/expert-v0)")
    p.add_argument("--max-attempts", type=int, help="give up after this many attempts (default 10 N + 100)")
    p.add_argument("--perturb", type=float, default=0.0,
                   help="recovery data: per step, the probability of executing a random move/turn in place "
                        "of the policy's action; the step is labelled with the expert's action (LEGENT format)")
    p.add_argument("--find-strategy", default="direct",
                   help="how the expert's find(a) looks for an object out of view: 'direct' (LEGENT's: straight "
                        "to it) or 'scan' (turn right in place until it is in view, then as direct)")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.set_defaults(func=cmd_collect)

    p = sub.add_parser("play", parents=[common], help="play ENV_ID in the browser, as the user or the agent",
                       description="Serve a page where a person plays ENV_ID as the user (a partner policy "
                                   "drives the agent) or as the agent. See docs/play.md.")
    add_play_arguments(p)
    p.set_defaults(func=cmd_play)
    return parser


def _input_of(args) -> str | None:
    """The file (or id) a command reads, which an error message names."""
    for name in ("scene", "asset", "env_id"):
        value = getattr(args, name, None)
        if value:
            return str(value)
    value = getattr(args, "out", None) or getattr(args, "out_dir", None)
    return None if value is None else str(value)


def _one_line(text: str) -> str:
    return "; ".join(line.strip() for line in text.splitlines() if line.strip()) or "(no message)"


#: The error types that say what is wrong with the user's input, in their own words.
USER_ERRORS: tuple[type[BaseException], ...] = (UserError, SceneError, AssetImportError, SceneBuildError,
                                                GenerationError, CollectError)


def error_message(err: BaseException, args) -> str:
    """One line that names the file and says what is wrong with it."""
    where = _input_of(args)
    if isinstance(err, SceneError):
        text = _one_line(err.summary())
        return text if err.source or where is None else f"{where}: {text}"
    if isinstance(err, OSError) and (err.filename2 or err.filename) is not None:
        # os.replace(tmp, target) fails naming both: the target is the user's path.
        return _one_line(f"{err.filename2 or err.filename}: {err.strerror or err}")
    if isinstance(err, SceneBuildError):
        text = str(err)
    elif isinstance(err, USER_ERRORS):
        return _one_line(str(err))
    else:  # not foreseen: still one line, with the way to the traceback
        text = f"unexpected {type(err).__name__}: {err} (run with --debug for the traceback)"
    text = _one_line(text)
    return text if where is None or where in text else f"{where}: {text}"


def _show_warning(message, category, filename, lineno, file=None, line=None) -> None:
    print(f"legent-gym: warning: {_one_line(str(message))}", file=sys.stderr)


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    debug = getattr(args, "debug", False)
    with warnings.catch_warnings():
        if not debug:
            warnings.showwarning = _show_warning
        try:
            return args.func(args)
        except Exception as err:  # errors in the input, in its words; anything else says so (see error_message)
            if debug:
                raise
            print(f"legent-gym: error: {error_message(err, args)}", file=sys.stderr)
            return 2


if __name__ == "__main__":
    sys.exit(main())

"""The ``legent-gym`` command line.

    legent-gym validate SCENE.json
    legent-gym render SCENE.json --view topdown|agent|user --out FILE.png [--size N] [--profile fast|pretty]
    legent-gym asset list
    legent-gym asset preview PATH.glb|ASSET_ID --out FILE.png [--size N] [--variant K]
    legent-gym generate --preset TwoRoom --seed 3 --out house.json [--map house.png]
    legent-gym generate --preset TwoRoom --seed 0 --count 100 --out-dir houses/
    legent-gym collect ENV_ID --episodes N --out DIR [--format minari,legent,video] [--workers K] [--seed S]

Errors a user can cause (a bad file, a bad argument) print one clear message and exit 2.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from legent_gym import gl_backend  # noqa: F401


class UserError(Exception):
    """A problem with the user's input: printed without a traceback."""


def _write_png(path: str, image) -> None:
    import cv2

    from legent_gym.atomic import atomic_write_bytes

    ok, data = cv2.imencode(".png", image[..., ::-1])
    if not ok:
        raise UserError(f"could not encode PNG for {path}")
    atomic_write_bytes(path, data.tobytes())
    print(f"wrote {path}")


def cmd_validate(args) -> int:
    from legent_gym.world.scene import load_scene

    scene = load_scene(args.scene)
    print(f"{args.scene}: valid ({len(scene.rooms)} rooms, {len(scene.objects)} objects, {len(scene.doors)} doors)")
    return 0


def cmd_render(args) -> int:
    from legent_gym.world.builder import build_world
    from legent_gym.world.render import Renderer
    from legent_gym.world.scene import load_scene

    scene = load_scene(args.scene)
    if args.view == "user" and scene.user is None:
        raise UserError(f"{args.scene} has no user spawn: cannot render the user's view")
    world = build_world(scene)
    renderer = Renderer(world, args.size, args.size, args.profile)
    _write_png(args.out, renderer.rgb(args.view))
    return 0


def cmd_asset_list(args) -> int:
    from legent_gym.world.assets import registry

    for asset_id in registry.asset_ids():
        model = registry.describe(asset_id)
        size = " x ".join(f"{v:.2f}" for v in model.size)
        kind = "pickupable" if model.pickupable else model.placement
        print(f"{asset_id:16s} {kind:10s} {size} m  names: {', '.join(model.names)}")
    return 0


def cmd_asset_preview(args) -> int:
    from legent_gym.world.preview import render_asset_preview

    source = Path(args.asset)
    if source.suffix.lower() in (".glb", ".gltf"):
        from legent_gym.world.assets.gltf import load_gltf
        from legent_gym.world.scene import ImportedAsset

        load_gltf(source, up_axis=args.up_axis)  # fail early, with the importer's message
        imported = ImportedAsset(id="preview_asset", source=str(source.resolve()), up_axis=args.up_axis)
        image = render_asset_preview("preview_asset", size=args.size, profile=args.profile, imported=imported)
    else:
        from legent_gym.world.assets import registry

        if not registry.has(args.asset):
            raise UserError(f"{args.asset!r} is neither a .glb/.gltf file nor a built-in asset id "
                            "(see `legent-gym asset list`)")
        image = render_asset_preview(args.asset, args.variant, size=args.size, profile=args.profile)
    _write_png(args.out, image)
    return 0


def cmd_generate(args) -> int:
    from legent_gym.world.generation import generate_house
    from legent_gym.world.scene import save_scene

    if args.count == 1 and args.out_dir is None:
        if args.out is None:
            raise UserError("give --out FILE.json (or --count N --out-dir DIR for a batch)")
        scene = generate_house(args.seed, args.preset)
        save_scene(scene, args.out)
        print(f"wrote {args.out} ({len(scene.rooms)} rooms, {len(scene.objects)} objects)")
        if args.map:
            from legent_gym.world.topdown_map import save_topdown_map

            save_topdown_map(scene, args.map)
            print(f"wrote {args.map}")
        return 0
    if args.out_dir is None:
        raise UserError("a batch (--count > 1) needs --out-dir DIR")
    from tqdm import tqdm

    out_dir = Path(args.out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    for seed in tqdm(range(args.seed, args.seed + args.count), desc="houses", unit="house"):
        target = out_dir / f"{args.preset}_{seed:06d}.json"
        if target.exists():  # resumable: a finished house is written atomically, so it is whole
            continue
        save_scene(generate_house(seed, args.preset), target)
    print(f"{args.count} houses in {out_dir}")
    return 0


def parse_env_kwargs(text: str | None) -> dict:
    """``--env-kwargs``: further ``gym.make`` arguments as a JSON object (``{}`` for none),
    or a :class:`UserError` that says what is wrong with the text."""
    import json

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
    from legent_gym.data.collect import CollectConfig, collect, describe

    env_kwargs = parse_env_kwargs(args.env_kwargs)
    for key, value in (("width", args.width), ("height", args.height), ("action_type", args.action_type),
                       ("max_episode_steps", args.max_steps)):
        if value is not None:
            env_kwargs[key] = value
    formats = tuple(f.strip() for f in args.format.split(",") if f.strip())
    config = CollectConfig(args.env_id, args.episodes, args.out, formats=formats, workers=args.workers,
                           seed=args.seed, env_kwargs=env_kwargs, policy=args.policy, window=args.window,
                           dataset_id=args.dataset_id, max_attempts=args.max_attempts, perturb=args.perturb,
                           find_strategy=args.find_strategy)
    print(describe(collect(config, show_progress=not args.quiet)))
    return 0


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="legent-gym", description=__doc__.split("\n\n")[0])
    sub = parser.add_subparsers(dest="command", required=True)

    p = sub.add_parser("validate", help="check a scene file")
    p.add_argument("scene")
    p.set_defaults(func=cmd_validate)

    p = sub.add_parser("render", help="render a scene to PNG")
    p.add_argument("scene")
    p.add_argument("--view", choices=["topdown", "agent", "user"], default="topdown")
    p.add_argument("--out", required=True)
    p.add_argument("--size", type=int, default=512)
    p.add_argument("--profile", choices=["fast", "pretty"], default="pretty")
    p.set_defaults(func=cmd_render)

    asset = sub.add_parser("asset", help="list or preview assets").add_subparsers(dest="asset_command", required=True)
    p = asset.add_parser("list", help="list registered assets")
    p.set_defaults(func=cmd_asset_list)
    p = asset.add_parser("preview", help="render one asset (a built-in id or a .glb/.gltf file)")
    p.add_argument("asset")
    p.add_argument("--out", required=True)
    p.add_argument("--size", type=int, default=384)
    p.add_argument("--variant", type=int, default=0)
    p.add_argument("--up-axis", choices=["y", "z"], default="y")
    p.add_argument("--profile", choices=["fast", "pretty"], default="pretty")
    p.set_defaults(func=cmd_asset_preview)

    p = sub.add_parser("generate", help="generate houses procedurally")
    p.add_argument("--preset", default="TwoRoom")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--out", help="scene JSON to write (single house)")
    p.add_argument("--map", help="also write the top-down map PNG (single house)")
    p.add_argument("--count", type=int, default=1, help="number of houses (seeds seed..seed+count-1)")
    p.add_argument("--out-dir", help="directory for a batch")
    p.set_defaults(func=cmd_generate)

    p = sub.add_parser("collect", help="record successful trajectories (of the expert by default)",
                       description="Record successful episodes of ENV_ID as Minari, LEGENT and video "
                                   "datasets; resumes what is in --out. See docs/datasets.md.")
    p.add_argument("env_id", help="e.g. Legent/ComeHere-OneRoom-v0")
    p.add_argument("--episodes", type=int, required=True, help="successful episodes wanted in all")
    p.add_argument("--out", required=True, help="output directory (resumed if it holds a collection)")
    p.add_argument("--format", default="minari,legent", help="comma-separated: minari, legent, video")
    p.add_argument("--workers", type=int, default=1, help="worker processes")
    p.add_argument("--seed", type=int, default=0, help="attempt k resets with seed S + k")
    p.add_argument("--policy", default="expert", help="'expert' or module:function, a callable (obs, info) -> action")
    p.add_argument("--width", type=int)
    p.add_argument("--height", type=int)
    p.add_argument("--action-type", choices=["text", "continuous"])
    p.add_argument("--max-steps", type=int, help="episode cap (the env's max_episode_steps)")
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
    return parser


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    from legent_gym.world.scene import SceneError

    user_errors: tuple[type[BaseException], ...] = (UserError, SceneError, FileNotFoundError)
    try:
        from legent_gym.world.assets.gltf import AssetImportError

        user_errors += (AssetImportError,)
    except ImportError:
        pass
    try:
        from legent_gym.world.generation import GenerationError

        user_errors += (GenerationError,)
    except ImportError:
        pass
    try:
        from legent_gym.data.collect import CollectError

        user_errors += (CollectError,)
    except ImportError:
        pass
    try:
        return args.func(args)
    except user_errors as err:
        print(f"legent-gym: error: {err}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())

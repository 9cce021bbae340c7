"""Measure the docs' figures again and rewrite their tables (see :mod:`baselines.figures`).

    python -m baselines.refresh                        # the cheap figures (= --scale small)
    python -m baselines.refresh --scale full           # every figure that one command measures
    python -m baselines.refresh --list-outdated        # the figures whose code changed since they were measured
    python -m baselines.refresh --scale full --outdated   # measure only those (a full refresh in parts)
    python -m baselines.refresh --only random-policy   # these figures
    python -m baselines.refresh --tables               # only rewrite the tables from the data files
    python -m baselines.refresh --check                # exit 1 if a table differs from its data file
    python -m baselines.refresh --show ablation-shift  # print a figure's table (those shown in no doc too)
    python -m baselines.refresh --adopt table-full --commit d54059b   # a kept run's results.json as its data
    python -m baselines.refresh --adopt ppo-curve --commit 03c3827    # a table typed in a doc, from that commit

Each figure measured is written to ``docs/data/figures/<name>.json`` with its commit,
command line, seeds, machine and wall time; then every figure block of the docs is rewritten
from the data files, and the figures that moved by more than their standard error are
printed (old -> new). Tables adopted from the docs' history are never measured again
here. Figures made from other data files (``<table>-run`` from a table run's kept
``results.json``, the side-by-side tables, the paper beside us) measure nothing and are
cheap: every run that measures something remakes them after it. Numbers quoted in the prose
(``<!-- value: FIGURE | ROW | COLUMN -->``) are rewritten and checked with the tables.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from pathlib import Path

if __package__ in (None, ""):  # run as a script: make `baselines` importable
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from baselines.figure_data import (  # noqa: E402
    MEASURED_CODE,
    Figure,
    FigureError,
    data_path,
    load,
    measure,
    moved,
    provenance,
    refresh_docs,
    render,
    stale_blocks,
    write,
)
from baselines.figures import FIGURES, adopt, figure, outdated  # noqa: E402


def derived_from_data(chosen: list[Figure]) -> list[Figure]:
    """The figures made from data files (nothing measured) that are not in ``chosen``: made
    again after it, so that a table run's details and the tables beside it follow its data."""
    return [f for f in FIGURES.values() if f.produce is not None and f.cheap and f not in chosen
            and data_path(f.name).is_file() and "made_from" in load(f.name)]


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--scale", choices=["small", "full"], default="small",
                        help="small: the cheap (deterministic, quick) figures; full: every figure that one command "
                        "measures (not the adopted typed tables)")
    parser.add_argument("--only", default="", help=f"comma-separated figures of: {', '.join(FIGURES)}")
    parser.add_argument("--outdated", action="store_true", help="of the figures chosen (--scale or --only), "
                        f"measure only those whose code ({', '.join(MEASURED_CODE)}) changed after the commit "
                        "they were measured at")
    parser.add_argument("--list-outdated", action="store_true", help="measure nothing; list the figures that "
                        "--scale full --outdated would measure, with the files changed since each was measured")
    parser.add_argument("--tables", action="store_true", help="measure nothing; rewrite the tables from the data")
    parser.add_argument("--check", action="store_true", help="measure nothing; exit 1 if a table is not its data")
    parser.add_argument("--show", metavar="NAME", help="measure nothing; print the figure's table from its data "
                        "file (also the figures kept as data only, shown in no doc)")
    parser.add_argument("--adopt", metavar="NAME", help="measure nothing; take the results.json that a table run "
                        "kept in docs/data/ as the figure's data, with --commit (the commit it ran at); for a "
                        "table typed in a doc and kept in no file, its text in the doc at --commit")
    parser.add_argument("--commit", help="with --adopt: the commit the run was made at")
    parser.add_argument("--commit-note", default="", help="with --adopt: how that commit is known")
    args = parser.parse_args(argv)
    try:
        if args.show:
            print(render(load(figure(args.show).name)), end="")
            return 0
        if args.adopt:
            if not args.commit:
                raise FigureError("--adopt needs --commit (the commit the run was made at)")
            print(f"wrote {write(adopt(args.adopt, args.commit, args.commit_note))}")
            args.tables = True
        elif args.list_outdated:
            found = outdated()
            for name, commit, changed in found:
                print(f"{name} (measured at {commit[:7]}): {len(changed)} file(s) changed since: "
                      + ", ".join(changed))
            if not found:
                print("every figure that one command measures was measured on the current code")
            return 0
        elif args.check:
            stale = stale_blocks()
            for line in stale:
                print(f"refresh: {line} differs from its data file", file=sys.stderr)
            return 1 if stale else 0
        if not args.tables:
            names = [n.strip() for n in args.only.split(",") if n.strip()]
            chosen = [figure(n) for n in names] if names else \
                [f for f in FIGURES.values() if f.produce is not None and (f.cheap or args.scale == "full")]
            if args.outdated:
                stale = {name for name, _, _ in outdated()}
                chosen = [f for f in chosen if f.name in stale]
            chosen += derived_from_data(chosen)
            changes: list[str] = []
            origin = provenance()  # before this run writes a data file
            for fig in chosen:
                print(f"measuring {fig.name} ...", file=sys.stderr, flush=True)
                old = load(fig.name) if data_path(fig.name).is_file() else None
                new = measure(fig, origin)
                write(new)
                print(f"  {fig.name}: {new['wall_seconds']:g} s", file=sys.stderr)
                if old is not None:
                    changes += moved(old, new)
            print("moved by more than their standard error:" if changes else "no figure moved by more than its "
                  "standard error")
            for line in changes:
                print(f"  {line}")
        for path in refresh_docs():
            print(f"rewrote {path.name}")
    except FigureError as err:
        print(f"refresh: error: {err}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

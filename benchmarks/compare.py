"""Before/after in the same run: a benchmark of another commit and of this tree, alternated.

    python benchmarks/compare.py --before REV [--rounds 3] -- step.py --ids Legent/ComeHere-TwoRoom-v0

Checks ``REV`` out in a temporary git worktree, then runs the benchmark script (a path under
``benchmarks/``, with its arguments) there and here in turn, ``--rounds`` times each, so
that other load on a shared machine weighs on both alike. Each run's last table row (or,
with ``--row TEXT``, the last line containing TEXT) is read (numbers after the first word
or cell); the output gives every round's rows and, per column, the
after/before ratio of each round and their median.
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def _last_row(output: str, row: str = "") -> list[float]:
    """The numbers of the last line of a benchmark's table (its first column is a name) that
    contains ``row``; Markdown table bars count as blanks."""
    for line in reversed(output.strip().splitlines()):
        if row not in line:
            continue
        if line.lstrip().startswith("|"):  # a Markdown row: its cells after the name
            values = [cell.strip() for cell in line.strip().strip("|").split("|")[1:]]
        else:  # a plain row: its words after the name
            values = line.split()[1:]
        numbers = []
        for field in (v for v in values if v):
            try:
                # "1,234" and ratios written "1.36x" read as numbers
                numbers.append(float(field.replace(",", "").removesuffix("x")))
            except ValueError:
                numbers = []
                break
        if numbers:
            return numbers
    raise RuntimeError(f"no table row in the benchmark's output:\n{output[-2000:]}")


def _run(tree: Path, script: list[str], row: str = "") -> tuple[str, list[float]]:
    env = {"PYTHONPATH": str(tree), "PATH": "/usr/bin:/bin"}
    done = subprocess.run([sys.executable, str(tree / "benchmarks" / script[0]), *script[1:]], cwd=tree,
                          env=env, capture_output=True, text=True)
    if done.returncode:
        raise RuntimeError(f"{script[0]} failed in {tree}:\n{done.stderr[-3000:]}")
    lines = [line for line in done.stdout.strip().splitlines() if line.strip() and row in line]
    if not lines:
        raise RuntimeError(f"no line with {row!r} in the output of {script[0]}")
    return lines[-1], _last_row(done.stdout, row)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--before", required=True, help="the commit to compare against")
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--row", default="", help="compare the last output line containing this text "
                        "(default: the last line), e.g. a throughput.py row name")
    parser.add_argument("script", nargs=argparse.REMAINDER, help="-- SCRIPT.py [ARGS...]")
    args = parser.parse_args(argv)
    script = args.script[1:] if args.script[:1] == ["--"] else args.script
    if not script:
        parser.error("give the benchmark after --, e.g. -- step.py --ids Legent/ComeHere-TwoRoom-v0")
    with tempfile.TemporaryDirectory(prefix="legent-before-") as tmp:
        before = Path(tmp) / "tree"
        subprocess.run(["git", "-C", str(ROOT), "worktree", "add", "--detach", str(before), args.before],
                       check=True, capture_output=True)
        try:
            ratios: list[list[float]] = []
            for round_ in range(args.rounds):
                line_b, b = _run(before, script, args.row)
                line_a, a = _run(ROOT, script, args.row)
                print(f"round {round_ + 1} before: {line_b}")
                print(f"round {round_ + 1} after:  {line_a}")
                ratios.append([x / y if y else float("nan") for x, y in zip(a, b)])
            print("after/before per column, by round:", [[round(r, 3) for r in row] for row in ratios])
            print("median after/before per column:   ",
                  [round(statistics.median(col), 3) for col in zip(*ratios)])
        finally:
            subprocess.run(["git", "-C", str(ROOT), "worktree", "remove", "--force", str(before)],
                           capture_output=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

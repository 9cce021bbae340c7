"""The machinery of figures as data (see :mod:`baselines.figures`, which defines the figures):
:class:`Table` and :class:`Figure`, a figure's data file (:func:`measure` with its
:func:`provenance`, :func:`write`, :func:`load`), its Markdown block and quoted values
(:func:`render`, :func:`rewrite`, :func:`stale_blocks`, :func:`refresh_docs`), what moved
between two measurements (:func:`moved`), the code changed since one
(:func:`code_changed_since`), and a table typed in a doc read back (:func:`adopt_typed`)."""

from __future__ import annotations

import datetime
import json
import math
import os
import platform
import re
import subprocess
import sys
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from legent_gym.utils.atomic import atomic_write_text

ROOT = Path(__file__).resolve().parents[1]
#: Where the figures' data files live.
FIGURE_DIR = ROOT / "docs" / "data" / "figures"
#: The Markdown files whose figure blocks :func:`refresh_docs` rewrites.
DOC_FILES = ("README.md", "docs/results.md", "docs/experts.md", "docs/performance.md", "docs/datasets.md",
             "docs/multiagent.md", "docs/scale.md", "docs/vlm.md")
FORMAT_VERSION = 1
BLOCK = re.compile(r"<!-- figure: (?P<name>[A-Za-z0-9_.-]+) -->\n(?P<body>.*?)<!-- /figure -->", re.S)
#: One number of a figure quoted in prose: ``<!-- value: FIGURE | ROW | COLUMN [| FORMAT] -->``
#: the number ``<!-- /value -->`` (ROW: the row's first cell; ``@`` with COLUMN ``commit`` or
#: ``wall_seconds``: where the figure comes from).
VALUE = re.compile(r"<!-- value: (?P<spec>[^<>]*?) -->(?P<text>[^<]*?)<!-- /value -->")


class FigureError(Exception):
    """A figure that does not exist, a data file that cannot be read, a block with no file."""


@dataclass(frozen=True)
class Table:
    """What a producer measures: column names, rows of cells, and for each numeric cell
    that is an estimate its standard error (None where a cell is not one)."""

    columns: list[str]
    rows: list[list[Any]]
    stderr: list[list[float | None]] | None = None
    #: Seeds or seed ranges the numbers come from, as the reader needs them.
    seeds: str = ""
    #: One sentence under the table (conditions the reader needs).
    note: str = ""
    #: A format spec per column for its numbers (default: the figure's ``number_format``).
    formats: list[str] | None = None
    #: For a table made from other data files, not measured: what it is made from.
    made_from: str = ""
    #: The wall time of the run that measured it, where that is not the producer's own (two
    #: figures read one run).
    wall_seconds: float | None = None


@dataclass(frozen=True)
class Figure:
    name: str
    #: The command a reader runs to measure it (``python -m baselines.refresh --only NAME``
    #: runs the same producer).
    command: str
    #: Measures it now; None for a table that no one command measures again (``typed``).
    produce: Callable[[], Table] | None
    #: Deterministic and quick: rerun by the default tests and by ``--scale small``.
    cheap: bool
    #: How a numeric cell is printed.
    number_format: str = ".3f"
    #: A reproduce_table.py run's folder under docs/data/ (its results.json), if it is one.
    folder: str | None = None
    #: A table typed in a doc before it was a figure, and kept in no file: (the doc, a line of
    #: the table) that finds it in the doc at the commit given to ``--adopt``.
    typed: tuple[str, str] | None = None


# -- provenance -----------------------------------------------------------------------------------
def git(*args: str) -> str:
    try:
        return subprocess.run(["git", *args], cwd=ROOT, capture_output=True, text=True, check=True,
                              timeout=30).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        return ""


def machine() -> dict[str, Any]:
    """The machine a figure was measured on, with the widest vector instruction set its
    processor offers (torch, MKL and oneDNN pick their kernels by it, so a trained model's
    numbers can differ between processors: docs/results.md, "Protocol")."""
    fields: dict[str, str] = {}  # the first processor's
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            key, _, value = line.partition(":")
            fields.setdefault(key.strip(), value.strip())
    except OSError:
        pass
    cpu = fields.get("model name") or platform.processor() or platform.machine()
    flags = set(fields.get("flags", "").split())
    vector = next((name for flag, name in (("avx512f", "AVX-512"), ("avx2", "AVX2"), ("avx", "AVX")) if flag in flags),
                  None)
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    return {"cpu": cpu, "cores": cores, **({"vector": vector} if vector else {}),
            "system": f"{platform.system()} {platform.release()}", "python": platform.python_version()}


def provenance() -> dict[str, Any]:
    """Where a figure measured now comes from: the commit (with ``dirty`` when the working
    tree differs from it), the command line, the machine and the date."""
    return {"commit": git("rev-parse", "HEAD") or "unknown",
            "dirty": bool(git("status", "--porcelain", "--untracked-files=no")),
            "argv": [Path(sys.argv[0]).name, *sys.argv[1:]],
            "machine": machine(),
            "date": datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M UTC")}


# -- data files -----------------------------------------------------------------------------------
def data_path(name: str) -> Path:
    return FIGURE_DIR / f"{name}.json"


def shown(path: Path) -> str:
    """A path as the docs name it: relative to the repository when inside it."""
    try:
        return str(path.relative_to(ROOT))
    except ValueError:
        return str(path)


def measure(figure: Figure, origin: dict[str, Any] | None = None) -> dict[str, Any]:
    """Run the figure's producer and return its data (not written). ``origin``: the
    :func:`provenance` taken before a run wrote anything (default: taken now)."""
    if figure.produce is None:
        raise FigureError(f"figure {figure.name!r} is not measured again by one command; its data is adopted "
                          f"(`python -m baselines.refresh --adopt {figure.name} --commit SHA`)")
    origin = provenance() if origin is None else origin
    started = time.perf_counter()
    table = figure.produce()
    return {"format": FORMAT_VERSION, "name": figure.name, "command": figure.command, "cheap": figure.cheap,
            "number_format": figure.number_format, "formats": table.formats, "columns": table.columns, "rows": table.rows,
            "stderr": table.stderr, "seeds": table.seeds, "note": table.note,
            **({"made_from": table.made_from} if table.made_from else {}),
            "wall_seconds": round(time.perf_counter() - started if table.wall_seconds is None else table.wall_seconds,
                                  1), **origin}


def write(data: dict[str, Any]) -> Path:
    path = data_path(data["name"])
    path.parent.mkdir(parents=True, exist_ok=True)
    atomic_write_text(path, json.dumps(data, indent=1) + "\n")
    return path


def load(name: str) -> dict[str, Any]:
    path = data_path(name)
    try:
        data = json.loads(path.read_text())
    except FileNotFoundError:
        raise FigureError(f"figure {name!r} has no data file {shown(path)}: "
                          f"run `python -m baselines.refresh --only {name}`") from None
    except (OSError, ValueError) as err:
        raise FigureError(f"{shown(path)}: unreadable figure data ({err})") from None
    if data.get("format") != FORMAT_VERSION or data.get("name") != name:
        raise FigureError(f"{shown(path)}: not a figure file of format {FORMAT_VERSION} named {name!r}")
    return data


# -- Markdown -------------------------------------------------------------------------------------
def _cell(value: Any, number_format: str) -> str:
    if isinstance(value, bool) or value is None or isinstance(value, str):
        return "" if value is None else str(value)
    if isinstance(value, int):
        if number_format.endswith("d"):  # an integer column's own format
            return format(value, number_format)
        return f"{value:,}" if abs(value) >= 10_000 else str(value)
    if isinstance(value, float):
        return "n/a" if not math.isfinite(value) else format(value, number_format)
    return str(value)


def render(data: dict[str, Any]) -> str:
    """The Markdown of a figure's block: its table, then where it comes from."""
    formats = data.get("formats") or [data.get("number_format", ".3f")] * len(data["columns"])
    numeric = [any(isinstance(row[c], int | float) and not isinstance(row[c], bool) for row in data["rows"])
               for c in range(len(data["columns"]))]
    align = data.get("align") or ["---:" if n else "---" for n in numeric]
    lines = ["| " + " | ".join(data["columns"]) + " |", "|" + "|".join(align) + "|"]
    lines += ["| " + " | ".join(_cell(v, f) for v, f in zip(row, formats)) + " |" for row in data["rows"]]
    commit = data["commit"][:7] + (" with uncommitted changes" if data.get("dirty") else "")
    if data.get("commit_note"):
        commit += f" ({data['commit_note']})"
    if data.get("typed"):
        how = (f"measured by `{data['command']}`" if data["command"] else
               "the command that measured it is not kept in the repository")
        where = (f"Typed in `{data['typed']}` at commit {commit} on {data['date']}; {how}; "
                 "not re-measured on the current code")
    elif data.get("made_from"):
        where = f"Made by `{data['command']}` at commit {commit} from {data['made_from']} (nothing measured)"
    else:
        where = f"Measured by `{data['command']}` at commit {commit} on {data['date']}"
        if data.get("machine"):
            cores = data["machine"]["cores"]
            vector = f", {data['machine']['vector']}" if data["machine"].get("vector") else ""
            where += f", {cores} core{'' if cores == 1 else 's'} ({data['machine']['cpu']}{vector})"
        if data.get("wall_seconds") is not None:
            where += f", {data['wall_seconds']:g} s"
    if data.get("seeds"):
        where += f"; seeds {data['seeds']}"
    where += f". Data: `{shown(data_path(data['name']))}`"
    where += " (rerun by the default tests)." if data.get("cheap") else "."
    out = "\n".join(lines) + "\n\n"
    if data.get("note"):
        out += data["note"] + "\n\n"
    return out + where + "\n"


def quoted_value(spec: str, loader: Callable[[str], dict[str, Any]] = load) -> str:
    """The text of one quoted value (see :data:`VALUE`): the cell at ``ROW`` and ``COLUMN`` of
    the figure's data, printed as its table prints it, or with ``FORMAT``."""
    parts = [p.strip() for p in spec.split("|")]
    if len(parts) not in (3, 4):
        raise FigureError(f"value {spec!r}: expected 'FIGURE | ROW | COLUMN [| FORMAT]'")
    name, row, column = parts[:3]
    data = loader(name)
    if row == "@":
        if column not in ("commit", "wall_seconds"):
            raise FigureError(f"value {spec!r}: '@' quotes the figure's commit or wall_seconds, not {column!r}")
        cell: Any = data[column][:7] if column == "commit" else data[column]
        number_format = parts[3] if len(parts) == 4 else "g"
    else:
        if column not in data["columns"]:
            raise FigureError(f"value {spec!r}: figure {name!r} has no column {column!r}")
        c = data["columns"].index(column)
        hits = [r for r in data["rows"] if str(r[0]) == row]
        if len(hits) != 1:
            raise FigureError(f"value {spec!r}: figure {name!r} has {len(hits)} rows named {row!r} (one expected)")
        cell = hits[0][c]
        formats = data.get("formats") or [data.get("number_format", ".3f")] * len(data["columns"])
        number_format = parts[3] if len(parts) == 4 else formats[c]
    return _cell(cell, number_format)


def blocks(text: str) -> list[tuple[str, str]]:
    """(figure name, block body) of every figure block in a Markdown text, in order."""
    return [(m["name"], m["body"]) for m in BLOCK.finditer(text)]


def rewrite(text: str, loader: Callable[[str], dict[str, Any]] = load) -> str:
    """``text`` with every figure block rewritten from its data file."""
    text = BLOCK.sub(lambda m: f"<!-- figure: {m['name']} -->\n{render(loader(m['name']))}<!-- /figure -->", text)
    return VALUE.sub(lambda m: f"<!-- value: {m['spec']} -->{quoted_value(m['spec'], loader)}<!-- /value -->", text)


def stale_blocks(paths: Sequence[Path] | None = None) -> list[str]:
    """The blocks and quoted values that differ from their data files, as ``file: figure``
    and ``file: value SPEC``."""
    problems = []
    for path in paths or [ROOT / p for p in DOC_FILES]:
        text = path.read_text()
        for name, body in blocks(text):
            if body != render(load(name)):
                problems.append(f"{path.name}: {name}")
        for m in VALUE.finditer(text):
            if m["text"] != quoted_value(m["spec"]):
                problems.append(f"{path.name}: value {m['spec']} (the doc says {m['text']!r})")
    return problems


def refresh_docs(paths: Sequence[Path] | None = None) -> list[Path]:
    """Rewrite every figure block from its data file; returns the files changed."""
    changed = []
    for path in paths or [ROOT / p for p in DOC_FILES]:
        text = path.read_text()
        new = rewrite(text)
        if new != text:
            atomic_write_text(path, new)
            changed.append(path)
    return changed


def moved(old: dict[str, Any], new: dict[str, Any]) -> list[str]:
    """Cells whose value moved by more than its standard error (or, with none, changed)."""
    out = []
    errors = new.get("stderr") or old.get("stderr")
    for r, (a_row, b_row) in enumerate(zip(old["rows"], new["rows"])):
        for c, (a, b) in enumerate(zip(a_row, b_row)):
            if a == b:
                continue
            if isinstance(a, int | float) and isinstance(b, int | float) and not isinstance(a, bool):
                se = errors[r][c] if errors and r < len(errors) and c < len(errors[r]) else None
                if se is not None and abs(float(b) - float(a)) <= se:
                    continue
                out.append(f"{new['name']}: {b_row[0]} / {new['columns'][c]}: {a} -> {b}"
                           + (f" (standard error {se:.3f})" if se is not None else ""))
            else:
                out.append(f"{new['name']}: {b_row[0]} / {new['columns'][c]}: {a!r} -> {b!r}")
    if len(old["rows"]) != len(new["rows"]):
        out.append(f"{new['name']}: {len(old['rows'])} rows -> {len(new['rows'])}")
    return out


# -- which figures hold on the current code -------------------------------------------------------
#: The code whose changes can move a measured figure: the package, the baselines, the
#: benchmarks and the dependencies' pins. This module and ``refresh.py`` are left out: they lay
#: the tables out, and a change to their layout moves no number.
MEASURED_CODE = ("legent_gym", "baselines", "benchmarks", "pyproject.toml")
NOT_MEASURED_CODE = ("baselines/figures.py", "baselines/figure_data.py", "baselines/refresh.py")


def code_changed_since(commit: str) -> list[str]:
    """The files of :data:`MEASURED_CODE` that differ between ``commit`` and ``HEAD``
    (committed changes only)."""
    try:
        done = subprocess.run(["git", "diff", "--name-only", commit, "HEAD", "--", *MEASURED_CODE,
                               *(f":(exclude){p}" for p in NOT_MEASURED_CODE)],
                              cwd=ROOT, capture_output=True, text=True, timeout=30)
    except (OSError, subprocess.SubprocessError) as err:
        raise FigureError(f"cannot run git to compare commit {commit[:7]} with HEAD: {err}") from None
    if done.returncode != 0:
        raise FigureError(f"commit {commit[:7]} is not in this clone's history (a shallow clone?): "
                          f"{done.stderr.strip().splitlines()[-1] if done.stderr.strip() else 'git diff failed'}")
    return done.stdout.split()


def typed_table(text: str, line: str) -> tuple[list[str], list[str], list[list[str]]]:
    """The Markdown table of ``text`` that holds a line containing ``line``: its columns, the
    alignment row's cells and its rows, each cell as typed."""
    lines = [row.strip() for row in text.splitlines()]  # a table may be indented (in a list)
    hits = [i for i, row in enumerate(lines) if row.startswith("|") and line in row]
    if len(hits) != 1:
        raise FigureError(f"{len(hits)} table lines contain {line!r} (one expected)")
    first = last = hits[0]
    while first > 0 and lines[first - 1].startswith("|"):
        first -= 1
    while last + 1 < len(lines) and lines[last + 1].startswith("|"):
        last += 1

    def cells(row: str) -> list[str]:
        return [c.strip() for c in row.strip().strip("|").split("|")]

    table = [cells(row) for row in lines[first:last + 1]]
    if len(table) < 3 or any(len(row) != len(table[0]) for row in table):
        raise FigureError(f"the table holding {line!r} is not a table of equal rows")
    return table[0], table[1], table[2:]


def adopt_typed(fig: Figure, full: str, note: str) -> dict[str, Any]:
    """The data of a figure whose table was typed in a doc, read from that doc at commit ``full``."""
    assert fig.typed is not None
    doc, line = fig.typed
    text = git("show", f"{full}:{doc}")
    if not text:
        raise FigureError(f"no {doc} at commit {full[:7]}")
    columns, align, rows = typed_table(text, line)
    return {"format": FORMAT_VERSION, "name": fig.name, "command": fig.command, "cheap": False,
            "number_format": fig.number_format, "formats": None, "columns": columns, "align": align,
            "rows": rows, "stderr": None, "seeds": "", "note": "", "wall_seconds": None,
            "commit": full, "dirty": False, "commit_note": note, "typed": doc, "typed_line": line,
            "argv": None, "machine": None,
            "date": git("show", "-s", "--format=%cd", "--date=format:%Y-%m-%d %H:%M UTC", full)}

"""Every code example of README.md and docs/*.md runs, as a reader runs it.

Each ```` ```python ```` and ```` ```bash ```` block of a Markdown file runs in a fresh Python
or bash, in order, in one working folder per file that holds links to the repository's
top-level entries (so ``examples/scenes/...`` and ``baselines/...`` resolve as from the
repository root, and the files the examples write stay out of the repository), with the
virtual environment's ``bin`` first on ``PATH`` (``legent-gym``, ``python``). A block that
fails fails its file's test, naming the block's line. Other fences (plain, ``json``) are
output, transcripts or formats, not run.

An HTML comment on the lines just above a block's fence, invisible where the Markdown is
rendered, changes what the test runs:

* ``<!-- test: skip (why) -->``: not run (a GPU, an LLM endpoint, hours of training, a
  server that runs until stopped, another machine); the reason is required;
* ``<!-- test: replace OLD => NEW -->``: the text OLD of the block replaced by NEW before it
  runs (smaller counts: ``--episodes 1000 => --episodes 4``); OLD must be in the block.
"""

from __future__ import annotations

import contextlib
import os
import re
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import pytest

from .conftest import REPO
from .ray_cluster import one_cluster_at_a_time

DOCS = [REPO / "README.md", *sorted((REPO / "docs").glob("*.md"))]
FENCE = re.compile(r"^```(python|bash)\n(.*?)^```$", re.S | re.M)
DIRECTIVE = re.compile(r"^<!-- test: (.*?) -->$")
SKIP = re.compile(r"skip \((.+)\)")
REPLACE = re.compile(r"replace (.+?) => (.*)")
#: The most seconds one block may take.
BLOCK_TIMEOUT = 300


@dataclass
class Block:
    language: str
    code: str
    line: int  # of the opening fence, 1-based
    skip: str | None = None


def blocks(path: Path) -> list[Block]:
    """The runnable blocks of ``path`` with their directives applied; ValueError for a
    directive that is malformed or whose OLD text is not in its block."""
    text = path.read_text()
    lines = text.splitlines()
    found = []
    for match in FENCE.finditer(text):
        line = text.count("\n", 0, match.start()) + 1
        block = Block(match.group(1), match.group(2), line)
        above = line - 2  # index of the line above the fence
        while above >= 0 and (directive := DIRECTIVE.match(lines[above].strip())):
            what = directive.group(1)
            where = f"{path.name}:{above + 1}"
            if skip := SKIP.fullmatch(what):
                block.skip = skip.group(1)
            elif replace := REPLACE.fullmatch(what):
                old, new = replace.groups()
                if old not in block.code:
                    raise ValueError(f"{where}: {old!r} is not in the block below it")
                block.code = block.code.replace(old, new)
            else:
                raise ValueError(f"{where}: unknown test directive {what!r} (skip (why) or replace OLD => NEW)")
            above -= 1
        found.append(block)
    return found


def working_folder(tmp_path: Path) -> Path:
    """A folder with a link to each tracked top-level entry of the repository."""
    tracked = subprocess.run(["git", "ls-files"], cwd=REPO, capture_output=True, text=True, check=True).stdout
    for name in sorted({entry.split("/")[0] for entry in tracked.splitlines()}):
        (tmp_path / name).symlink_to(REPO / name)
    return tmp_path


def run_block(block: Block, name: str, cwd: Path) -> subprocess.CompletedProcess:
    env = dict(os.environ)
    env["PATH"] = f"{Path(sys.executable).parent}{os.pathsep}{env.get('PATH', '')}"
    if block.language == "python":
        script = cwd / f"{name}-{block.line}.py"
        script.write_text(block.code)
        command = [sys.executable, str(script)]
    else:
        command = ["bash", "-e", "-o", "pipefail", "-c", block.code]
    return subprocess.run(command, cwd=cwd, env=env, capture_output=True, text=True, timeout=BLOCK_TIMEOUT)


@pytest.mark.parametrize("path", DOCS, ids=[str(p.relative_to(REPO)) for p in DOCS])
def test_every_example_runs(path, tmp_path, tmp_path_factory):
    runnable = [block for block in blocks(path) if block.skip is None]
    if not runnable:
        return
    cwd = working_folder(tmp_path)
    for block in runnable:
        # a block that starts a Ray waits for any other test's cluster to stop
        ray = "--backend ray" in block.code
        with one_cluster_at_a_time(tmp_path_factory) if ray else contextlib.nullcontext():
            done = run_block(block, path.name, cwd)
        assert done.returncode == 0, (f"{path.relative_to(REPO)}:{block.line}: the {block.language} block "
                                      f"exits with {done.returncode}\n{block.code}\n{done.stdout[-2000:]}"
                                      f"\n{done.stderr[-4000:]}")


def test_directives_are_read(tmp_path):
    page = tmp_path / "page.md"
    page.write_text("text\n<!-- test: skip (needs a GPU) -->\n```python\nimport torch\n```\n"
                    "<!-- test: replace 1000 => 3 -->\n<!-- test: replace out/ => tmp/ -->\n"
                    "```bash\nlegent-gym collect X --episodes 1000 --out out/\n```\n"
                    "```json\n{}\n```\n```\nplain\n```\n")
    skipped, bash = blocks(page)
    assert skipped.skip == "needs a GPU" and skipped.line == 3 and skipped.code == "import torch\n"
    assert bash.skip is None and bash.code == "legent-gym collect X --episodes 3 --out tmp/\n" and bash.line == 8
    page.write_text("<!-- test: replace 10 => 1 -->\n```python\nx = 2\n```\n")
    with pytest.raises(ValueError, match="page.md:1: '10' is not in the block"):
        blocks(page)
    page.write_text("<!-- test: skip -->\n```python\nx = 2\n```\n")
    with pytest.raises(ValueError, match="unknown test directive 'skip'"):
        blocks(page)


def test_a_broken_example_fails(tmp_path):
    """What the test does with a block that raises or a command that fails: its status."""
    cwd = working_folder(tmp_path)
    assert run_block(Block("python", "import legent_gym\nraise SystemExit(3)\n", 1), "x", cwd).returncode == 3
    failed = run_block(Block("bash", "legent-gym validate examples/scenes/no_such_scene.json\necho after\n", 1),
                       "x", cwd)
    assert failed.returncode != 0 and "after" not in failed.stdout
    ok = run_block(Block("bash", "legent-gym validate examples/scenes/one_room.json\n", 1), "x", cwd)
    assert ok.returncode == 0, ok.stderr

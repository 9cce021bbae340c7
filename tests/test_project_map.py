"""README's layout table is the project's one map: it names every package and top-level
module of legent_gym, and every file and folder it names is in the tree. (The layers
between the packages are contracts in ``.importlinter``, checked by ``lint-imports``.)"""

import importlib
import re
from pathlib import Path

import legent_gym

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = Path(legent_gym.__file__).parent
#: A file (``name.py``, ``folder/name.py``) or a folder (``name/``) as the table writes it.
TREE_NAME = re.compile(r"(?:\w+/)*\w+\.py|\w+/")


def layout() -> dict[str, str]:
    """README's layout table: each row's path -> what the row says it holds."""
    text = ROOT.joinpath("README.md").read_text()
    section = text.split("\n## Layout\n", 1)[1].split("\n## ", 1)[0]
    rows = {}
    for line in section.splitlines():
        match = re.fullmatch(r"\| `([^`]+)` \| (.+) \|", line)
        if match:
            rows[match.group(1)] = match.group(2)
    return rows


def parts() -> list[str]:
    """Every subpackage and top-level module, as ``name/`` or ``name.py``."""
    out = []
    for path in sorted(PACKAGE.iterdir()):
        if path.is_dir() and (path / "__init__.py").exists():
            out.append(f"{path.name}/")
        elif path.suffix == ".py" and path.name != "__init__.py":
            out.append(path.name)
    return out


def test_the_layout_names_every_package_and_top_level_module():
    rows = layout()
    assert len(parts()) >= 12
    for part in parts():
        if part.endswith("/"):
            assert f"legent_gym/{part}" in rows, f"README's layout has no row for legent_gym/{part}"
        else:  # in the legent_gym/*.py row, or by its path in the row of what it serves
            named = f"`{part}`" in rows["legent_gym/*.py"] or any(f"`legent_gym/{part}`" in text for text in rows.values())
            assert named, f"README's layout names legent_gym/{part} nowhere"


def test_every_path_the_layout_names_is_in_the_tree():
    rows = layout()
    assert len(rows) >= 10
    for path, text in rows.items():
        folder = ROOT / path.removesuffix("*.py")
        assert folder.is_dir(), f"README's layout names {path}, which is not a folder"
        for name in re.findall(r"`([^`]+)`", text):
            if TREE_NAME.fullmatch(name):
                found = (folder / name).exists() or (ROOT / name).exists() or any(folder.rglob(name.rstrip("/")))
                assert found, f"README's layout row {path} names {name}, which is in neither {path} nor the root"


def test_the_check_reads_the_table():
    rows = layout()
    assert "`cli.py`" in rows["legent_gym/*.py"]
    assert TREE_NAME.fullmatch("plan.py") and TREE_NAME.fullmatch("assets/") and TREE_NAME.fullmatch("vla/model.py")
    assert not TREE_NAME.fullmatch("docs/llm.md") and not TREE_NAME.fullmatch("for_sb3(env)")


def test_packages_export_their_api():
    """``from legent_gym.<package> import Name`` works for the names the docs use."""
    expected = {"agent": ["Body", "Outcome", "parse_actions", "format_actions", "ActionLimits"],
                "tasks": ["TASKS", "PAPER_WHERE_IS", "MAX_ACTIONS", "make_task", "TaskContext"],
                "envs": ["ENV_IDS"], "experts": ["Oracle"], "wrappers": ["ExpertInfo"],
                "multiagent": ["parallel_env"], "llm": ["ChatClient", "LLMError"]}
    for package, names in expected.items():
        module = importlib.import_module(f"legent_gym.{package}")
        for name in names:
            assert name in module.__all__ and getattr(module, name) is not None, f"legent_gym.{package}.{name}"
        for name in module.__all__:
            assert hasattr(module, name), f"legent_gym.{package}.__all__ names {name}, which it lacks"

"""README's layout table, docs/architecture.md and the package docstring name every package
and top-level module of legent_gym, so that the three maps of the project cannot drift
apart as packages are added."""

from pathlib import Path

import legent_gym

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = Path(legent_gym.__file__).parent


def parts() -> list[str]:
    """Every subpackage and top-level module, as ``name/`` or ``name.py``."""
    out = []
    for path in sorted(PACKAGE.iterdir()):
        if path.is_dir() and (path / "__init__.py").exists():
            out.append(f"{path.name}/")
        elif path.suffix == ".py" and path.name != "__init__.py":
            out.append(path.name)
    return out


def test_every_part_is_on_each_map():
    readme = ROOT.joinpath("README.md").read_text()
    architecture = ROOT.joinpath("docs", "architecture.md").read_text()
    docstring = legent_gym.__doc__
    assert len(parts()) >= 12
    for part in parts():
        name = part.rstrip("/").removesuffix(".py")
        assert f"legent_gym/{part}" in readme or f"`{part}`" in readme, f"README's layout lacks {part}"
        assert part in architecture, f"docs/architecture.md lacks {part}"
        assert f"legent_gym.{name}" in docstring, f"the package docstring lacks legent_gym.{name}"


def test_packages_export_their_api():
    """``from legent_gym.<package> import Name`` works for the names the docs use."""
    import importlib

    expected = {"agent": ["Body", "Outcome", "parse_actions", "format_actions", "ActionLimits"],
                "tasks": ["TASKS", "PAPER_WHERE_IS", "MAX_ACTIONS", "make_task", "TaskContext"],
                "envs": ["ENV_IDS"], "experts": ["Oracle"], "wrappers": ["ExpertInfo"],
                "multiagent": ["parallel_env"]}
    for package, names in expected.items():
        module = importlib.import_module(f"legent_gym.{package}")
        for name in names:
            assert name in module.__all__ and getattr(module, name) is not None, f"legent_gym.{package}.{name}"
        for name in module.__all__:
            assert hasattr(module, name), f"legent_gym.{package}.__all__ names {name}, which it lacks"

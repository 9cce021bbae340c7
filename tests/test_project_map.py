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

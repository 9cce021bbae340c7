"""No module of ``legent_gym`` reaches into another module's or class's private names.

A name with a leading underscore is private to the module or class that defines it. The
package's modules talk to each other only through public names, so that each layer's
interface is what its public names say. This test walks the AST of every module and
fails on:

- ``from m import _name`` and ``import m._name`` (another module's private name or module);
- ``obj._name`` where ``obj`` is not ``self`` or ``cls`` (another object's private
  attribute), dunder names aside.

Exceptions: ``os._exit``, the standard library's documented way for a child process to
exit without running its parent's clean-up, and a named tuple's public methods
(``_replace``, ``_asdict``, ...).
"""

import ast
from pathlib import Path

import legent_gym

PACKAGE = Path(legent_gym.__file__).parent
ALLOWED_ATTRIBUTES = {("os", "_exit")}
#: A named tuple's public methods carry an underscore so as not to clash with its fields.
NAMEDTUPLE_METHODS = {"_replace", "_asdict", "_fields", "_make"}


def _private(name: str) -> bool:
    return name.startswith("_") and not (name.startswith("__") and name.endswith("__"))


def violations(source: str, filename: str) -> list[str]:
    """Each use of another's private name in ``source``, in line order."""
    out: list[tuple[int, str]] = []
    for node in ast.walk(ast.parse(source, filename)):
        if isinstance(node, ast.ImportFrom):
            parts = (node.module or "").split(".")
            names = [a.name for a in node.names]
            if any(_private(p) for p in parts) or any(_private(n) for n in names):
                out.append((node.lineno, f"{filename}:{node.lineno}: from {node.module} import {', '.join(names)}"))
        elif isinstance(node, ast.Import):
            for alias in node.names:
                if any(_private(p) for p in alias.name.split(".")):
                    out.append((node.lineno, f"{filename}:{node.lineno}: import {alias.name}"))
        elif isinstance(node, ast.Attribute) and _private(node.attr) and node.attr not in NAMEDTUPLE_METHODS:
            owner = node.value
            if isinstance(owner, ast.Name) and (owner.id in ("self", "cls") or (owner.id, node.attr) in ALLOWED_ATTRIBUTES):
                continue
            out.append((node.lineno, f"{filename}:{node.lineno}: {ast.unparse(node)}"))
    return [text for _, text in sorted(out)]


def test_no_module_uses_another_modules_private_names():
    found = []
    for path in sorted(PACKAGE.rglob("*.py")):
        found += violations(path.read_text(), str(path.relative_to(PACKAGE.parent)))
    assert not found, "private names used across modules or classes:\n" + "\n".join(found)


def test_the_check_sees_each_kind_of_violation():
    source = ("from a import _b\nimport a._c\nx._d\nself._e\ncls._f\nos._exit(0)\nx.__class__\n"
              "from a._g import h\n")
    assert [v.split(": ", 1)[1] for v in violations(source, "m.py")] == [
        "from a import _b", "import a._c", "x._d", "from a._g import h"]

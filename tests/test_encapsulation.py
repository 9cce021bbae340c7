"""No module of ``legent_gym`` reaches into another module's or class's private names.

A name with a leading underscore is private to the module or class that defines it. The
package's modules talk to each other only through public names, so that each layer's
interface is what its public names say. Private *modules* (``import m._name``, ``from
m._x import y``) are import-linter's ``private_modules`` contract (``.importlinter``); this
test walks the AST of every module for what import-linter does not see, and fails on:

- ``from m import _name`` (another module's private name);
- ``obj._name`` where ``obj`` is not ``self`` or ``cls`` (another object's private
  attribute), dunder names aside, unless the class the code is in defines ``_name`` itself
  (its own private on another instance of it).

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


def _own_privates(cls: ast.ClassDef) -> set[str]:
    """The private names a class defines: methods, class attributes and ``self._x``."""
    names = set()
    for node in ast.walk(cls):
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef) and _private(node.name):
            names.add(node.name)
        elif isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name) and node.value.id in ("self", "cls") \
                and _private(node.attr):
            names.add(node.attr)
        elif isinstance(node, ast.Name) and isinstance(node.ctx, ast.Store) and _private(node.id):
            names.add(node.id)
    return names


def violations(source: str, filename: str) -> list[str]:
    """Each use of another's private name in ``source``, in line order. Inside a class, a
    private name the class itself defines may be used on another instance of it
    (``other._x`` in ``__eq__``, a factory filling in a new instance)."""
    out: list[tuple[int, str]] = []
    tree = ast.parse(source, filename)
    allowed_at: dict[int, set[str]] = {}  # id(attribute node) -> names its class owns
    for cls in (n for n in ast.walk(tree) if isinstance(n, ast.ClassDef)):
        own = _own_privates(cls)
        for node in ast.walk(cls):
            if isinstance(node, ast.Attribute):
                allowed_at.setdefault(id(node), set()).update(own)
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            names = [a.name for a in node.names]
            if any(_private(n) for n in names):
                out.append((node.lineno, f"{filename}:{node.lineno}: from {node.module} import {', '.join(names)}"))
        elif isinstance(node, ast.Attribute) and _private(node.attr) and node.attr not in NAMEDTUPLE_METHODS:
            owner = node.value
            if isinstance(owner, ast.Name) and (owner.id in ("self", "cls") or (owner.id, node.attr) in ALLOWED_ATTRIBUTES):
                continue
            if node.attr in allowed_at.get(id(node), ()):
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
              "from a._g import h\n"
              "class K:\n    def f(self, other):\n        self._own = 1\n        return other._own, other._theirs\n")
    assert [v.split(": ", 1)[1] for v in violations(source, "m.py")] == [
        "from a import _b", "x._d", "other._theirs"]

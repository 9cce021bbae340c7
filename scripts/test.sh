#!/usr/bin/env bash
# Set everything up, lint, type-check, then run the default test suite (slow acceptance tests: add `-m slow`).
set -euo pipefail
cd "$(dirname "$0")/.."
LEGENT_EXTRAS="${LEGENT_EXTRAS:-dev,rl,multiagent,data,baselines,scale,play,vlm,clients,docs}" bash scripts/setup.sh
.venv/bin/ruff check legent_gym tests benchmarks baselines examples
.venv/bin/mypy legent_gym
# The architecture's contracts (.importlinter: layers, no cycles, the library below the baselines).
.venv/bin/lint-imports --no-cache
# The docs site (mkdocs.yml), into a temporary folder: a broken link, nav entry or API reference fails.
site="$(mktemp -d)"; NO_MKDOCS_2_WARNING=1 .venv/bin/mkdocs build --strict --quiet --site-dir "$site"; rm -rf "$site"
# The whole default suite (no arguments, as CI runs it) also fails if a test skips for a reason
# other than an absence listed in tests/skip_check.py (README.md: Quick start).
if [ "$#" -eq 0 ]; then set -- --check-skips; fi
exec .venv/bin/python -m pytest -n 2 -q "$@"

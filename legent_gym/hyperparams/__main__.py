"""``python -m legent_gym.hyperparams ALGO``: print the path of ALGO's YAML file (to copy and edit)."""

import sys

from legent_gym.hyperparams import ALGOS, path

if len(sys.argv) != 2 or sys.argv[1] not in ALGOS:
    sys.exit(f"usage: python -m legent_gym.hyperparams ALGO  (ALGO: one of {', '.join(ALGOS)})")
print(path(sys.argv[1]))

#!/usr/bin/env bash
# Set up legent_gym on a fresh Debian/Ubuntu machine: the system OpenGL (EGL + Mesa) that
# headless rendering needs, and a virtual environment in .venv with the package and the
# extras named in $LEGENT_EXTRAS (default: dev). Idempotent: a second run is quick.
set -euo pipefail
cd "$(dirname "$0")/.."

extras="${LEGENT_EXTRAS:-dev}"

# Headless rendering: EGL with Mesa's software rasteriser (llvmpipe). No X server needed.
need_gl=()
for pkg in libegl1 libgl1 libegl-mesa0 libgl1-mesa-dri libgles2; do
  dpkg -s "$pkg" >/dev/null 2>&1 || need_gl+=("$pkg")
done
if [ "${#need_gl[@]}" -gt 0 ]; then
  if command -v apt-get >/dev/null 2>&1; then
    sudo_cmd=""; [ "$(id -u)" -ne 0 ] && sudo_cmd="sudo"
    echo "installing system packages: ${need_gl[*]}"
    $sudo_cmd apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq "${need_gl[@]}" >/dev/null
  else
    echo "warning: cannot install ${need_gl[*]} (no apt-get); install EGL + Mesa by hand" >&2
  fi
fi

# The play extra's browser tests drive Debian's chromium package (never a downloaded browser build).
case ",$extras," in
  *,play,*|*,all,*)
    if ! command -v chromium >/dev/null 2>&1; then
      if command -v apt-get >/dev/null 2>&1; then
        sudo_cmd=""; [ "$(id -u)" -ne 0 ] && sudo_cmd="sudo"
        echo "installing system package: chromium"
        $sudo_cmd apt-get update -qq
        DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq chromium >/dev/null
      else
        echo "warning: cannot install chromium (no apt-get); the browser tests of legent-gym play are skipped" >&2
      fi
    fi ;;
esac

python="${PYTHON:-python3}"
if [ ! -x .venv/bin/python ]; then
  "$python" -m venv .venv
fi
.venv/bin/python -m pip install -q --upgrade pip
# torch is pinned (a bare `torch` pulls gigabytes of CUDA packages); install it first so
# that no other requirement drags in another build.
case ",$extras," in
  *,baselines,*|*,rl,*|*,all,*) .venv/bin/python -m pip install -q "torch==2.13.0" ;;
esac
.venv/bin/python -m pip install -q -e ".[$extras]"
echo "legent_gym is set up in .venv (extras: $extras)"

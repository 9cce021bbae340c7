#!/usr/bin/env bash
# Set up legent_gym on a fresh Debian/Ubuntu machine: the system OpenGL (EGL + Mesa) that
# headless rendering needs, and a virtual environment in .venv with the package and the
# extras named in $LEGENT_EXTRAS (default: dev). Idempotent: a second run is quick.
set -euo pipefail
cd "$(dirname "$0")/.."

extras="${LEGENT_EXTRAS:-dev}"

# apt_install CONSEQUENCE PACKAGE...: install the Debian packages not installed yet (with no
# apt-get: a warning that ends with CONSEQUENCE).
apt_install() {
  local without="$1" need=() pkg
  shift
  for pkg in "$@"; do
    dpkg -s "$pkg" >/dev/null 2>&1 || need+=("$pkg")
  done
  [ "${#need[@]}" -gt 0 ] || return 0
  if command -v apt-get >/dev/null 2>&1; then
    local sudo_cmd=""; [ "$(id -u)" -ne 0 ] && sudo_cmd="sudo"
    echo "installing system packages: ${need[*]}"
    $sudo_cmd apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq "${need[@]}" >/dev/null
  else
    echo "warning: cannot install ${need[*]} (no apt-get); $without" >&2
  fi
}

# Headless rendering: EGL with Mesa's software rasteriser (llvmpipe). No X server needed.
apt_install "install EGL + Mesa by hand" libegl1 libgl1 libegl-mesa0 libgl1-mesa-dri libgles2

# The dev extra's tests render through the other backends too (tests/utils/test_gl_backend.py:
# MUJOCO_GL=osmesa, and GLFW on a display: a virtual X server).
case ",$extras," in
  *,dev,*|*,all,*) apt_install "tests/utils/test_gl_backend.py skips its OSMesa and display tests" libosmesa6 xvfb ;;
esac

# The play extra's browser tests drive Debian's chromium package (never a downloaded browser build).
case ",$extras," in
  *,play,*|*,all,*)
    command -v chromium >/dev/null 2>&1 || apt_install "the browser tests of legent-gym play are skipped" chromium ;;
esac

python="${PYTHON:-python3}"
if [ ! -x .venv/bin/python ]; then
  "$python" -m venv .venv
fi
.venv/bin/python -m pip install -q --upgrade pip
# torch is pinned (a bare `torch` pulls gigabytes of CUDA packages); install it first so
# that no other requirement drags in another build.
case ",$extras," in
  *,baselines,*|*,rl,*|*,clients,*|*,all,*) .venv/bin/python -m pip install -q "torch==2.13.0" ;;
esac
.venv/bin/python -m pip install -q -e ".[$extras]"
echo "legent_gym is set up in .venv (extras: $extras)"

#!/usr/bin/env bash
# Idempotent setup: Debian packages and a Python venv for the third-party readers and peers.
# Usage: scripts/setup.sh [--peers]   (--peers also installs the heavy Python peers for the harness)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
venv="${MESHER_VENV:-$root/.venv}"

# g++ builds the CGAL driver (reference/build.rs); time (/usr/bin/time -v) is used by scripts/bench-kernel.sh.
apt_pkgs=(tetgen libcgal-dev libgmp-dev libmpfr-dev g++ time python3-venv)
# chromium: harness/tests/report.rs renders the HTML report headless and checks the screenshot.
apt_pkgs+=(chromium)
missing=()
for p in "${apt_pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  sudo_cmd=""
  [ "$(id -u)" -eq 0 ] || sudo_cmd="sudo"
  echo "setup: installing ${missing[*]}"
  $sudo_cmd apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq "${missing[@]}" >/dev/null
fi

py_pkgs=(meshio numpy)
if [ "${1:-}" = "--peers" ]; then
  py_pkgs+=(gmsh pytetwild pyvista pymeshlab)
fi
if [ ! -x "$venv/bin/python" ]; then
  python3 -m venv "$venv"
fi
need=()
for p in "${py_pkgs[@]}"; do
  "$venv/bin/python" -m pip show -q "$p" >/dev/null 2>&1 || need+=("$p")
done
if [ ${#need[@]} -gt 0 ]; then
  echo "setup: pip installing ${need[*]}"
  "$venv/bin/python" -m pip install -q "${need[@]}"
fi
echo "setup: ok (venv $venv)"

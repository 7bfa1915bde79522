#!/usr/bin/env bash
# Idempotent setup: Debian packages and a Python venv for the third-party readers and peers.
# Usage: scripts/setup.sh [--peers]   (--peers also installs the heavy Python peers for the harness)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
venv="${MESHER_VENV:-$root/.venv}"

# g++ builds the CGAL driver (reference/build.rs); time (/usr/bin/time -v) is used by scripts/bench-kernel.sh.
apt_pkgs=(tetgen libcgal-dev libgmp-dev libmpfr-dev g++ time python3-venv)
# chromium: harness/tests/report.rs renders the HTML report headless and checks the screenshot.
# fonts-dejavu-core: the font `harness report` lays out plot text with (SVG and PNG).
apt_pkgs+=(chromium fonts-dejavu-core)
# apt_ensure PKG...: installs the packages that are not installed yet (one apt run).
apt_ensure() {
  local missing=() p sudo_cmd=""
  for p in "$@"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  [ ${#missing[@]} -gt 0 ] || return 0
  [ "$(id -u)" -eq 0 ] || sudo_cmd="sudo"
  echo "setup: installing ${missing[*]}"
  $sudo_cmd apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq "${missing[@]}" >/dev/null
}
apt_ensure "${apt_pkgs[@]}"

# Python packages, pinned in scripts/requirements.txt: meshio and numpy always; with --peers
# every line (gmsh, pytetwild, pyvista, pymeshlab). pip runs only when a pin is not met.
reqs="$root/scripts/requirements.txt"
mapfile -t py_pkgs < <(grep -v -e '^#' -e '^[[:space:]]*$' "$reqs")
if [ "${1:-}" != "--peers" ]; then
  mapfile -t py_pkgs < <(printf '%s\n' "${py_pkgs[@]}" | grep -i -e '^meshio==' -e '^numpy==')
fi
if [ ! -x "$venv/bin/python" ]; then
  python3 -m venv "$venv"
fi
# gmsh and pymeshlab load the GL/X client libraries at import time.
if [ "${1:-}" = "--peers" ]; then
  apt_ensure libglu1-mesa libgl1 libxcursor1 libxft2 libfontconfig1 libxinerama1
fi
frozen="$("$venv/bin/python" -m pip freeze 2>/dev/null | tr '[:upper:]' '[:lower:]')"
need=()
for p in "${py_pkgs[@]}"; do
  grep -qx -F "$(echo "$p" | tr '[:upper:]' '[:lower:]')" <<<"$frozen" || need+=("$p")
done
if [ ${#need[@]} -gt 0 ]; then
  echo "setup: pip installing ${need[*]}"
  "$venv/bin/python" -m pip install -q "${need[@]}"
fi
echo "setup: ok (venv $venv)"

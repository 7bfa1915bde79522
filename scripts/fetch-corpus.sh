#!/usr/bin/env bash
# Fetches the real boundary meshes of the corpus from Debian packages into the
# git-ignored corpus/cache/ (idempotent; no root needed for the download itself).
#
#   corpus/cache/cgal/meshes/*.off   CGAL's data meshes (package libcgal-demo,
#                                    usr/share/doc/libcgal-dev/data.tar.gz, data/meshes/)
#
# Usage: scripts/fetch-corpus.sh
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cache="$root/corpus/cache"
mkdir -p "$cache/debs"

# fetch_deb PACKAGE: downloads PACKAGE's .deb into cache/debs once; prints its path.
fetch_deb() {
  local pkg="$1" deb
  deb="$(ls "$cache/debs/${pkg}"_*.deb 2>/dev/null | head -n 1 || true)"
  if [ -z "$deb" ]; then
    (cd "$cache/debs" && apt-get download "$pkg" >/dev/null 2>&1) || {
      # An empty or stale package list: refresh it once and retry.
      local sudo_cmd=""
      [ "$(id -u)" -eq 0 ] || sudo_cmd="sudo"
      $sudo_cmd apt-get update -qq
      (cd "$cache/debs" && apt-get download "$pkg" >/dev/null 2>&1)
    }
    deb="$(ls "$cache/debs/${pkg}"_*.deb | head -n 1)"
  fi
  echo "$deb"
}

if [ ! -f "$cache/cgal/meshes/fandisk.off" ]; then
  deb="$(fetch_deb libcgal-demo)"
  tmp="$(mktemp -d)"
  trap 'rm -rf "$tmp"' EXIT
  dpkg-deb -x "$deb" "$tmp/x"
  mkdir -p "$tmp/d" "$cache/cgal"
  tar -xzf "$tmp/x/usr/share/doc/libcgal-dev/data.tar.gz" -C "$tmp/d"
  rm -rf "$cache/cgal/meshes"
  mv "$tmp/d/data/meshes" "$cache/cgal/meshes"
  cp "$tmp/x/usr/share/doc/libcgal-demo/copyright" "$cache/cgal/COPYRIGHT" 2>/dev/null || true
  sha256sum "$deb" > "$cache/cgal/SOURCE.sha256"
  echo "fetch-corpus: CGAL data meshes in $cache/cgal/meshes ($(ls "$cache/cgal/meshes" | wc -l) files)"
else
  echo "fetch-corpus: CGAL data meshes already in $cache/cgal/meshes"
fi

#!/usr/bin/env bash
# Fetches the real boundary meshes of the corpus from Debian packages into the
# git-ignored corpus/cache/ (idempotent; no root needed for the download itself).
#
#   corpus/cache/cgal/meshes/*.off   CGAL's data meshes (package libcgal-demo,
#                                    usr/share/doc/libcgal-dev/data.tar.gz, data/meshes/)
#   corpus/cache/netgen/{hinge,part1}.stl   Netgen's examples (package netgen-doc, LGPL)
#   corpus/cache/gmsh/t13_data.stl          Gmsh's tutorial t13 (package gmsh-doc, GPL;
#                                           gunzipped)
# Each package's copyright file is kept beside its data (COPYRIGHT). Checksums of the
# extracted files are in corpus/manifest.toml; `harness corpus check` verifies them.
#
# Usage: scripts/fetch-corpus.sh
set -euo pipefail
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
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
  dpkg-deb -x "$deb" "$tmp/x"
  mkdir -p "$tmp/d" "$cache/cgal"
  tar -xzf "$tmp/x/usr/share/doc/libcgal-dev/data.tar.gz" -C "$tmp/d"
  rm -rf "$cache/cgal/meshes"
  mv "$tmp/d/data/meshes" "$cache/cgal/meshes"
  sha256sum "$deb" > "$cache/cgal/SOURCE.sha256"
  echo "fetch-corpus: CGAL data meshes in $cache/cgal/meshes ($(ls "$cache/cgal/meshes" | wc -l) files)"
else
  echo "fetch-corpus: CGAL data meshes already in $cache/cgal/meshes"
fi
# libcgal-demo's doc folder is a symlink to libcgal-dev's: the copyright file (CGAL's
# licences; the data meshes carry no notice, hence CC0) comes from libcgal-dev's package.
if [ ! -f "$cache/cgal/COPYRIGHT" ]; then
  deb="$(fetch_deb libcgal-dev)"
  mkdir -p "$tmp/dev"
  dpkg-deb --fsys-tarfile "$deb" | tar -x -C "$tmp/dev" ./usr/share/doc/libcgal-dev/copyright
  cp "$tmp/dev/usr/share/doc/libcgal-dev/copyright" "$cache/cgal/COPYRIGHT"
fi

# fetch_doc PACKAGE DEST COPYRIGHT SRC...: extracts files SRC (paths inside the package;
# a .gz one is gunzipped) from PACKAGE into cache/DEST, with the package's copyright.
fetch_doc() {
  local pkg="$1" dest="$cache/$2" copyright="$3" deb src out
  shift 3
  local missing=0
  for src in "$@"; do
    out="$dest/$(basename "${src%.gz}")"
    [ -f "$out" ] || missing=1
  done
  if [ "$missing" -eq 0 ]; then
    echo "fetch-corpus: $pkg files already in $dest"
    return
  fi
  deb="$(fetch_deb "$pkg")"
  rm -rf "$tmp/$pkg" && mkdir -p "$tmp/$pkg" "$dest"
  dpkg-deb -x "$deb" "$tmp/$pkg"
  for src in "$@"; do
    out="$dest/$(basename "${src%.gz}")"
    case "$src" in
      *.gz) gunzip -c "$tmp/$pkg/$src" > "$out" ;;
      *) cp "$tmp/$pkg/$src" "$out" ;;
    esac
  done
  cp "$tmp/$pkg/$copyright" "$dest/COPYRIGHT"
  sha256sum "$deb" > "$dest/SOURCE.sha256"
  echo "fetch-corpus: $pkg files in $dest"
}

fetch_doc netgen-doc netgen usr/share/doc/netgen-doc/copyright \
  usr/share/doc/netgen/examples/hinge.stl usr/share/doc/netgen/examples/part1.stl
fetch_doc gmsh-doc gmsh usr/share/doc/gmsh-doc/copyright \
  usr/share/doc/gmsh-doc/doc/gmsh/tutorial/t13_data.stl.gz

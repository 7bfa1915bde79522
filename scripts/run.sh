#!/usr/bin/env bash
# A demo of the Delaunay kernel (the main job is scripts/compare.sh, the comparison
# report): generates a sphere surface, checks it, and builds the Delaunay tetrahedralisation of
# its vertices and of 10^6 random points, writing the meshes and statistics to
# reports/out/.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
out="reports/out"
mkdir -p "$out"
cargo build --release -q -p mesher -p reference
bin="target/release"
"$bin/mesher" generate sphere --level 5 -o "$out/sphere.off"
"$bin/mesher" check "$out/sphere.off"
"$bin/mesher" delaunay "$out/sphere.off" -o "$out/sphere-delaunay.vtu" --validate --stats \
  | tee "$out/sphere-delaunay.json"
"$bin/random-points" 1000000 --seed 1 -o "$out/points-1e6.node"
"$bin/mesher" delaunay "$out/points-1e6.node" --stats | tee "$out/points-1e6.json"
echo "run: outputs in $out/"

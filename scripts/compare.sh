#!/usr/bin/env bash
# The main job: the comparison report of the mesher and its peers on the ci tier, with
# the dirty tier's rows (each with its status), in reports/latest/ (index.html, table.md,
# targets.md, table.tex, plots; the records in reports/latest/run/).
#
# Idempotent setup first (apt peers, the Python venv, the corpus data), then a release
# build and `harness compare` with every registered runner: tetgen, tetgen-y, cgal,
# ftetwild, gmsh-hxt, gmsh-delaunay, their -sized configurations, and ours (listed as
# missing until `mesher mesh` exists). fTetWild takes minutes per model: when CI is set
# it runs on the 5 smallest models of the ci tier only (--limit-slow 5: the N smallest
# of each clean tier, no dirty model), and each run's time limit is 120 s.
#
# Usage: scripts/compare.sh [extra harness compare arguments, e.g. --timeout 300]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
scripts/setup.sh --peers
scripts/fetch-corpus.sh
# cgal-mesh3 must sit beside the harness binary (target/release): build both.
cargo build --release -q -p harness -p reference --bins
# A mesher build failure must not stop the peers' report: "ours" is then missing.
cargo build --release -q -p mesher --bin mesher || echo "compare: mesher does not build; ours will be missing" >&2
limit=()
if [ -n "${CI:-}" ]; then
  # Every ci-tier run takes under 20 s here; on the dirty tier CGAL can spend its whole
  # time limit on the self-intersecting `man` (a timeout row either way): 120 s, not 600.
  limit=(--limit-slow 5 --timeout 120)
fi
target/release/harness compare --corpus ci,dirty --out reports/latest "${limit[@]}" "$@"
echo "compare: open reports/latest/index.html"

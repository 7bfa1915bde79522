#!/usr/bin/env bash
# Fuzzing with cargo fuzz (libFuzzer, nightly toolchain), issue 8.
# Usage: scripts/fuzz.sh SECONDS [TARGET...]
#   Runs every target of fuzz/ (or the named ones) for SECONDS each, one after the other,
#   with debug assertions on (checked id arithmetic), and prints per target the run time,
#   the executions and whether it found something. Installs cargo-fuzz if missing.
#   Corpora go to fuzz/corpus/TARGET, findings to fuzz/artifacts/TARGET, logs to
#   fuzz/logs (all git-ignored). A finding becomes a regression: minimise it with
#   `cargo +nightly fuzz tmin -a TARGET ARTIFACT`, copy it to mesher/tests/regress/TARGET/
#   under a descriptive name; mesher/tests/fuzz_regress.rs replays that folder.
# Environment: FUZZ_TIMEOUT (seconds per input before libFuzzer calls it a hang, 20),
#   FUZZ_RSS_MB (memory limit, 4096).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
secs="${1:?usage: scripts/fuzz.sh SECONDS [TARGET...]}"
shift
timeout_s="${FUZZ_TIMEOUT:-20}"
rss_mb="${FUZZ_RSS_MB:-4096}"

rustup toolchain list | grep -q '^nightly' || rustup toolchain install nightly --profile minimal
command -v cargo-fuzz >/dev/null 2>&1 || cargo install cargo-fuzz --locked

cd "$root/fuzz"
mapfile -t all < <(cargo +nightly fuzz list)
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=("${all[@]}")
cargo +nightly fuzz build -a
mkdir -p logs

# Tiny valid seeds for the parsers (libFuzzer mutates from them).
seed() { # TARGET NAME CONTENT
  mkdir -p "corpus/$1"
  [ -e "corpus/$1/$2" ] || printf '%b' "$3" >"corpus/$1/$2"
}
seed parse_off tet.off 'OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n'
seed parse_obj tet.obj 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n'
seed parse_stl tet.stl 'solid t\nfacet normal 0 0 -1\nouter loop\nvertex 0 0 0\nvertex 0 1 0\nvertex 1 0 0\nendloop\nendfacet\nendsolid t\n'
seed parse_medit tet.mesh 'MeshVersionFormatted 2\nDimension 3\nVertices\n4\n0 0 0 0\n1 0 0 0\n0 1 0 0\n0 0 1 0\nTriangles\n4\n1 3 2 1\n1 2 4 1\n2 3 4 1\n1 4 3 1\nEnd\n'
# Full-length seeds for the decoded targets (libFuzzer's length limit grows slowly from
# short inputs, and the mesh target needs 3 bytes per perturbed vertex).
for t in delaunay mesh; do
  mkdir -p "corpus/$t"
  [ -e "corpus/$t/seed-256" ] || head -c 256 /dev/urandom >"corpus/$t/seed-256"
done

printf '%-12s %8s %12s  %s\n' target seconds executions result
status=0
for t in "${targets[@]}"; do
  log="logs/$t.log"
  mkdir -p "corpus/$t" "artifacts/$t"
  start=$(date +%s)
  rc=0
  cargo +nightly fuzz run -a "$t" "corpus/$t" -- \
    -max_total_time="$secs" -timeout="$timeout_s" -rss_limit_mb="$rss_mb" \
    -artifact_prefix="artifacts/$t/" -print_final_stats=1 >"$log" 2>&1 || rc=$?
  # libFuzzer's own fuzzing time ("Done N runs in S second(s)"); wall time on a finding.
  took=$(grep -o 'Done [0-9]* runs in [0-9]* second' "$log" | grep -o 'in [0-9]*' | grep -o '[0-9]*' | tail -1)
  [ -n "$took" ] || took=$(($(date +%s) - start))
  runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' | tail -1)
  [ -n "$runs" ] || runs=$(grep -o '^#[0-9]*' "$log" | tail -1 | tr -d '#')
  if [ "$rc" -eq 0 ]; then
    result="ok"
  else
    status=1
    result="FOUND (exit $rc): $(grep -o 'artifacts/[^ ]*' "$log" | tail -1), see fuzz/$log"
  fi
  printf '%-12s %8s %12s  %s\n' "$t" "$took" "${runs:-?}" "$result"
done
exit $status

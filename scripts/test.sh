#!/usr/bin/env bash
# The project's test command: installs what the tests need (idempotent), then runs
# formatting, lints, the ci tier with the regression gate (`harness gate`, issue 7) and
# the whole test suite.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
scripts/setup.sh --peers
scripts/fetch-corpus.sh
export MESHER_PYTHON="${MESHER_PYTHON:-$root/.venv/bin/python}"
# A one-off build gains nothing from incremental caches (about 1 GB here).
export CARGO_INCREMENTAL="${CARGO_INCREMENTAL:-0}"
echo "== disk: $(df -h --output=avail "$root" | tail -1 | tr -d ' ') free under $root," \
    "$(df -h --output=avail "${TMPDIR:-/tmp}" | tail -1 | tr -d ' ') under ${TMPDIR:-/tmp}"
echo "== cargo fmt --check"
cargo fmt --all -- --check
echo "== cargo clippy"
cargo clippy --workspace --all-targets -- -D warnings
# One ci-tier run serves both the regression gate and tests/ci_tier.rs (which reads it
# through HARNESS_CI_RUN instead of running the tier again): our runners, the peers the
# gate's speed ratios need (reports/baseline/tolerances.toml) and the peers ci_tier.rs
# checks. Release build: the baseline was measured with one.
echo "== ci tier run (release)"
cargo build --release -p harness -p mesher -p reference --bins
run_dir="$(mktemp -d)/ci"
target/release/harness run --corpus ci --out "$run_dir" \
    --meshers ours,ours-boundary,tetgen-y-boundary,tetgen-y,gmsh-hxt,cgal
echo "== harness gate (against reports/baseline/ci.json)"
gate=0
target/release/harness gate "$run_dir" --baseline reports/baseline/ci.json || gate=$?
echo "== cargo test"
HARNESS_CI_RUN="$run_dir" cargo test --workspace
if [ "$gate" -ne 0 ]; then
    echo "scripts/test.sh: the regression gate failed (table above); if the change is" \
        "deliberate: harness gate RUN_DIR --update, and commit the baseline" >&2
    exit "$gate"
fi

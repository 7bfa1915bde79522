#!/usr/bin/env bash
# The project's test command: installs what the tests need (idempotent), then runs
# formatting, lints and the whole test suite.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
scripts/setup.sh --peers
scripts/fetch-corpus.sh
export MESHER_PYTHON="${MESHER_PYTHON:-$root/.venv/bin/python}"
echo "== cargo fmt --check"
cargo fmt --all -- --check
echo "== cargo clippy"
cargo clippy --workspace --all-targets -- -D warnings
echo "== cargo test"
cargo test --workspace

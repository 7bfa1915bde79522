#!/usr/bin/env bash
# The nightly job (issue 7): the nightly tier (ci + nightly models) with every runner
# into reports/nightly/<date>/ (records in run/, the report beside them), one summary
# row per mesher appended to reports/history.csv, and the report's trend plots drawn
# from that history.
#
# Progress goes to stderr (pairs done / total, the current model, elapsed time). A
# killed nightly is resumed with --resume: pairs already recorded in the run directory
# are skipped. fTetWild takes minutes per model: pass --limit-slow N to run it on the N
# smallest models of each tier only.
#
# Usage: scripts/nightly.sh [--resume] [--date YYYY-MM-DD] [extra harness run arguments,
#        e.g. --limit-slow 3 --timeout 900 --meshers ours,tetgen-y]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
date="$(date -u +%F)"
resume=()
extra=()
while [ $# -gt 0 ]; do
  case "$1" in
    --resume) resume=(--resume); shift ;;
    --date) date="$2"; shift 2 ;;
    *) extra+=("$1"); shift ;;
  esac
done
if [ -z "${NIGHTLY_SKIP_SETUP:-}" ]; then
  scripts/setup.sh --peers
  scripts/fetch-corpus.sh
fi
# One build of everything (separate builds of mesher alone would rebuild it with other
# dependency features); if the mesher does not build, the peers still run (ours missing).
cargo build --release -q -p harness -p mesher -p reference --bins || {
  echo "nightly: mesher does not build; ours will be missing" >&2
  cargo build --release -q -p harness -p reference --bins
}
H=target/release/harness
out="reports/nightly/$date"
started=$SECONDS
# The fastest of 3 runs of each quick (model, mesher): the timing ratios of the
# sub-second rows are otherwise mostly the machine's noise (an explicit --repeat wins).
repeat=(--repeat 3)
case " ${extra[*]} " in *" --repeat"*) repeat=() ;; esac
$H run --corpus nightly "${repeat[@]}" --out "$out/run" "${resume[@]}" "${extra[@]}"
$H history "$out/run" --history reports/history.csv --date "$date"
$H report "$out/run" --out "$out" --history reports/history.csv >/dev/null
# A PNG of the report (headless Chromium, when installed), to look at without a browser.
chromium_bin="$(command -v chromium || command -v chromium-browser || true)"
if [ -n "$chromium_bin" ]; then
  profile="$(mktemp -d)"
  timeout 180 "$chromium_bin" --headless --no-sandbox --disable-gpu \
    --disable-background-networking --disable-component-update --disable-sync \
    --no-first-run --hide-scrollbars --window-size=1400,"${NIGHTLY_PNG_HEIGHT:-9000}" \
    --user-data-dir="$profile" --screenshot="$root/$out/index.png" \
    "file://$root/$out/index.html" >/dev/null 2>&1 ||
    echo "nightly: chromium wrote no screenshot" >&2
  rm -rf "$profile"
fi
echo "nightly: $((SECONDS - started)) s; open $out/index.html" >&2

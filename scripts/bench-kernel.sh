#!/usr/bin/env bash
# Delaunay kernel vs CGAL and TetGen on N uniform random points, in one run.
#
# Usage: scripts/bench-kernel.sh [N=1000000]
# Env:   SEED (default 20240601), BENCH_TIMEOUT seconds per peer (default 1800),
#        KEEP=1 keeps the scratch directory, PYTHON (default python3),
#        MESHER_BIN=path uses that mesher binary instead of building target/release/mesher.
#
# Each peer runs once under /usr/bin/time -v (wall clock, peak RSS):
#   ours   target/release/mesher delaunay pts.node --stats   (JSON: points, tets, insert_seconds)
#   cgal   target/release/cgal-dt3 pts.node                   (JSON: finite_tets, insert_seconds)
#   tetgen tetgen -NEFI pts.node  (no -p: Delaunay of the points; writes no files;
#                                  its "Delaunay seconds" is the insert time)
# A peer that is missing or fails is recorded as such; the others still run.
# Prints a table and writes reports/out/bench-kernel.json.
set -euo pipefail

n="${1:-1000000}"
seed="${SEED:-20240601}"
timeout_s="${BENCH_TIMEOUT:-1800}"
python="${PYTHON:-python3}"
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
out_dir="$root/reports/out"
out_json="$out_dir/bench-kernel.json"
mkdir -p "$out_dir"

case "$n" in
  '' | *[!0-9]*) echo "bench-kernel: N must be a positive integer, got '$n'" >&2; exit 2 ;;
esac
[ -x /usr/bin/time ] || { echo "bench-kernel: /usr/bin/time missing (apt-get install time; see scripts/setup.sh)" >&2; exit 2; }

work="$(mktemp -d "${TMPDIR:-/tmp}/bench-kernel.XXXXXX")"
if [ "${KEEP:-0}" = 1 ]; then
  echo "bench-kernel: scratch kept in $work"
else
  trap 'rm -rf "$work"' EXIT
fi

echo "bench-kernel: building release binaries"
cd "$root"
cargo build --release -q -p reference --bins
# The mesher is developed elsewhere; a build failure only disables "ours".
mesher_built=1
if [ -n "${MESHER_BIN:-}" ]; then
  echo "bench-kernel: using MESHER_BIN=$MESHER_BIN"
elif ! cargo build --release -q -p mesher --bin mesher 2>"$work/mesher-build.err"; then
  mesher_built=0
  echo "bench-kernel: mesher does not build (see below); ours will be skipped" >&2
  tail -n 20 "$work/mesher-build.err" >&2 || true
fi
bin="$root/target/release"
mesher="${MESHER_BIN:-$bin/mesher}"

load_before="$(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null || echo unknown)"
echo "bench-kernel: generating $n points (seed $seed)"
pts="$work/pts.node"
"$bin/random-points" "$n" --seed "$seed" -o "$pts"

# run_peer NAME DIR CMD...: runs CMD in DIR; stdout, stderr, time -v report
# and exit status go to $work/NAME.{out,err,time,rc}. Never fails the script.
run_peer() {
  local name="$1" dir="$2"
  shift 2
  echo "bench-kernel: running $name: $*"
  local rc=0 t0 t1
  t0="$(date +%s.%N)"
  (cd "$dir" && timeout "$timeout_s" /usr/bin/time -v -o "$work/$name.time" "$@" \
    >"$work/$name.out" 2>"$work/$name.err") || rc=$?
  t1="$(date +%s.%N)"
  echo "$rc" >"$work/$name.rc"
  # time -v prints wall clock to 10 ms only; keep a finer one of our own.
  echo "$t0 $t1" >"$work/$name.wall"
  if [ "$rc" -ne 0 ]; then
    echo "bench-kernel: $name exited with status $rc" >&2
    tail -n 5 "$work/$name.err" >&2 || true
  fi
}

# (a) ours: only if the CLI has a `delaunay` subcommand.
ours_status=absent
if [ "$mesher_built" = 1 ] && [ -x "$mesher" ] &&
  "$mesher" delaunay --help >"$work/ours.help" 2>&1 && [ -s "$work/ours.help" ]; then
  run_peer ours "$work" "$mesher" delaunay "$pts" --stats
  ours_status=ran
else
  echo "ours: not available ($mesher has no 'delaunay' subcommand yet)"
fi

# (b) CGAL
run_peer cgal "$work" "$bin/cgal-dt3" "$pts"

# (c) TetGen, in its own directory (it names outputs after the input).
tg_status=ran
if command -v tetgen >/dev/null 2>&1; then
  mkdir -p "$work/tetgen"
  ln -s "$pts" "$work/tetgen/pts.node"
  run_peer tetgen "$work/tetgen" tetgen -NEFI pts.node
else
  tg_status=absent
  echo "tetgen: not available (apt-get install tetgen; see scripts/setup.sh)"
fi

commit="$(git -C "$root" rev-parse --short HEAD 2>/dev/null || echo unknown)"
load_after="$(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null || echo unknown)"
"$python" - "$work" "$out_json" "$n" "$seed" "$commit" "$ours_status" "$tg_status" "$load_before" "$load_after" <<'PY'
import json, os, re, sys, time, platform

work, out_json, n, seed, commit, ours_status, tg_status, load_before, load_after = sys.argv[1:10]
n, seed = int(n), int(seed)

def read(path):
    try:
        with open(path, errors="replace") as f:
            return f.read()
    except OSError:
        return None

def time_v(name):
    """Wall seconds and peak RSS (MiB) from a /usr/bin/time -v report."""
    text = read(os.path.join(work, name + ".time")) or ""
    wall = rss = None
    m = re.search(r"Elapsed \(wall clock\) time.*?:\s*(?:(\d+):)?(\d+):([\d.]+)\s*$", text, re.M)
    if m:
        h, mi, s = m.groups()
        wall = int(h or 0) * 3600 + int(mi) * 60 + float(s)
    m = re.search(r"Maximum resident set size \(kbytes\):\s*(\d+)", text)
    if m:
        rss = int(m.group(1)) / 1024.0
    return wall, rss

def json_line(text):
    for line in reversed((text or "").splitlines()):
        line = line.strip()
        if line.startswith("{"):
            try:
                return json.loads(line)
            except ValueError:
                pass
    return None

def peer(name, status, parse):
    rec = {"peer": name, "status": status, "wall_seconds": None, "insert_seconds": None,
           "peak_rss_mib": None, "tets": None, "points": None}
    if status != "ran":
        return rec
    rc = (read(os.path.join(work, name + ".rc")) or "").strip()
    rec["exit_status"] = int(rc) if rc.lstrip("-").isdigit() else None
    rec["wall_seconds"], rec["peak_rss_mib"] = time_v(name)
    try:
        t0, t1 = map(float, (read(os.path.join(work, name + ".wall")) or "").split())
        rec["wall_seconds"] = t1 - t0
    except ValueError:
        pass
    out = read(os.path.join(work, name + ".out"))
    try:
        parse(rec, out)
    except Exception as e:  # a peer's odd output must not sink the report
        rec["parse_error"] = repr(e)
    ok = rec["exit_status"] == 0 and rec["tets"] is not None
    rec["status"] = "ok" if ok else ("timeout" if rec["exit_status"] == 124 else "failed")
    if not ok:
        err = read(os.path.join(work, name + ".err")) or ""
        rec["stderr_tail"] = err.strip().splitlines()[-5:]
    return rec

def parse_ours(rec, out):
    j = json_line(out)
    if j:
        rec["points"] = j.get("points")
        rec["tets"] = j.get("tets", j.get("finite_tets"))
        rec["insert_seconds"] = j.get("insert_seconds")

def parse_cgal(rec, out):
    j = json_line(out)
    if j:
        rec["points"] = j.get("points")
        rec["tets"] = j.get("finite_tets")
        rec["insert_seconds"] = j.get("insert_seconds")
        rec["vertices"] = j.get("vertices")

def parse_tetgen(rec, out):
    out = out or ""
    m = re.search(r"Delaunay seconds:\s*([\d.eE+-]+)", out)
    rec["insert_seconds"] = float(m.group(1)) if m else None
    m = re.search(r"Mesh tetrahedra:\s*(\d+)", out)
    rec["tets"] = int(m.group(1)) if m else None
    m = re.search(r"Mesh points:\s*(\d+)", out)
    rec["vertices"] = int(m.group(1)) if m else None
    m = re.search(r"Input points:\s*(\d+)", out)
    rec["points"] = int(m.group(1)) if m else None
    m = re.search(r"Total running seconds:\s*([\d.eE+-]+)", out)
    rec["total_seconds_self"] = float(m.group(1)) if m else None

peers = [peer("ours", ours_status, parse_ours),
         peer("cgal", "ran", parse_cgal),
         peer("tetgen", tg_status, parse_tetgen)]
by = {p["peer"]: p for p in peers}

def ratio(a, b):
    return a / b if isinstance(a, (int, float)) and isinstance(b, (int, float)) and b > 0 else None

o, c, t = by["ours"], by["cgal"], by["tetgen"]
ok = lambda p: p["status"] == "ok"
ratios = {
    "insert_time_ours_over_cgal": ratio(o["insert_seconds"], c["insert_seconds"]) if ok(o) and ok(c) else None,
    "wall_time_ours_over_cgal": ratio(o["wall_seconds"], c["wall_seconds"]) if ok(o) and ok(c) else None,
    "peak_rss_ours_over_cgal": ratio(o["peak_rss_mib"], c["peak_rss_mib"]) if ok(o) and ok(c) else None,
    "throughput_ours_over_cgal": ratio(c["insert_seconds"], o["insert_seconds"]) if ok(o) and ok(c) else None,
}
tet_counts = {p["peer"]: p["tets"] for p in peers if ok(p)}
agree = len(set(tet_counts.values())) == 1 if len(tet_counts) >= 2 else None

report = {
    "bench": "kernel",
    "points": n, "seed": seed, "commit": commit,
    "date_utc": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
    "host": {"cpus": os.cpu_count(), "machine": platform.machine(), "system": platform.platform(),
             "loadavg_before": load_before, "loadavg_after": load_after},
    "peers": peers, "ratios": ratios,
    "tet_counts_agree": agree,
}
with open(out_json, "w") as f:
    json.dump(report, f, indent=2)
    f.write("\n")

def fmt(v, spec):
    """format(v, spec), or a dash padded to the same width when v is unknown."""
    if v is None:
        width = re.match(r"\d*", spec).group(0)
        return format("-", ">" + width) if width else "-"
    return format(v, spec)

print()
print(f"Delaunay kernel, {n} uniform random points in the unit cube (seed {seed}, commit {commit})")
print(f"{'peer':<8} {'status':<14} {'wall s':>8} {'insert s':>9} {'RSS MiB':>9} {'tets':>10}")
for p in peers:
    status = "not available" if p["status"] == "absent" else p["status"]
    print(f"{p['peer']:<8} {status:<14} {fmt(p['wall_seconds'], '8.3f')} {fmt(p['insert_seconds'], '9.3f')}"
          f" {fmt(p['peak_rss_mib'], '9.1f')} {fmt(p['tets'], '10d')}")
print()
print("ours / CGAL:  insert time " + fmt(ratios["insert_time_ours_over_cgal"], ".2f")
      + ",  wall time " + fmt(ratios["wall_time_ours_over_cgal"], ".2f")
      + ",  peak RSS " + fmt(ratios["peak_rss_ours_over_cgal"], ".2f")
      + ",  throughput (CGAL insert s / ours insert s) " + fmt(ratios["throughput_ours_over_cgal"], ".2f"))
if agree is None:
    print("tet counts: fewer than two peers succeeded, nothing to compare")
else:
    print("tet counts " + ("agree" if agree else "DIFFER") + ": "
          + ", ".join(f"{k} {v}" for k, v in tet_counts.items()))
print(f"load average (1/5/15 min) before {load_before}, after {load_after}; {os.cpu_count()} CPUs")
print(f"JSON: {out_json}")
PY

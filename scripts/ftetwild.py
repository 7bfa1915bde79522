#!/usr/bin/env python3
"""Tetrahedralise a closed surface with fTetWild through pytetwild.

Called by the harness runner `harness/src/runners/ftetwild.rs`, which builds the command
line and runs it in a scratch folder (pytetwild writes `__tracked_surface.stl` into the
working directory):

    ftetwild.py --input domain.json --output out.mesh --meta meta.json --edge-length H [--sized]

`domain.json` is the double-precision surface the Gmsh runner uses too (only
`vertices` and `triangles` are read: fTetWild finds the inside by winding number).
Options: edge_length_abs = H (the harness passes the mean input edge length), one thread,
with --sized also the background size field of `domain.json` (`background`: a tet mesh
with a size per vertex, pytetwild's bg_vertices / bg_tets / bg_values);
every other option at pytetwild's default (epsilon 1e-3 of the box, optimize, simplify).
fTetWild moves the boundary within its envelope. Its tets may come out negatively
oriented; they are written as returned and the harness normalises the orientation.
Output: Medit .mesh with full double precision; `meta.json` gets the version, options and
the seconds spent in tetrahedralize() alone.

Exit codes: 0 ok, 3 pytetwild not importable (peer missing), 1 any other failure.
"""
import argparse
import json
import sys
import time


def write_medit(path, v, t):
    with open(path, "w") as f:
        f.write("MeshVersionFormatted 2\nDimension 3\n")
        f.write(f"Vertices\n{len(v)}\n")
        for p in v:
            f.write(f"{p[0]!r} {p[1]!r} {p[2]!r} 0\n")
        f.write(f"Tetrahedra\n{len(t)}\n")
        for q in t:
            f.write(f"{q[0] + 1} {q[1] + 1} {q[2] + 1} {q[3] + 1} 0\n")
        f.write("End\n")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--input", required=True)
    ap.add_argument("--output", required=True)
    ap.add_argument("--meta", required=True)
    ap.add_argument("--edge-length", type=float, required=True)
    ap.add_argument("--sized", action="store_true", help="sizes from the domain's background")
    a = ap.parse_args()
    try:
        import numpy as np
        import pytetwild
    except ImportError as e:
        print(f"pytetwild not importable: {e}", file=sys.stderr)
        return 3
    with open(a.input) as f:
        dom = json.load(f)
    v = np.asarray(dom["vertices"], dtype=np.float64)
    t = np.asarray(dom["triangles"], dtype=np.int32)
    extra = {}
    if a.sized:
        bg = dom["background"]
        extra = {
            "bg_vertices": np.asarray(bg["vertices"], dtype=np.float64),
            "bg_tets": np.asarray(bg["tets"], dtype=np.int32),
            "bg_values": np.asarray(bg["values"], dtype=np.float64),
        }
    t0 = time.perf_counter()
    ov, ot = pytetwild.tetrahedralize(
        v, t, edge_length_abs=a.edge_length, num_threads=1, **extra
    )
    seconds = time.perf_counter() - t0
    write_medit(a.output, [tuple(map(float, p)) for p in ov], ot.tolist())
    meta = {
        "version": pytetwild.__version__,
        "edge_length_abs": a.edge_length,
        "num_threads": 1,
        "sized": a.sized,
        "mesh_seconds": seconds,
    }
    with open(a.meta, "w") as f:
        json.dump(meta, f)
    return 0


if __name__ == "__main__":
    sys.exit(main())

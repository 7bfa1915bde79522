#!/usr/bin/env python3
"""Surface measures with pymeshlab for the harness: the two-sided Hausdorff distance
between the input surface and a peer's output boundary (peers that move the boundary).

    surface_check.py --input in.off --output boundary.off --samples N

Prints JSON on stdout: {"hausdorff": max of both one-sided maxima, "mean": mean of the
one-sided means, "diag": bounding-box diagonal of the input, "relative": hausdorff / diag,
"pymeshlab": version}. Sampling: vertices, edges and faces of the sampled mesh, N samples
each way (pymeshlab's Hausdorff filter). Sampled, so a lower bound of the true distance
that tightens with N.

Exit codes: 0 ok, 3 pymeshlab not importable, 1 other failure.
"""
import argparse
import json
import sys


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--input", required=True)
    ap.add_argument("--output", required=True)
    ap.add_argument("--samples", type=int, default=100000)
    a = ap.parse_args()
    try:
        import pymeshlab
    except ImportError as e:
        print(f"pymeshlab not importable: {e}", file=sys.stderr)
        return 3
    ms = pymeshlab.MeshSet()
    ms.load_new_mesh(a.input)
    ms.load_new_mesh(a.output)
    opts = dict(samplevert=True, sampleedge=True, sampleface=True, samplenum=a.samples)
    ab = ms.get_hausdorff_distance(sampledmesh=0, targetmesh=1, **opts)
    ba = ms.get_hausdorff_distance(sampledmesh=1, targetmesh=0, **opts)
    h = max(ab["max"], ba["max"])
    diag = ab["diag_mesh_0"]
    out = {
        "hausdorff": h,
        "mean": 0.5 * (ab["mean"] + ba["mean"]),
        "diag": diag,
        "relative": h / diag if diag > 0 else None,
        "pymeshlab": getattr(pymeshlab, "__version__", "unknown"),
    }
    json.dump(out, sys.stdout)
    return 0


if __name__ == "__main__":
    sys.exit(main())

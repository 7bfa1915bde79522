#!/usr/bin/env python3
"""Independent numpy computation of Q_K and the smallest dihedral angle of every tet of
a TetGen mesh (`base.node` / `base.ele`), for the cross-check in runners_peers.rs.

    quality_numpy.py BASE   -> JSON {"q_k": [...], "min_dihedral_deg": [...]} on stdout

Q_K = (sqrt(6)/12) * h_max / rho, rho = 3 V / (sum of face areas) (paper §6.1).
Dihedral angle at edge (i, j): the angle between the other two vertices projected onto
the plane orthogonal to the edge (not via face normals, unlike mesher::quality).
"""
import json
import sys

import numpy as np


def load(path, cols):
    rows = []
    with open(path) as f:
        lines = [l.split("#")[0].split() for l in f]
    lines = [l for l in lines if l]
    n = int(lines[0][0])
    for l in lines[1 : n + 1]:
        rows.append([float(x) for x in l[1 : 1 + cols]])
    return np.array(rows), int(lines[1][0])


def main():
    base = sys.argv[1]
    pts, first = load(base + ".node", 3)
    tets, _ = load(base + ".ele", 4)
    tets = tets.astype(np.int64) - first
    p = pts[tets]  # (n, 4, 3)
    edges = [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)]
    hmax = np.max([np.linalg.norm(p[:, j] - p[:, i], axis=1) for i, j in edges], axis=0)
    vol = np.abs(np.einsum("ij,ij->i", p[:, 1] - p[:, 0], np.cross(p[:, 2] - p[:, 0], p[:, 3] - p[:, 0]))) / 6
    faces = [(1, 2, 3), (0, 2, 3), (0, 1, 3), (0, 1, 2)]
    area = sum(0.5 * np.linalg.norm(np.cross(p[:, b] - p[:, a], p[:, c] - p[:, a]), axis=1) for a, b, c in faces)
    rho = 3 * vol / area
    q_k = np.sqrt(6) / 12 * hmax / rho
    angles = []
    for i, j in edges:
        k, l = [m for m in range(4) if m not in (i, j)]
        e = p[:, j] - p[:, i]
        e = e / np.linalg.norm(e, axis=1)[:, None]
        u = p[:, k] - p[:, i]
        w = p[:, l] - p[:, i]
        u = u - np.einsum("ij,ij->i", u, e)[:, None] * e
        w = w - np.einsum("ij,ij->i", w, e)[:, None] * e
        c = np.einsum("ij,ij->i", u, w) / (np.linalg.norm(u, axis=1) * np.linalg.norm(w, axis=1))
        angles.append(np.degrees(np.arccos(np.clip(c, -1, 1))))
    json.dump({"q_k": q_k.tolist(), "min_dihedral_deg": np.min(angles, axis=0).tolist()}, sys.stdout)


if __name__ == "__main__":
    main()

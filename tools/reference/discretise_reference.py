#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""High-precision ZOH / FOH reference for `flexloop discretise` (issue 17, case 1).

Reads a continuous state-space JSON (as written by `flexloop linearise`), forms the augmented
matrices of plant/lti/discretise.hpp from the exact double values of A, B and T = 1/rate (the
products are exact at this precision), takes their exponential with mpmath at --dps digits
(Taylor with scaling and squaring, no balancing: an algorithm independent of flexloop's) and
prints the discrete matrices' relative errors of a `flexloop discretise` output, and of
scipy.linalg.expm as a cross-check.

  /usr/bin/python3 tools/reference/discretise_reference.py CONT.json --rate 1000 --method zoh \
      --compare DISC.json [--dps 60]

Errors are ||X - X_ref||_F / ||X_ref||_F per matrix, and the largest column error relative to
that column's norm for Ad ("worst column"). Needs python3-mpmath, python3-numpy, python3-scipy.
"""
import argparse
import json
import sys

import mpmath
import numpy as np


def augmented(A, B, T, method):
    """The matrix whose exponential holds the discretisation (discretise.hpp), entries exact."""
    n, m = len(A), len(B[0]) if B else 0
    size = n + m if method == "zoh" else n + 2 * m
    M = mpmath.zeros(size, size)
    for i in range(n):
        for j in range(n):
            M[i, j] = mpmath.mpf(A[i][j]) * T
        for j in range(m):
            M[i, n + j] = mpmath.mpf(B[i][j]) * T
    if method == "foh":
        for j in range(m):
            M[n + j, n + m + j] = 1
    return M, n, m


def discrete(E, C, D, n, m, method):
    """Ad, Bd, Cd, Dd from the exponential E (mpmath matrix); FOH with the shifted state."""
    phi = E[0:n, 0:n]
    g1 = E[0:n, n:n + m]
    if method == "zoh":
        return phi, g1, C, D
    g2 = E[0:n, n + m:n + 2 * m]
    bd = g1 + (phi - mpmath.eye(n)) * g2
    dd = D + C * g2
    return phi, bd, C, dd


def to_mp(rows, r, c):
    M = mpmath.zeros(r, c)
    for i in range(r):
        for j in range(c):
            M[i, j] = mpmath.mpf(rows[i][j])
    return M


def frob_rel(x, ref):
    """||x - ref||_F / ||ref||_F, x a numpy array, ref an mpmath matrix."""
    num = mpmath.mpf(0)
    den = mpmath.mpf(0)
    for i in range(ref.rows):
        for j in range(ref.cols):
            num += (mpmath.mpf(float(x[i][j])) - ref[i, j]) ** 2
            den += ref[i, j] ** 2
    return float(mpmath.sqrt(num / den)) if den else float(mpmath.sqrt(num))


def worst_column(x, ref):
    worst = 0.0
    for j in range(ref.cols):
        num = sum((mpmath.mpf(float(x[i][j])) - ref[i, j]) ** 2 for i in range(ref.rows))
        den = sum(ref[i, j] ** 2 for i in range(ref.rows))
        if den:
            worst = max(worst, float(mpmath.sqrt(num / den)))
    return worst


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("continuous")
    p.add_argument("--rate", type=float, required=True, help="sample rate, Hz (T = 1/rate)")
    p.add_argument("--method", choices=["zoh", "foh"], default="zoh")
    p.add_argument("--compare", help="a `flexloop discretise` output to check")
    p.add_argument("--dps", type=int, default=60, help="mpmath decimal digits")
    p.add_argument("--write", help="write the reference Ad, Bd, Cd, Dd as JSON (17 digits)")
    a = p.parse_args()

    mpmath.mp.dps = a.dps
    c = json.load(open(a.continuous))
    A, B, C, D = c["A"], c["B"], c["C"], c["D"]
    n, m, ny = len(c["states"]), len(c["inputs"]), len(c["outputs"])
    T = mpmath.mpf(1.0 / a.rate)  # the double flexloop uses
    M, n, m = augmented(A, B, T, a.method)
    norm1 = max(sum(abs(M[i, j]) for i in range(M.rows)) for j in range(M.cols))
    print(f"{a.method} at {a.rate:g} Hz: n = {n}, m = {m}, ||A T|| (1-norm of the augmented "
          f"matrix) = {float(norm1):.3g}")
    E = mpmath.expm(M)
    ref = discrete(E, to_mp(C, ny, n), to_mp(D, ny, m), n, m, a.method)
    names = ("Ad", "Bd", "Cd", "Dd")

    Mf = np.array([[float(M[i, j]) for j in range(M.cols)] for i in range(M.rows)])
    try:
        import scipy.linalg
        Es = scipy.linalg.expm(Mf)
        Em = mpmath.matrix(Es.tolist())
        sc = discrete(Em, to_mp(C, ny, n), to_mp(D, ny, m), n, m, a.method)
        fl = [np.array([[float(x[i, j]) for j in range(x.cols)] for i in range(x.rows)])
              for x in sc]
        print("scipy.linalg.expm vs mpmath: " +
              ", ".join(f"{k} {frob_rel(x, r):.2e}" for k, x, r in zip(names, fl, ref)) +
              f"; Ad worst column {worst_column(fl[0], ref[0]):.2e}")
    except ImportError:
        print("scipy not available: no cross-check")

    if a.compare:
        d = json.load(open(a.compare))
        got = [d["Ad"], d["Bd"], d["Cd"], d["Dd"]]
        print("flexloop vs mpmath:          " +
              ", ".join(f"{k} {frob_rel(x, r):.2e}" for k, x, r in zip(names, got, ref)) +
              f"; Ad worst column {worst_column(got[0], ref[0]):.2e}")
    if a.write:
        out = {k: [[float(x[i, j]) for j in range(x.cols)] for i in range(x.rows)]
               for k, x in zip(names, ref)}
        out["made_by"] = (f"tools/reference/discretise_reference.py {a.continuous} --rate {a.rate:g}"
                          f" --method {a.method} --dps {a.dps} (mpmath {mpmath.__version__})")
        json.dump(out, open(a.write, "w"))
    return 0


if __name__ == "__main__":
    sys.exit(main())

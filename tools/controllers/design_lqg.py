#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""Design a discrete LQG controller for a flexloop loop and write it as a flexloop state-space
controller file (discrete form, doc/controllers.md).

The plant is the one the loop runs, read with flexloop's Python module (doc/python.md): a loop
artefact (`flexloop build SCENE -o LOOP.json`, flexloop.load) or a scene (flexloop.build):
    x+ = A x + B1 w + B2 u,   z = C1 x + D11 w + D12 u,   y = C2 x + D21 w + D22 u
with w the floor accelerations, u the actuator forces, z the performance outputs (the frame's
accelerations) and y the sensors. The controller is designed for that discrete plant, with the
sensors seeing the command of their own sample (y = C2 x + D22 u); flexloop's runtime removes the
command the sensors hold from the previous sample and solves that loop exactly
(controller/runtime/state_space_controller.hpp), so the design holds as it runs.

States the actuators cannot move -- a gravity-preloaded plant's floor states, the floor's
position and velocity, double integrators of the floor acceleration at z = 1 -- make the LQR's
Riccati equation unsolvable (the pair (A, B2) is not stabilisable). They are separated first:
  1. controllability staircase: an orthonormal basis V of the controllable subspace (the Krylov
     space of (A, B2), each step's rank by SVD) and Vu of its complement: in x = V xc + Vu xu the
     plant is block triangular, xu+ = Auu xu + B1u w, untouched by u;
  2. the coupling Acu of the floor into the rest is removed by xr = xc - Pi xu, with Pi solving
     the Sylvester equation Acc Pi - Pi Auu + Acu = 0 (Acc and Auu share no eigenvalue): xr and
     xu are then two separate systems driven by w, and xu reaches the outputs only through
     C_u = C Vu + C V Pi (the frame's accelerations do not see the floor's position: C1_u = 0 to
     rounding; the force sensors do, under the preload);
  3. LQR on (Acc, Bc) with the performance outputs' weight (what u can change), u = -Kr xr;
  4. Kalman predictor on the detectable part: xr, and xu where the sensors see it (so that the
     floor's share of the measurement is not taken for the structure's); xu seen by no sensor is
     left out. u = -[Kr 0] xhat.
The controller's eigenvalues are those of Acc - Bc Kr and of the predictor; the plant's floor
states stay where they are (at z = 1: the floor's, not the loop's). A plant with no such states
is designed as before, on its own coordinates.

LQR: minimise sum of q |z|^2 + r |u|^2 with z = C1 x + D12 u (cross term included).
Kalman predictor: floor acceleration as white noise of variance w_var per channel through B1
(correlated with the sensors through D21), sensor noise of variance v_var.
Controller (a predictor: u_k depends on the estimate made before y_k arrives, so Dc = 0):
    xc+ = (A - B2 K - L C2 + L D22 K) xc + L y,   u = -K xc.

Example (the metrology frame; the shipped file tools/controllers/metrology_frame_lqg.json):
    flexloop build tools/scenes/metrology_frame.toml -o /tmp/metrology.json
    tools/controllers/design_lqg.py /tmp/metrology.json -o tools/controllers/metrology_frame_lqg.json
The module is found on PYTHONPATH, else beside an installed copy of this script
(PREFIX/lib/python3/dist-packages) or in this source tree's build/*/tools/python.
"""
import argparse
import glob
import json
import os
import pathlib
import sys

import numpy as np
import scipy.linalg

# Rank decisions of the staircase: a direction is reachable when its singular value is above
# this share of the scale (|B2| for the first step, |A - I| after). The metrology frame under
# gravity preload: reachable directions at 1e-4 of |A - I|, the floor's at 1e-30.
RANK_TOL = 1e-9


def import_flexloop():
    """flexloop's module: on PYTHONPATH, beside an installed copy of this script, or in this
    source tree's newest build."""
    try:
        import flexloop
        return flexloop
    except ImportError:
        pass
    here = pathlib.Path(__file__).resolve().parent
    candidates = [here.parents[2] / "lib" / "python3" / "dist-packages"]  # PREFIX/share/flexloop/..
    built = glob.glob(str(here.parents[1] / "build" / "*" / "tools" / "python" / "flexloop.*.so"))
    candidates += [pathlib.Path(f).parent for f in sorted(built, key=os.path.getmtime, reverse=True)]
    for folder in candidates:
        if list(folder.glob("flexloop.*.so")):
            sys.path.insert(0, str(folder))
            import flexloop
            return flexloop
    sys.exit("design_lqg.py: flexloop's Python module is not found: build it (target "
             "flexloop_python, Debian's pybind11-dev and python3-dev; doc/python.md) and put its "
             "folder on PYTHONPATH")


def controllable_basis(A, B):
    """Orthonormal bases (V, Vu) of the controllable subspace of (A, B) and of its complement:
    the Krylov space of (A - I, B) (the same space as of (A, B)), one block at a time, each new
    block projected off the space so far (twice) and its rank decided by SVD."""
    n = A.shape[0]
    U, s, _ = np.linalg.svd(B, full_matrices=False)
    rank = int(np.sum(s > RANK_TOL * s[0])) if s.size and s[0] > 0 else 0
    V = U[:, :rank]
    block = V
    shifted = A - np.eye(n)
    scale = max(np.linalg.norm(shifted, 2), np.finfo(float).tiny)
    while V.shape[1] < n and block.shape[1] > 0:
        W = shifted @ block
        for _ in range(2):
            W -= V @ (V.T @ W)
        U, s, _ = np.linalg.svd(W, full_matrices=False)
        block = U[:, :int(np.sum(s > RANK_TOL * scale))]
        V = np.hstack([V, block])
    return V, scipy.linalg.null_space(V.T) if V.shape[1] < n else np.zeros((n, 0))


def lqr(A, B2, C1, D12, q, r):
    """The LQR gain on z = C1 x + D12 u: q z'z + r u'u = x'Qx + 2 x'N u + u'Ru."""
    Q = q * C1.T @ C1
    N = q * C1.T @ D12
    R = q * D12.T @ D12 + r * np.eye(B2.shape[1])
    P = scipy.linalg.solve_discrete_are(A, B2, Q, R, s=N)
    return np.linalg.solve(R + B2.T @ P @ B2, B2.T @ P @ A + N.T)


def kalman(A, B1, C2, D21, w_var, v_var):
    """The Kalman predictor's gain, the floor's cross-correlation to the sensors through D21."""
    nw, ns = B1.shape[1], C2.shape[0]
    W = w_var * np.eye(nw)
    Qn = B1 @ W @ B1.T
    Rn = D21 @ W @ D21.T + v_var * np.eye(ns)
    Sn = B1 @ W @ D21.T
    S = scipy.linalg.solve_discrete_are(A.T, C2.T, Qn, Rn, s=Sn)
    return (A @ S @ C2.T + Sn) @ np.linalg.inv(C2 @ S @ C2.T + Rn)


def separate(A, B1, B2, C1, C2):
    """The plant in coordinates [xr; xu] (module docstring, steps 1-2): xr the controllable part
    freed of the floor's coupling, xu the part the actuators cannot move; xu is dropped where no
    sensor sees it. Returns the design plant (A, B1, B2, C1, C2), the names of its states and
    what was separated."""
    V, Vu = controllable_basis(A, B2)
    nr, nu = V.shape[1], Vu.shape[1]
    Acc, Acu, Auu = V.T @ A @ V, V.T @ A @ Vu, Vu.T @ A @ Vu
    Pi = scipy.linalg.solve_sylvester(Acc, -Auu, -Acu)
    C1u, C2u = C1 @ V @ Pi + C1 @ Vu, C2 @ V @ Pi + C2 @ Vu
    Br1 = V.T @ B1 - Pi @ (Vu.T @ B1)
    seen = np.linalg.norm(C2u) > RANK_TOL * max(np.linalg.norm(C2 @ V), np.finfo(float).tiny)
    keep = nu if seen else 0
    Ad = scipy.linalg.block_diag(Acc, Auu[:keep, :keep])
    B1d = np.vstack([Br1, (Vu.T @ B1)[:keep]])
    B2d = np.vstack([V.T @ B2, np.zeros((keep, B2.shape[1]))])
    C1d = np.hstack([C1 @ V, C1u[:, :keep]])
    C2d = np.hstack([C2 @ V, C2u[:, :keep]])
    names = [f"c{i + 1}" for i in range(nr)] + [f"floor{i + 1}" for i in range(keep)]
    info = {"controllable_states": nr, "uncontrollable_states": nu,
            "uncontrollable_in_the_predictor": keep,
            "uncontrollable_eigenvalues_abs_max": float(max(abs(np.linalg.eigvals(Auu)))),
            "uncontrollable_seen_by_performance": float(np.linalg.norm(C1u)),
            "uncontrollable_seen_by_sensors": float(np.linalg.norm(C2u))}
    return (Ad, B1d, B2d, C1d, C2d), nr, names, info


def design(loop, q, r, w_var, v_var):
    nw, nc = len(loop.disturbances), len(loop.actuators)
    nz = len(loop.performance)
    A, B, C, D = loop.A, loop.B, loop.C, loop.D
    B1, B2 = B[:, :nw], B[:, nw:]
    C1, C2 = C[:nz, :], C[nz:, :]
    D12, D21, D22 = D[:nz, nw:], D[nz:, :nw], D[nz:, nw:]
    names, info = [f"xhat:{s}" for s in loop.states], None
    V, _ = controllable_basis(A, B2)
    if V.shape[1] < A.shape[0]:  # states the actuators cannot move: design on the rest
        (A, B1, B2, C1, C2), nr, parts, info = separate(A, B1, B2, C1, C2)
        C1 = C1[:, :nr]  # the LQR weighs what u can change
        names = [f"xhat:{s}" for s in parts]
        K = np.hstack([lqr(A[:nr, :nr], B2[:nr], C1, D12, q, r),
                       np.zeros((nc, A.shape[0] - nr))])
    else:
        K = lqr(A, B2, C1, D12, q, r)
    try:
        L = kalman(A, B1, C2, D21, w_var, v_var)
    except (np.linalg.LinAlgError, ValueError) as e:
        sys.exit(f"design_lqg.py: no Kalman predictor: the sensors do not see enough of the "
                 f"plant (a state they miss on or outside the unit circle): {e}")
    Ac = A - B2 @ K - L @ C2 + L @ D22 @ K
    return Ac, L, -K, np.zeros((nc, C2.shape[0])), names, info


def read_loop(flexloop, path):
    """A loop artefact (JSON) or a scene (TOML, built as `flexloop build` builds it)."""
    try:
        return flexloop.build(path) if path.endswith(".toml") else flexloop.load(path)
    except flexloop.InputError as e:
        sys.exit(f"design_lqg.py: {e}")


def text(v):
    """JSON with one matrix row per line; repr() of a float round-trips exactly."""
    if isinstance(v, list) and v and isinstance(v[0], list):
        return "[\n    " + ",\n    ".join(json.dumps(row) for row in v) + "\n  ]"
    return json.dumps(v)


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("loop", help="loop artefact (flexloop build SCENE -o LOOP.json) or scene (TOML)")
    ap.add_argument("-o", "--output", required=True, help="controller file to write")
    ap.add_argument("--q", type=float, default=1.0, help="weight on |z|^2 [(m/s^2)^-2]")
    ap.add_argument("--r", type=float, default=1e-10, help="weight on |u|^2 [N^-2]")
    ap.add_argument("--floor-var", type=float, default=1e-6,
                    help="floor acceleration variance per channel and sample [(m/s^2)^2]")
    ap.add_argument("--sensor-var", type=float, default=4e-6,
                    help="sensor noise variance [N^2] (0.002 N RMS: 4e-6)")
    a = ap.parse_args()
    loop = read_loop(import_flexloop(), a.loop)
    Ac, Bc, Cc, Dc, names, separated = design(loop, a.q, a.r, a.floor_var, a.sensor_var)
    nx = Ac.shape[0]
    rho = float(max(abs(np.linalg.eigvals(Ac)))) if nx else 0.0
    provenance = {
        "tool": "tools/controllers/design_lqg.py",
        "loop": loop.name,
        "design": "discrete LQG: LQR on the performance outputs, Kalman predictor",
        "q": a.q, "r": a.r, "floor_var": a.floor_var, "sensor_var": a.sensor_var,
    }
    if separated:
        provenance["separated"] = separated
    out = {
        "method": loop.method,
        "dt": 1.0 / loop.rate_hz,
        "prewarp_hz": 0.0,
        "spectral_radius": rho,
        "states": names,
        "inputs": loop.sensors,
        "outputs": loop.actuators,
        "Ad": Ac.tolist(),
        "Bd": Bc.tolist(),
        "Cd": Cc.tolist(),
        "Dd": Dc.tolist(),
        "provenance": provenance,
    }
    body = ",\n".join(f"  {json.dumps(k)}: {text(v)}" for k, v in out.items())
    tmp = a.output + ".tmp"
    with open(tmp, "w") as f:
        f.write("{\n" + body + "\n}\n")
    os.replace(tmp, a.output)  # atomic: a reader never sees half a file
    note = ""
    if separated:
        note = (f"; {separated['uncontrollable_states']} states the actuators cannot move "
                f"separated ({separated['uncontrollable_in_the_predictor']} kept in the "
                f"predictor: the sensors see them)")
    print(f"wrote {a.output}: {nx} states, {len(out['inputs'])} sensors -> "
          f"{len(out['outputs'])} actuators, controller spectral radius {rho:.6f}{note}")


if __name__ == "__main__":
    main()

#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""Design a discrete LQG controller for a flexloop loop artefact and write it as a flexloop
state-space controller file (discrete form, doc/controllers.md).

The plant is the one the loop runs (`flexloop build SCENE -o LOOP.json` writes it):
    x+ = A x + B1 w + B2 u,   z = C1 x + D11 w + D12 u,   y = C2 x + D21 w + D22 u
with w the floor accelerations, u the actuator forces, z the performance outputs (the frame's
accelerations) and y the sensors. The controller is designed for that discrete plant, with the
sensors seeing the command of their own sample (y = C2 x + D22 u); flexloop's runtime removes the
command the sensors hold from the previous sample and solves that loop exactly
(controller/runtime/state_space_controller.hpp), so the design holds as it runs.

LQR: minimise sum of q |z|^2 + r |u|^2 with z = C1 x + D12 u (cross term included).
Kalman predictor: floor acceleration as white noise of variance w_var per channel through B1
(correlated with the sensors through D21), sensor noise of variance v_var.
Controller (a predictor: u_k depends on the estimate made before y_k arrives, so Dc = 0):
    xc+ = (A - B2 K - L C2 + L D22 K) xc + L y,   u = -K xc.

Example (the metrology frame; the shipped file tools/controllers/metrology_frame_lqg.json):
    flexloop build tools/scenes/metrology_frame.toml -o /tmp/metrology.json
    tools/controllers/design_lqg.py /tmp/metrology.json -o tools/controllers/metrology_frame_lqg.json
"""
import argparse
import json
import os
import sys

import numpy as np
import scipy.linalg


def design(loop, q, r, w_var, v_var):
    ch = loop["channels"]
    nw, nc = len(ch["disturbances"]), len(ch["actuators"])
    nz, ns = len(ch["performance"]), len(ch["sensors"])
    p = loop["plant"]
    A, B, C, D = (np.array(p[k], dtype=float) for k in "ABCD")
    nx = A.shape[0]
    B1, B2 = B[:, :nw], B[:, nw:]
    C1, C2 = C[:nz, :], C[nz:, :]
    D12, D21, D22 = D[:nz, nw:], D[nz:, :nw], D[nz:, nw:]

    # LQR on z = C1 x + D12 u: q z'z + r u'u = x'Qx + 2 x'N u + u'Ru.
    Q = q * C1.T @ C1
    N = q * C1.T @ D12
    R = q * D12.T @ D12 + r * np.eye(nc)
    P = scipy.linalg.solve_discrete_are(A, B2, Q, R, s=N)
    K = np.linalg.solve(R + B2.T @ P @ B2, B2.T @ P @ A + N.T)

    # Kalman predictor with the floor's cross-correlation to the sensors (through D21).
    W = w_var * np.eye(nw)
    Qn = B1 @ W @ B1.T
    Rn = D21 @ W @ D21.T + v_var * np.eye(ns)
    Sn = B1 @ W @ D21.T
    S = scipy.linalg.solve_discrete_are(A.T, C2.T, Qn, Rn, s=Sn)
    L = (A @ S @ C2.T + Sn) @ np.linalg.inv(C2 @ S @ C2.T + Rn)

    Ac = A - B2 @ K - L @ C2 + L @ D22 @ K
    return Ac, L, -K, np.zeros((nc, ns)), nx


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("loop", help="loop artefact (flexloop build SCENE -o LOOP.json)")
    ap.add_argument("-o", "--output", required=True, help="controller file to write")
    ap.add_argument("--q", type=float, default=1.0, help="weight on |z|^2 [(m/s^2)^-2]")
    ap.add_argument("--r", type=float, default=1e-10, help="weight on |u|^2 [N^-2]")
    ap.add_argument("--floor-var", type=float, default=1e-6,
                    help="floor acceleration variance per channel and sample [(m/s^2)^2]")
    ap.add_argument("--sensor-var", type=float, default=4e-6,
                    help="sensor noise variance [N^2] (0.002 N RMS: 4e-6)")
    a = ap.parse_args()
    with open(a.loop) as f:
        loop = json.load(f)
    if loop.get("format") != "flexloop loop artefact":
        sys.exit(f"{a.loop}: not a flexloop loop artefact (flexloop build SCENE -o LOOP.json)")
    Ac, Bc, Cc, Dc, nx = design(loop, a.q, a.r, a.floor_var, a.sensor_var)
    rho = float(max(abs(np.linalg.eigvals(Ac)))) if nx else 0.0
    ch = loop["channels"]
    out = {
        "method": loop["method"],
        "dt": 1.0 / loop["rate_hz"],
        "prewarp_hz": 0.0,
        "spectral_radius": rho,
        "states": [f"xhat:{s}" for s in loop["plant"]["states"]],
        "inputs": [c["name"] for c in ch["sensors"]],
        "outputs": [c["name"] for c in ch["actuators"]],
        "Ad": Ac.tolist(),
        "Bd": Bc.tolist(),
        "Cd": Cc.tolist(),
        "Dd": Dc.tolist(),
        "provenance": {
            "tool": "tools/controllers/design_lqg.py",
            "loop": loop.get("name", ""),
            "design": "discrete LQG: LQR on the performance outputs, Kalman predictor",
            "q": a.q, "r": a.r, "floor_var": a.floor_var, "sensor_var": a.sensor_var,
        },
    }
    # One matrix row per line; repr() of a float round-trips exactly.
    def text(v):
        if isinstance(v, list) and v and isinstance(v[0], list):
            return "[\n    " + ",\n    ".join(json.dumps(row) for row in v) + "\n  ]"
        return json.dumps(v)
    body = ",\n".join(f"  {json.dumps(k)}: {text(v)}" for k, v in out.items())
    tmp = a.output + ".tmp"
    with open(tmp, "w") as f:
        f.write("{\n" + body + "\n}\n")
    os.replace(tmp, a.output)  # atomic: a reader never sees half a file
    print(f"wrote {a.output}: {nx} states, {len(out['inputs'])} sensors -> "
          f"{len(out['outputs'])} actuators, controller spectral radius {rho:.6f}")


if __name__ == "__main__":
    main()

#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""Writes the continuous state space of a stiff spring-mass chain (issue 17, case 1 fixture).

Four masses on a soft suspension (about 2 Hz) joined by stiff undamped struts whose top mode is
near 47 kHz (47 x the rate), so at 1 kHz ||A T||_1 = 9.5e7 in SI units (position m, velocity m/s).
Inputs: forces on the first and last mass; outputs: last position, first velocity (D has one
non-zero entry so that FOH's Dd = D + C Gamma2 is checked too).

  /usr/bin/python3 tools/reference/make_stiff_chain.py tests/discretise/fixtures/stiff_chain.json
  for m in zoh foh; do /usr/bin/python3 tools/reference/discretise_reference.py \
      tests/discretise/fixtures/stiff_chain.json --rate 1000 --method $m --dps 60 \
      --write tests/discretise/fixtures/stiff_chain_$m.json; done
"""
import json
import math
import sys

masses = [0.4, 1.0, 0.25, 2.0]
suspension = 2.0 * math.pi * 2.0  # rad/s, first mass to ground
strut = 1.0e10  # N/m, each of the three struts
n = len(masses)

K = [[0.0] * n for _ in range(n)]
K[0][0] += sum(masses) * suspension**2
for i in range(n - 1):
    K[i][i] += strut
    K[i + 1][i + 1] += strut
    K[i][i + 1] -= strut
    K[i + 1][i] -= strut

A = [[0.0] * (2 * n) for _ in range(2 * n)]
for i in range(n):
    A[i][n + i] = 1.0
    for j in range(n):
        A[n + i][j] = -K[i][j] / masses[i]
B = [[0.0, 0.0] for _ in range(2 * n)]
B[n][0] = 1.0 / masses[0]
B[2 * n - 1][1] = 1.0 / masses[-1]
C = [[0.0] * (2 * n) for _ in range(2)]
C[0][n - 1] = 1.0
C[1][n] = 1.0
D = [[0.0, 0.0], [0.5, 0.0]]

doc = {
    "states": [f"x{i + 1}" for i in range(2 * n)],
    "inputs": ["u1", "u2"],
    "outputs": ["y1", "y2"],
    "A": A,
    "B": B,
    "C": C,
    "D": D,
}
with open(sys.argv[1], "w") as f:
    json.dump(doc, f, indent=1)

#!/usr/bin/env bash
# PI force feedback per strut on box8 (tests/fixtures/box8.toml: 8 struts, 6 degrees of freedom):
# `flexloop analyse` accepts the scene, designs one loop per strut, its closed loop is stable
# (continuous and sampled), every mode is damped more than open loop, and its closed-loop poles
# are those of an independent model (a rigid body on eight axial springs, numpy) closed by the
# printed gains. A scene whose sensor 8 is not actuator 8's force sensor exits 2 at that entry.
# SPDX-License-Identifier: BSD-3-Clause
set -uo pipefail
flexloop=$1
root=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
checks=0

out=$("$flexloop" analyse "$root/tests/fixtures/box8.toml" --points 50 --out-dir "$tmp/an" 2>&1); rc=$?
[[ $rc -eq 0 ]] || fail "analyse box8: exit $rc ($out)"
[[ "$out" == *"designed per strut (8 collocated struts)"* ]] || fail "no per-strut design printed: $out"
checks=$((checks + 1))

/usr/bin/python3 - "$tmp/an/analysis.json" "$root/tests/fixtures/box8_model.toml" <<'PY' || fail "box8's closed loop"
import json, math, sys, tomllib
import numpy as np
j = json.load(open(sys.argv[1]))
assert j["closed_loop_stable"] and j["continuous_loop_stable"] and j["sampled_loop"]["stable"], "unstable"
KP, KI = np.array(j["K_P"]), np.array(j["K_I"])
assert KP.shape == (8, 8) and np.array_equal(KP, np.diag(np.diag(KP))), "K_P is not diagonal"
# Damping per mode: open loop from the plant's A (the floor's integrator states at s = 0 left
# out), closed loop from analyse's poles (its integrators left out).
def zetas(poles):
    scale = max(abs(p) for p in poles)
    return [-p.real / abs(p) for p in poles if abs(p) > 1e-9 * scale]
open_poles = np.linalg.eigvals(np.array(j["open_loop"]["A"]))
closed = [complex(re, im) for re, im in j["closed_loop_poles"]]
zo, zc = zetas(open_poles), zetas(closed)
assert len(zo) == 12 and len(zc) == 14, (len(zo), len(zc))
assert max(zo) < 0.01 and min(zc) > 10 * max(zo), (max(zo), min(zc))
# The independent model: rigid payload at its centre of gravity, strut i along n_i (floor to
# mount) at r_i from it, a_i = [n_i; r_i x n_i]; M x'' = -A sigma_1, sigma_1 = sigma_a + k e + d e',
# e = A^T x, sigma_a = -(K_P sigma_1 + K_I xi), xi' = sigma_1 - w_l xi (w_l = 0 here).
m = tomllib.load(open(sys.argv[2], "rb"))
nodes = {n["id"]: n for n in m["node"]}
P = nodes["P"]; cg = np.array(P["position"])
M = np.diag([P["mass"]] * 3 + P["inertia"])
struts = {e["id"]: e for e in m["element"] if e["type"] == "truss"}
names = [a.split(".", 1)[1] for a in j["controller"]["outputs"]]
A, k, d = [], [], []
for name in names:
    e = struts[name]
    mount, floor = (np.array(nodes[i]["position"]) for i in e["nodes"])
    n = (mount - floor) / np.linalg.norm(mount - floor)
    A.append(np.concatenate([n, np.cross(mount - cg, n)])); k.append(e["stiffness"]); d.append(e["damping"])
A = np.array(A).T; k = np.array(k); d = np.array(d)
Minv = np.linalg.inv(M)
E = np.linalg.inv(np.eye(8) + KP)
Sx, Sv, Sxi = E @ np.diag(k) @ A.T, E @ np.diag(d) @ A.T, -E @ KI
Acl = np.block([[np.zeros((6, 6)), np.eye(6), np.zeros((6, 8))],
                [-Minv @ A @ Sx, -Minv @ A @ Sv, -Minv @ A @ Sxi],
                [Sx, Sv, Sxi]])
ref = np.linalg.eigvals(Acl)
scale = max(abs(ref))
worst = max(min(abs(r - c) for c in closed) for r in ref) / scale
assert worst < 1e-9, f"closed-loop poles differ from the rigid-body model by {worst:.2e} of |s|max"
print(f"box8: open-loop damping <= {max(zo):.4f}, closed-loop >= {min(zc):.4f}; "
      f"poles = rigid-body model within {worst:.1e}")
PY
checks=$((checks + 1))

# Sensor 8 an accelerometer: actuator 8 has no collocated force sensor.
sed -e "s|^model = .*|model = \"$root/tests/fixtures/box8_model.toml\"|" \
    -e '/^sensors = /,/\]$/ s|"stress:e1.T3", "stress:e1.T4"\]$|"stress:e1.T3", "acc:z.M4"]|' \
  "$root/tests/fixtures/box8.toml" >"$tmp/box8.toml"
line=$(grep -n '"acc:z.M4"\]$' "$tmp/box8.toml" | cut -d: -f1)
[[ -n "$line" ]] || fail "the bad scene was not made"
out=$("$flexloop" analyse "$tmp/box8.toml" --out-dir "$tmp/bad" 2>&1); rc=$?
[[ $rc -eq 2 ]] || fail "a sensor that is not the actuator's own: exit $rc, not 2 ($out)"
[[ "$out" == *"$tmp/box8.toml:$line: [plant]: sensors entry 8 'acc:z.M4'"* &&
   "$out" == *"'stress:e1.T4'"* ]] || fail "the refusal does not name the file, line and entry: $out"
checks=$((checks + 1))

echo "pi per strut: $checks checks passed"

#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Write a flexible arm of any size: a 2 m steel cantilever (40 x 40 mm) in N planar beams on a
base that moves with the floor, two piezo struts from the floor to node 2, and its scene (VC-C
floor, force sensors, no controller), like tools/models/flexible_arm.toml (N = 25). With
--mass-model beam the beams carry their consistent mass with rotary inertia (2 N bending
coordinates, 4 N + 6 states); with lumped, the HRZ nodal rotary inertia of the shipped model.

Example (the 206-state plant of the sim figures in doc/performance.md):
  tools/models/make_flexible_arm.py --elements 50 --mass-model beam -o out/arm50
  flexloop sim out/arm50/scene.toml --duration 5
"""
import argparse
import os
import sys

E, A, I, RHO, LENGTH = 210e9, 0.0016, 0.04**4 / 12, 7850.0, 2.0


def model_text(n, mass_model):
    l = LENGTH / n
    element_mass = RHO * A * l
    out = [f'# Flexible arm, {n} planar beams, mass model {mass_model} '
           '(tools/models/make_flexible_arm.py)\n[model]\nname = "flexible_arm_'
           f'{n}"\ndimension = 2\n']
    for i in range(n + 1):
        out.append(f'[[node]]\nid = "{i}"\nposition = [{l * i!r}, 0.0]\nrotational = true\n')
        if mass_model == "lumped" and i > 0:  # HRZ: m_e l^2 / 78 per element end
            out.append(f"mass = {element_mass * (0.5 if i == n else 1.0)!r}\n")
            out.append(f"inertia = {element_mass * l * l / 78 * (1 if i == n else 2)!r}\n")
    out.append('[[node]]\nid = "Ga"\nposition = [0.08, -0.15]\n'
               '[[node]]\nid = "Gb"\nposition = [0.08, 0.15]\n')
    for k in range(1, n + 1):
        out.append(f'[[element]]\nid = "b{k}"\ntype = "planar_beam"\nnodes = ["{k - 1}", "{k}"]\n'
                   f"E = {E!r}\nA = {A!r}\nI = {I!r}\n"
                   + (f'rho = {RHO!r}\nmass_model = "beam"\n' if mass_model == "beam" else "")
                   + 'modes = ["rigid", "flexible", "flexible"]\n')
    strut_node = min(2, n)
    for s, ground in (("sa", "Ga"), ("sb", "Gb")):
        out.append(f'[[element]]\nid = "{s}"\ntype = "truss"\nnodes = ["{ground}", "{strut_node}"]\n'
                   "stiffness = 5.0e7\ndamping = 50.0\nactuator = true\n")
    dynamic = ", ".join(f'"e2.b{k}", "e3.b{k}"' for k in range(1, n + 1))
    out.append('[coordinates]\nfixed = ["x.0", "phi.0", "x.Ga", "x.Gb"]\n'
               f'dynamic = [{dynamic}]\nprescribed = ["y.0", "y.Ga", "y.Gb"]\n')
    return "".join(out)


def scene_text(n):
    return (f'[scene]\nname = "flexible_arm_{n}"\nmodel = "model.toml"\n'
            '[plant]\ndisturbances = ["acc:y.0", "acc:y.Ga", "acc:y.Gb"]\n'
            'actuators = ["stress:e1.sa", "stress:e1.sb"]\n'
            f'performance = ["acc:y.{n}", "acc:y.{n // 2}"]\n'
            'sensors = ["stress:e1.sa", "stress:e1.sb"]\n'
            '[controller]\ntype = "none"\n'
            '[discretisation]\nmethod = "zoh"\nrate_hz = 10000\n'
            '[floor]\nspectrum = "VC-C"\nseed = 1\n'
            '[effects.force_sensor]\nnoise_rms_n = 0.01\nadc_bits = 16\nadc_range_n = 1000.0\nseed = 2\n'
            '[run]\nduration_s = 5\n')


def main():
    p = argparse.ArgumentParser(description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--elements", type=int, default=25, help="beam elements (>= 2)")
    p.add_argument("--mass-model", choices=("beam", "lumped"), default="beam")
    p.add_argument("-o", "--out-dir", required=True, help="writes model.toml and scene.toml here")
    a = p.parse_args()
    if a.elements < 2:
        sys.exit("make_flexible_arm.py: --elements must be at least 2")
    try:
        os.makedirs(a.out_dir, exist_ok=True)
        for name, text in (("model.toml", model_text(a.elements, a.mass_model)),
                           ("scene.toml", scene_text(a.elements))):
            with open(os.path.join(a.out_dir, name), "w") as f:
                f.write(text)
    except OSError as e:
        sys.exit(f"make_flexible_arm.py: {a.out_dir}: cannot be written ({e.strerror})")
    print(f"wrote {a.out_dir}/model.toml and {a.out_dir}/scene.toml "
          f"({a.elements} beams, {4 * a.elements + 6} states)")


if __name__ == "__main__":
    main()

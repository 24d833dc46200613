#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""The lens support as a superelement (issue 58): a steel ring (lens_support.geo) meshed by
gmsh in tet10, exported by CalculiX (*FREQUENCY, SOLVER=MATRIXSTORAGE: K, M, the row map), and
a flexloop model and scene that hold it on six piezo struts, as the metrology frame's bipods:

  OUT/ring.inp, ring.sti, ring.mas, ring.dof   the deck and CalculiX's matrices
  OUT/lens_support.toml                        the model: [[superelement]] + six struts
  OUT/lens_support_scene.toml                  PI force feedback on the six struts
  OUT/ring_struts.inp, .dat (--reference N)    an outside reference: the whole machine in
                                               CalculiX (ring + six SPRINGA struts to held floor
                                               nodes), its N lowest frequencies by *FREQUENCY

The ring is free in the FE model (no boundary condition): its three mounts, the interface, hold
it. The mounts are at radius 0.25 m on the bottom face, at 90, 210 and 330 degrees; the points
above them on the top face are the interface too (performance channels).
Each bipod's two struts run 45 degrees from the vertical in the mount's tangential plane to
their floor nodes, from the interface point.

Each interface point is a rigid pad by default ([[superelement.pad]], RBE2): the face's mesh
nodes within 0.03 m of the point (a strut's foot, 60 mm across), the interface point at their
centroid; the reference deck holds them as *RIGID BODY (--pad-kind distributing: RBE3, and the
distributing pads' *EQUATION rows). --pads 0 makes each one mesh node (a pin), whose local
stiffness on a tet10 mesh, in series with the strut's, softens as the mesh is refined (a point
load on a solid): from --clmax 0.02 to 0.015 the six suspension modes moved up to 0.23 % with
pins (the first pair still falling), 0.06 % or less with rigid pads (doc/superelements.md).

  make_lens_support.py -o out/lens_support              # --clmax 0.02: 10 062 nodes, 30 186 DOFs
  make_lens_support.py --clmax 0.04 -o /tmp/ls            # coarse: seconds (the tests' mesh)
  make_lens_support.py --pads 0 -o out/lens_support       # six single-node interfaces (pins)
"""
import argparse
import math
import os
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from fe_deck import distributing_equations, gmsh_mesh, rigid_pad, write_deck  # noqa: E402

STEEL = (2.1e11, 0.3, 7850.0)  # E (Pa), nu, rho (kg/m^3)
MOUNT_RADIUS, THICKNESS = 0.25, 0.05
ANGLES_DEG = (90.0, 210.0, 330.0)
STRUT = {"stiffness": 2.0e7, "damping": 60.0, "length": 0.2}  # N/m, N s/m, m


def nearest(nodes, point):
    return min(nodes, key=lambda n: sum((a - b) ** 2 for a, b in zip(nodes[n], point)))


def face_nodes_within(nodes, point, radius):
    """The mesh nodes on the face through `point` (its z) within `radius` of it, ascending."""
    return sorted(n for n, p in nodes.items() if abs(p[2] - point[2]) <= 1e-9 * THICKNESS and
                  math.dist(p[:2], point[:2]) <= radius)


class Interface:
    """The six interface points: per mount k, m<k> on the bottom face (the struts' end) and
    t<k> on the top face above it; each a mesh node, or with a pad radius the face's nodes
    within it (at their centroid)."""

    def __init__(self, nodes, pad_radius, pad_kind):
        self.pad_radius, self.pad_kind = pad_radius, pad_kind
        self.angles, self.points = [], {}  # name -> (position, [mesh nodes])
        for k, angle in enumerate(ANGLES_DEG, 1):
            self.angles.append(angle)
            c, s = math.cos(math.radians(angle)), math.sin(math.radians(angle))
            for name, z in ((f"m{k}", 0.0), (f"t{k}", THICKNESS)):
                point = (MOUNT_RADIUS * c, MOUNT_RADIUS * s, z)
                group = face_nodes_within(nodes, point, pad_radius) if pad_radius else \
                    [nearest(nodes, point)]
                if pad_radius and len(group) < 3:
                    sys.exit(f"--pads {pad_radius}: {len(group)} face node(s) under {name} (3 or "
                             "more needed): widen the pads or refine the mesh")
                centroid = tuple(sum(nodes[n][a] for n in group) / len(group) for a in range(3))
                self.points[name] = (centroid, group)

    def floor_nodes(self, k):
        """Bipod k's two floor points: along the ring's tangent at m<k>, 45 degrees down."""
        x, y, z = self.points[f"m{k}"][0]
        angle = math.radians(self.angles[k - 1])
        tx, ty = -math.sin(angle), math.cos(angle)
        d = STRUT["length"] / math.sqrt(2.0)
        return [(x + sign * d * tx, y + sign * d * ty, z - d) for sign in (-1.0, 1.0)]

    def toml(self):
        """The superelement's interface: an `interface` table, or [[superelement.pad]] entries."""
        if not self.pad_radius:
            return "interface = { " + ", ".join(f"{name} = {group[0]}" for name, (_, group) in
                                                self.points.items()) + " }\n"
        return "".join(f'\n[[superelement.pad]]\nid = "{name}"\nkind = "{self.pad_kind}"\n'
                       f"nodes = [{', '.join(str(n) for n in group)}]\n"
                       for name, (_, group) in self.points.items())


def model_text(interface):
    lines = ["# Generated by tools/models/lens_support/make_lens_support.py: the lens support ring",
             "# (a CalculiX superelement) on three bipods of piezo struts.",
             '[model]\nname = "lens_support"\n',
             '[[superelement]]\nid = "ring"\nformat = "calculix"\nstiffness = "ring.sti"',
             'mass = "ring.mas"\ndofs = "ring.dof"\nnodes = "ring.inp"\nmodes_up_to_hz = 6000',
             "damping_ratio = 0.002", interface.toml()]
    fixed, prescribed = [], []
    for k in range(1, len(ANGLES_DEG) + 1):
        for j, p in enumerate(interface.floor_nodes(k)):
            f = f"f{k}{'ab'[j]}"
            lines.append(f'[[node]]\nid = "{f}"\nposition = [{p[0]:.9g}, {p[1]:.9g}, {p[2]:.9g}]\n')
            lines.append(f'[[element]]\nid = "s{k}{"ab"[j]}"\ntype = "truss"\n'
                         f'nodes = ["{f}", "m{k}"]\nstiffness = {STRUT["stiffness"]:g}\n'
                         f'damping = {STRUT["damping"]:g}\nactuator = true\n')
            fixed += [f"x.{f}", f"y.{f}"]
            prescribed.append(f"z.{f}")
    lines.append("[coordinates]\nfixed = [" + ", ".join(f'"{c}"' for c in fixed) + "]")
    lines.append("prescribed = [" + ", ".join(f'"{c}"' for c in prescribed) + "]")
    return "\n".join(lines) + "\n"


def scene_text():
    struts = [f"s{k}{j}" for k in (1, 2, 3) for j in "ab"]
    floors = [f"f{k}{j}" for k in (1, 2, 3) for j in "ab"]

    def quoted(items):
        return "[" + ", ".join(f'"{i}"' for i in items) + "]"
    return f"""# Generated by tools/models/lens_support/make_lens_support.py: the lens support ring on
# six piezo struts under PI force feedback, the floor shaking each strut's foot vertically.
[scene]
name = "lens_support"
model = "lens_support.toml"

[plant]
disturbances = {quoted("acc:z." + f for f in floors)}
actuators = {quoted("stress:e1." + s for s in struts)}
performance = ["acc:z.t1", "acc:z.t2", "acc:z.t3"]
sensors = {quoted("stress:e1." + s for s in struts)}
# The ring's interface nodes carry local modes far above Nyquist (12-75 kHz on the coarse mesh):
# a force loop sampled at 10 kHz cannot act on them as designed, and aliased they undo it over
# the whole band (`flexloop analyse` warns). Below a quarter of the rate the modes stay, the
# rest enter as their static compliance.
reduction = "modal-dc"
below_hz = 2500

[controller]
type = "pi_force_feedback"
omega_d_hz = 40.0
zeta = 0.5
leak_hz = 0.01       # six pure integrators sit at s = 0 to rounding (1e-6 1/s either side)

[discretisation]
method = "zoh"
rate_hz = 10000

[floor]
spectrum = "VC-C"
seed = 1

[run]
duration_s = 2
"""


def reference_deck(path, nodes, etype, elements, interface, modes):
    """The ring on its six struts as one CalculiX model: each strut a SPRINGA element of the
    struts' stiffness to a floor node held in x, y, z (the scene's floor held still), from the
    mount's mesh node, or from its pad's reference node (pads as *RIGID BODY or *EQUATION)."""
    extra, first, struts, pads = {}, max(nodes) + 1, [], ""
    for k, (name, (centroid, group)) in enumerate(interface.points.items()):
        if not interface.pad_radius:
            continue
        ref, rot = first + 2 * k, first + 2 * k + 1
        extra[ref], extra[rot] = centroid, centroid
        pads += rigid_pad(f"PAD{name.upper()}", group, ref, rot) \
            if interface.pad_kind == "rigid" else distributing_equations(nodes, group, ref, rot)
    floor = {}
    for k in range(1, len(ANGLES_DEG) + 1):
        group = interface.points[f"m{k}"][1]
        end = first + 2 * list(interface.points).index(f"m{k}") if interface.pad_radius \
            else group[0]
        for p in interface.floor_nodes(k):
            node = first + len(extra) + 12 + len(floor)
            floor[node] = p
            struts.append((end, node))
    write_deck(path, {**nodes, **extra, **floor}, etype, elements, sorted(floor), STEEL,
               f"*FREQUENCY\n{modes}\n")
    with open(path) as f:
        deck = f.read()
    springs = "*ELEMENT, TYPE=SPRINGA, ELSET=STRUTS\n" + "".join(
        f"{len(elements) + 1 + k}, {a}, {b}\n" for k, (a, b) in enumerate(struts))
    springs += f"*SPRING, ELSET=STRUTS\n{STRUT['stiffness']:.10e}\n"  # a decimal point: a force per length
    with open(path, "w") as f:
        f.write(deck.replace("*NSET, NSET=FIX", pads + springs + "*NSET, NSET=FIX", 1))


def run_ccx(out, job):
    env = dict(os.environ, OMP_NUM_THREADS="1")
    with open(os.path.join(out, job + ".log"), "w") as log:
        subprocess.run(["ccx", "-i", job], cwd=out, check=True, stdout=log, stderr=log, env=env)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--clmax", type=float, default=0.02, help="gmsh element size, m")
    ap.add_argument("--reference", type=int, default=0, metavar="N",
                    help="also solve the whole machine in CalculiX for its N lowest modes")
    ap.add_argument("--pads", type=float, default=0.03, metavar="RADIUS",
                    help="each interface point a pad of the face's nodes within RADIUS (m); "
                    "0: one mesh node each")
    ap.add_argument("--pad-kind", choices=("rigid", "distributing"), default="rigid")
    ap.add_argument("-o", "--out", required=True)
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    here = os.path.dirname(os.path.abspath(__file__))
    mesh = os.path.join(a.out, "mesh.inp")
    subprocess.run(["gmsh", "-3", "-format", "inp", "-clmax", str(a.clmax),
                    os.path.join(here, "lens_support.geo"), "-o", mesh],
                   check=True, stdout=subprocess.DEVNULL)
    nodes, etype, elements = gmsh_mesh(mesh)
    os.remove(mesh)
    write_deck(os.path.join(a.out, "ring.inp"), nodes, etype, elements, [], STEEL,
               "*FREQUENCY, SOLVER=MATRIXSTORAGE\n1\n")
    run_ccx(a.out, "ring")
    interface = Interface(nodes, a.pads, a.pad_kind)
    if a.reference > 0:
        reference_deck(os.path.join(a.out, "ring_struts.inp"), nodes, etype, elements, interface,
                       a.reference)
        run_ccx(a.out, "ring_struts")
    with open(os.path.join(a.out, "lens_support.toml"), "w") as f:
        f.write(model_text(interface))
    with open(os.path.join(a.out, "lens_support_scene.toml"), "w") as f:
        f.write(scene_text())
    print(f"{len(nodes)} nodes, {len(elements)} {etype}, {3 * len(nodes)} DOFs -> {a.out}")


if __name__ == "__main__":
    main()

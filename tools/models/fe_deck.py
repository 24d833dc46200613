# SPDX-License-Identifier: BSD-3-Clause
"""CalculiX input decks from gmsh meshes (issue 58), shared by the shipped superelement models
(tools/models/lens_support) and the tests' bar (tests/fixtures/make_calculix_bar.py)."""
import re
import sys


def gmsh_mesh(path):
    """The nodes and the C3D10 elements of a gmsh .inp file."""
    nodes, elements = {}, []
    section = None
    pending = []
    with open(path) as f:
        for raw in f:
            line = raw.strip()
            if not line or line.startswith("**"):
                continue
            if line.startswith("*"):
                head = line.upper().replace(" ", "")
                if head.startswith("*NODE"):
                    section = "node"
                elif head.startswith("*ELEMENT"):
                    section = "c3d10" if "TYPE=C3D10" in head else "other"
                else:
                    section = None
                continue
            fields = [x for x in re.split(r"[,\s]+", line) if x]
            if section == "node":
                nodes[int(fields[0])] = tuple(float(x) for x in fields[1:4])
            elif section == "c3d10":
                pending += [int(x) for x in fields]
                if len(pending) >= 11:  # an element may continue on the next line
                    elements.append(pending[1:11])
                    pending = []
    if not elements:
        sys.exit(f"{path}: no C3D10 elements (mesh with -order 2 and a Physical Volume)")
    used = {n for e in elements for n in e}
    return {n: x for n, x in nodes.items() if n in used}, "C3D10", elements


def field(v):
    """A number in CalculiX's 20 characters a field: to the bit when it fits, else 13 digits."""
    text = f"{v:.17g}"
    return text if len(text) <= 20 else f"{v:.13g}"


def write_deck(path, nodes, etype, elements, fixed, material, step):
    """A CalculiX deck: the nodes, the elements, `fixed` nodes held in x, y, z (none: a free
    body), one isotropic material (E, nu, rho) and one step."""
    e_modulus, nu, rho = material
    with open(path, "w") as f:
        f.write("*NODE, NSET=NALL\n")
        for n in sorted(nodes):
            x, y, z = nodes[n]
            f.write(f"{n}, {field(x)}, {field(y)}, {field(z)}\n")
        f.write(f"*ELEMENT, TYPE={etype}, ELSET=EALL\n")
        for e, conn in enumerate(elements, 1):
            f.write(f"{e}, " + ", ".join(str(n) for n in conn) + "\n")  # <= 16 entries a line
        if fixed:
            f.write("*NSET, NSET=FIX\n")
            for start in range(0, len(fixed), 10):
                f.write(", ".join(str(n) for n in fixed[start:start + 10]) + "\n")
            f.write("*BOUNDARY\nFIX, 1, 3\n")
        f.write(f"*MATERIAL, NAME=SOLID\n*ELASTIC\n{e_modulus:.17g}, {nu:.17g}\n"
                f"*DENSITY\n{rho:.17g}\n")
        f.write("*SOLID SECTION, ELSET=EALL, MATERIAL=SOLID\n")
        f.write("*STEP\n" + step + "*END STEP\n")


def distributing_equations(nodes, pad, ref, rot):
    """*EQUATION cards of a distributing pad (RBE3, equal weights): the reference point's motion,
    ref's translations and rot's (as rotations, rad), is the least-squares rigid fit of the pad
    nodes' translations, v = W u, W = (R'R)^-1 R'. As flexloop joins it (plant/superelement/
    pads.hpp): six pad translations, the first pivots of W's column-pivoted QR, are eliminated,
    u_A = W_A^-1 (v - W_B u_B), each the dependent term of its own equation."""
    import numpy as np
    import scipy.linalg
    p = np.array([nodes[n] for n in pad])
    r = p - p.mean(axis=0)
    cross = [np.array([[0, -x[2], x[1]], [x[2], 0, -x[0]], [-x[1], x[0], 0]]) for x in r]
    modes = np.vstack([np.hstack([np.eye(3), -c]) for c in cross])
    w = np.linalg.solve(modes.T @ modes, modes.T)
    _, _, pivots = scipy.linalg.qr(w, pivoting=True)
    a, b = pivots[:6], pivots[6:]
    pa = np.linalg.inv(w[:, a])
    q = -pa @ w[:, b]
    dof = [(pad[i // 3], i % 3 + 1) for i in range(3 * len(pad))]
    reference = [(ref, 1), (ref, 2), (ref, 3), (rot, 1), (rot, 2), (rot, 3)]
    text = "*EQUATION\n"
    for i in range(6):
        terms = [(dof[a[i]], 1.0)] + [(reference[c], -pa[i, c]) for c in range(6)] + \
                [(dof[j], -q[i, k]) for k, j in enumerate(b)]
        terms = [t for t in terms if abs(t[1]) > 1e-14]  # rounding's zeros: not terms
        text += f"{len(terms)}\n"
        for start in range(0, len(terms), 4):  # CalculiX: at most 12 fields a line
            text += ", ".join(f"{n}, {d}, {field(c)}" for (n, d), c in terms[start:start + 4])
            text += "\n"
    return text


def rigid_pad(name, pad, ref, rot):
    """A rigid pad (RBE2) as CalculiX's *RIGID BODY: the node set `name` moves rigidly with
    REF NODE ref (its translations) and ROT NODE rot (its translations are the rotations)."""
    text = f"*NSET, NSET={name}\n"
    for start in range(0, len(pad), 10):
        text += ", ".join(str(n) for n in pad[start:start + 10]) + "\n"
    return text + f"*RIGID BODY, NSET={name}, REF NODE={ref}, ROT NODE={rot}\n"

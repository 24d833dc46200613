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

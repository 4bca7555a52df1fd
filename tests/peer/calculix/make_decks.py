#!/usr/bin/env python3
"""Writes the CalculiX (ccx) decks of the peer check into the current folder.

Units mm, N, t, s. Run: `python3 make_decks.py && for d in *.inp; do ccx -i ${d%.inp}; done`,
then read each `.dat` (the displacements of the node set PR). The expected values are in
the comments below and in ../README.md, with what CalculiX 2.20 (Debian 2.20-1) printed.

- cantilever_x.inp: a straight cantilever along x (10 U1 beams, L = 100, d = 3 mm wire,
  E = 190708 MPa, nu = 0.3), tip force 1 N along z and torque 100 N mm about x:
  w = PL^3/3EI = 0.43960 mm, twist = TL/GJ = 0.017144 rad.
- cantilever_xz.inp: the same cantilever along (1, 0, 1)/sqrt(2), force 1 N along y,
  torque 100 N mm about its axis, orientation vector (-1, 0, 1)/sqrt(2) (normal to the
  axis): the same w and twist.
- spring_u1.inp: the paper's spring as coil-mesh builds it (n = 14, D = 24, d = 3,
  h = 6.2 mm, 24 straight beams per coil, base clamped, top wire end guided: only u_z
  free), 10 N along -z on the top wire end: Castigliano 3.7987 N/mm, coil 3.8641 N/mm.
"""
import math

E, NU = 190708.0, 0.3
R_WIRE = 1.5
A = math.pi * R_WIRE**2
I = math.pi * R_WIRE**4 / 4
J = 2 * I
SECTION = "%.10g, %.10g, 0., %.10g, %.10g" % (A, I, I, J)
U1 = "*USER ELEMENT, TYPE=U1, INTEGRATION POINTS=2, MAXDOF=6, NODES=2"
MATERIAL = ["*MATERIAL, NAME=STEEL", "*ELASTIC", f"{E}, {NU}", "*DENSITY", "7.85e-9"]


def write(name, nodes, orientation, boundary, loads, printed):
    lines = ["*HEADING", name, "*NODE"]
    lines += [f"{i}, {x:.12g}, {y:.12g}, {z:.12g}" for i, (x, y, z) in nodes]
    lines += [U1, "*ELEMENT, TYPE=U1, ELSET=WIRE"]
    ids = [i for i, _ in nodes]
    lines += [f"{k + 1}, {a}, {b}" for k, (a, b) in enumerate(zip(ids, ids[1:]))]
    lines += MATERIAL
    lines += ["*BEAM SECTION, ELSET=WIRE, MATERIAL=STEEL, SECTION=GENERAL", SECTION, orientation]
    lines += ["*NSET, NSET=PR", ", ".join(str(p) for p in printed), "*BOUNDARY"] + boundary
    lines += ["*STEP", "*STATIC", "*CLOAD"] + loads
    lines += ["*NODE PRINT, NSET=PR", "U", "*END STEP"]
    with open(f"{name}.inp", "w") as f:
        f.write("\n".join(lines) + "\n")


def cantilevers():
    c = 1 / math.sqrt(2)
    along_x = [(i + 1, (10.0 * i, 0.0, 0.0)) for i in range(11)]
    write("cantilever_x", along_x, "0., 0., 1.", ["1, 1, 6"], ["11, 3, 1.", "11, 4, 100."], [11])
    along_xz = [(i + 1, (10.0 * i * c, 0.0, 10.0 * i * c)) for i in range(11)]
    write(
        "cantilever_xz",
        along_xz,
        f"{-c:.12g}, 0., {c:.12g}",
        ["1, 1, 6"],
        ["11, 2, 1.", f"11, 4, {100 * c:.12g}", f"11, 6, {100 * c:.12g}"],
        [11],
    )


def spring():
    coils, mean_d, pitch, per_coil = 14, 24.0, 6.2, 24
    n = coils * per_coil
    radius = mean_d / 2

    def helix(t):
        return (radius * math.cos(t), radius * math.sin(t), pitch * t / (2 * math.pi))

    nodes = [(i + 1, helix(2 * math.pi * coils * i / n)) for i in range(n + 1)]
    top = n + 1
    write(
        "spring_u1",
        nodes,
        "0., 0., 1.",
        ["1, 1, 6", f"{top}, 1, 2", f"{top}, 4, 6"],
        [f"{top}, 3, -10."],
        [top],
    )


if __name__ == "__main__":
    cantilevers()
    spring()

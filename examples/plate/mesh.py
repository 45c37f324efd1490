"""Writes plate_mesh.inp: a steel plate 300 x 200 x 4 mm of 10 x 6 x 1 twenty-node bricks
(C3D20R), its nodes, elements, material and the node set CLAMP on the edge x = 0. The decks
plate.inp (matrices), plate_modes.inp (CalculiX's own natural frequencies) and plate_free.inp
(the unsupported plate's mass matrix) include it. square.inp's square plate clamped on every
edge (modes in equal pairs) is python3 mesh.py 6 6 0.2 0.2 0.004 square_mesh.inp C3D20R all. Run: python3 mesh.py [NX NY] (default 10 6:
1410 degrees of freedom once clamped; 40 26 gives 22,440, for benchmarks). The cantilever beam
of beam.inp (500 x 20 x 10 mm, 20 x 1 x 1 fully integrated bricks) is the same mesh of other sizes:
python3 mesh.py 20 1 0.5 0.02 0.01 beam_mesh.inp C3D20."""

import sys

ARGS = sys.argv[1:]
NX, NY = (int(ARGS[0]), int(ARGS[1])) if len(ARGS) >= 2 else (10, 6)
LX, LY, T = (float(ARGS[2]), float(ARGS[3]), float(ARGS[4])) if len(ARGS) >= 5 else (0.30, 0.20, 0.004)
OUT = ARGS[5] if len(ARGS) >= 6 else "plate_mesh.inp"
# Reduced integration (C3D20R) has zero-energy modes in a stack one element wide and thick:
# the beam takes full integration (C3D20).
ELEMENT = ARGS[6] if len(ARGS) >= 7 else "C3D20R"
# The clamped edges: "x0" (the edge x = 0, a cantilever) or "all" (every edge: the square
# plate of square.inp, whose modes come in equal pairs).
CLAMPED = ARGS[7] if len(ARGS) >= 8 else "x0"


def used(i, j, k):
    # A twenty-node brick has nodes at its corners and mid-edges, none at face or body centres.
    return (i % 2) + (j % 2) + (k % 2) <= 1


def main():
    ids = {}
    with open(OUT, "w") as f:
        f.write(f"** Steel {LX * 1e3:g} x {LY * 1e3:g} x {T * 1e3:g} mm, {NX} x {NY} x 1 {ELEMENT}; written by mesh.py\n*NODE, NSET=NALL\n")
        n = 0
        for k in range(3):
            for j in range(2 * NY + 1):
                for i in range(2 * NX + 1):
                    if used(i, j, k):
                        n += 1
                        ids[(i, j, k)] = n
                        f.write(f"{n}, {LX * i / (2 * NX):.9g}, {LY * j / (2 * NY):.9g}, {T * k / 2:.9g}\n")
        f.write(f"*ELEMENT, TYPE={ELEMENT}, ELSET=EALL\n")
        e = 0
        for j in range(NY):
            for i in range(NX):
                a, b = 2 * i, 2 * j
                c = [(a, b, 0), (a + 2, b, 0), (a + 2, b + 2, 0), (a, b + 2, 0),
                     (a, b, 2), (a + 2, b, 2), (a + 2, b + 2, 2), (a, b + 2, 2),
                     (a + 1, b, 0), (a + 2, b + 1, 0), (a + 1, b + 2, 0), (a, b + 1, 0),
                     (a + 1, b, 2), (a + 2, b + 1, 2), (a + 1, b + 2, 2), (a, b + 1, 2),
                     (a, b, 1), (a + 2, b, 1), (a + 2, b + 2, 1), (a, b + 2, 1)]
                e += 1
                nodes = [str(ids[p]) for p in c]
                f.write(f"{e}, " + ", ".join(nodes[:15]) + ",\n" + ", ".join(nodes[15:]) + "\n")
        f.write("*NSET, NSET=CLAMP\n")
        for (i, j, k), n in sorted(ids.items(), key=lambda x: x[1]):
            edge = i == 0 or (CLAMPED == "all" and (i == 2 * NX or j == 0 or j == 2 * NY))
            if edge:
                f.write(f"{n},\n")
        f.write("*MATERIAL, NAME=STEEL\n*ELASTIC\n210E9, 0.3\n*DENSITY\n7850.\n")
        f.write("*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL\n")
    # The nodes a user would pick: the free edge's mid-surface corners and middle.
    if OUT != "plate_mesh.inp":
        return
    for name, (i, j) in [("free corner y = 0", (2 * NX, 0)), ("free edge middle", (2 * NX, NY)),
                         ("free corner y = 0.2", (2 * NX, 2 * NY)), ("plate middle", (NX, NY))]:
        print(f"{name}: node {ids[(i, j, 1)] if (i, j, 1) in ids else ids[(i, j, 0)]}")


if __name__ == "__main__":
    main()

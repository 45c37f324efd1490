"""A shear building with beds of shot under a ground-acceleration record in OpenSees
(openseespy): each bed a mass between two penalty contact elements, for the comparison with
shotdamp's exact impacts (tests/opensees.rs, docs/model.md section 5).

Usage: python opensees_shot.py IN.json OUT.json. IN.json:
  {"masses": [kg...], "stiffnesses": [N/m...], "alpha": a0, "beta": a1,
   "dt": s, "accel": [m/s^2...],
   "beds": [{"host": floor (1-based), "mass": kg, "clearance": m}],
   "contacts": [{"stiffness": N/m, "division": d}, ...]}
OUT.json: for each contact stiffness, every floor's displacement relative to the ground at
the record's sample times and the largest magnitude of each floor's over every step, computed
with Newmark's average acceleration method at the step dt / d:
  {"version": "...", "runs": [{"stiffness": k, "division": d, "u": [[...] per sample],
   "peak": [...]}]}

The building: node 0 fixed, nodes 1..n the floors, storey i a zeroLength element (stiffness
k_i, Rayleigh damping a0 on the floors' masses and a1 on the storeys' stiffness, none on the
beds or the contacts). Each bed a node of its own mass at its floor's
position, joined to it by a zeroLength element of two materials in parallel: "ENT" (no
tension: the first wall, pushing when the bed is behind it) and "ElasticPPGap" with the gap
equal to the clearance (the second wall). Both are elastic: the contact conserves energy, the
penalty counterpart of a coefficient of restitution of 1. The record acts as a
UniformExcitation on every mass (beds included: they move with the ground until a wall
pushes them).
"""

import json
import sys

import openseespy.opensees as ops

from opensees_shear import building, transient


def run(spec, stiffness, division):
    # Rayleigh damping on what exists now: the floors and storeys. The beds and contacts made
    # after it take none (a region's -rayleigh left the building undamped in openseespy
    # 3.7.1, and zeroing a node's by a region did nothing: measured).
    n = building(spec)
    for j, bed in enumerate(spec["beds"]):
        node, tag = 100 + j, 100 + 2 * j
        ops.node(node, 0.0)
        ops.mass(node, bed["mass"])
        ops.uniaxialMaterial("ENT", tag, stiffness)
        ops.uniaxialMaterial("ElasticPPGap", tag + 1, stiffness, 1e30, bed["clearance"])
        ops.uniaxialMaterial("Parallel", tag + 1000, tag, tag + 1)
        ops.element("zeroLength", 100 + j, bed["host"], node, "-mat", tag + 1000, "-dir", 1)
    dt = spec["dt"]
    transient(spec, "Newton")
    u = [[0.0] * n]
    peak = [0.0] * n
    h = dt / division
    for _ in range(len(spec["accel"]) - 1):
        for _ in range(division):
            if ops.analyze(1, h) != 0:
                raise SystemExit("OpenSees failed to advance")
            for i in range(n):
                peak[i] = max(peak[i], abs(ops.nodeDisp(i + 1, 1)))
        u.append([ops.nodeDisp(i, 1) for i in range(1, n + 1)])
    return u, peak


def main():
    with open(sys.argv[1]) as f:
        spec = json.load(f)
    version = ops.version() if hasattr(ops, "version") else "unknown"
    runs = []
    for c in spec["contacts"]:
        u, peak = run(spec, c["stiffness"], c["division"])
        runs.append({"stiffness": c["stiffness"], "division": c["division"], "u": u, "peak": peak})
    with open(sys.argv[2], "w") as f:
        json.dump({"version": str(version), "runs": runs}, f)


if __name__ == "__main__":
    main()

"""A shear building under a ground-acceleration record in OpenSees (openseespy), for the
comparison with shotdamp's exact response (tests/opensees.rs, docs/model.md section 6).

Usage: python opensees_shear.py IN.json OUT.json (OpenSees writes its own lines to standard
output). IN.json:
  {"masses": [kg...], "stiffnesses": [N/m...], "alpha": a0, "beta": a1,
   "dt": s, "accel": [m/s^2...], "divisions": [1, 2, 4, 8]}
OUT.json: for each division d, every floor's displacement relative
to the ground at the record's sample times, computed with Newmark's average acceleration
method at the step dt / d (the record linear between its samples, OpenSees' Path series):
  {"version": "...", "runs": [{"division": d, "u": [[floor 1..n] per sample]}]}

The building: node 0 fixed, nodes 1..n carry the masses, storey i a zeroLength element of
stiffness k_i between nodes i-1 and i; Rayleigh damping C = a0 M + a1 K; the record applied as
a UniformExcitation (the load -M r a_g).
"""

import json
import sys

import openseespy.opensees as ops


def building(spec):
    """The shear building of `spec` in a fresh model, with its Rayleigh damping (on what
    exists when it is called: elements and nodes made later take none)."""
    masses, ks = spec["masses"], spec["stiffnesses"]
    n = len(masses)
    ops.wipe()
    ops.model("basic", "-ndm", 1, "-ndf", 1)
    for i in range(n + 1):
        ops.node(i, 0.0)
    ops.fix(0, 1)
    for i in range(1, n + 1):
        ops.mass(i, masses[i - 1])
        ops.uniaxialMaterial("Elastic", i, ks[i - 1])
        # zeroLength elements take no Rayleigh damping unless asked (-doRayleigh 1).
        ops.element("zeroLength", i, i - 1, i, "-mat", i, "-dir", 1, "-doRayleigh", 1)
    ops.rayleigh(spec["alpha"], spec["beta"], 0.0, 0.0)
    return n


def transient(spec, algorithm):
    """The record as a UniformExcitation and Newmark's average acceleration method."""
    ops.timeSeries("Path", 1, "-dt", spec["dt"], "-values", *spec["accel"])
    ops.pattern("UniformExcitation", 1, 1, "-accel", 1)
    ops.constraints("Plain")
    ops.numberer("Plain")
    ops.system("FullGeneral")
    if algorithm == "Newton":
        ops.test("NormDispIncr", 1e-12, 50)
    ops.algorithm(algorithm)
    ops.integrator("Newmark", 0.5, 0.25)
    ops.analysis("Transient")


def run(spec, division):
    n = building(spec)
    dt = spec["dt"]
    transient(spec, "Linear")
    u = [[0.0] * n]
    for _ in range(len(spec["accel"]) - 1):
        if ops.analyze(division, dt / division) != 0:
            raise SystemExit("OpenSees failed to advance")
        u.append([ops.nodeDisp(i, 1) for i in range(1, n + 1)])
    return u


def main():
    with open(sys.argv[1]) as f:
        spec = json.load(f)
    version = ops.version() if hasattr(ops, "version") else "unknown"
    runs = [{"division": d, "u": run(spec, d)} for d in spec["divisions"]]
    with open(sys.argv[2], "w") as f:
        json.dump({"version": str(version), "runs": runs}, f)


if __name__ == "__main__":
    main()

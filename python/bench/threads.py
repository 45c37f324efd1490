"""Two Python threads sweeping at once use two cores: the same two sweeps (one thread each,
jobs=1) one after the other, then in two threads at once; wall and CPU time of each.
Run from the repository root after installing the wheel: python python/bench/threads.py"""

import os
import threading
import time

import numpy as np

import shotdamp as sd


def system():
    paper = sd.Structure(
        masses_kg=[0.74, 0.71, 0.64],
        chain_stiffness_n_per_m=[24.3e3, 21.8e3, 19.8e3],
        modal_ratios=[0.01, 0.01, 0.01],
    )
    beds = [sd.Damper(mass=m, mass_ratio=0.1, clearance_mm=0.2) for m in (1, 2, 3)]
    return sd.System(paper, beds, force_n=2.6)


def sweep(s):
    s.sweep(np.round(np.arange(44.0, 56.0001, 0.1), 1), jobs=1)


def timed(f):
    w, c = time.perf_counter(), time.process_time()
    f()
    return time.perf_counter() - w, time.process_time() - c


def main():
    s = system()
    sweep(s)  # warm up
    rows = []
    for _ in range(5):
        seq = timed(lambda: (sweep(s), sweep(s)))

        def both():
            ts = [threading.Thread(target=sweep, args=(s,)) for _ in range(2)]
            for t in ts:
                t.start()
            for t in ts:
                t.join()

        par = timed(both)
        rows.append((seq, par))
    seq_wall = np.median([r[0][0] for r in rows])
    par_wall = np.median([r[1][0] for r in rows])
    par_cpu = np.median([r[1][1] for r in rows])
    print(f"cores: {os.cpu_count()}")
    print(f"two sweeps one after the other: {seq_wall:.3f} s wall")
    print(f"two sweeps in two threads:      {par_wall:.3f} s wall, {par_cpu:.3f} s CPU (CPU/wall {par_cpu / par_wall:.2f})")
    print(f"speed-up: {seq_wall / par_wall:.2f}")


if __name__ == "__main__":
    main()

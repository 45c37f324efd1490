"""Long calls release the interpreter lock and stop on Ctrl-C."""

import _thread
import threading
import time

import numpy as np
import pytest

import shotdamp as sd
from conftest import paper_structure

# A slow sweep: 3 beds, waiting for the transient at every point (about 10-25 ms a point).
SLOW = {"method": "transient"}


def slow_system():
    beds = [sd.Damper(mass=m, mass_ratio=0.1, clearance_mm=0.2) for m in (1, 2, 3)]
    return sd.System(paper_structure(modal_ratios=[0.002] * 3), beds, force_n=2.6)


def test_the_lock_is_released_while_a_sweep_runs():
    system = slow_system()
    done = threading.Event()
    counted = []

    def work():
        system.sweep(np.linspace(44.0, 56.0, 40), steady=SLOW, jobs=1)
        done.set()

    t = threading.Thread(target=work)
    t.start()
    n = 0
    while not done.is_set():
        n += 1  # runs only while the sweep's thread does not hold the lock
    t.join()
    counted.append(n)
    # Held for the whole sweep, the lock would let this loop run only in the gaps between
    # the thread's switches (a handful of iterations); released, it spins all along.
    assert n > 100_000, n


def test_ctrl_c_stops_a_sweep_at_its_next_point():
    system = slow_system()
    freqs = np.linspace(44.0, 56.0, 4000)  # about a minute on one thread
    timer = threading.Timer(0.5, _thread.interrupt_main)
    started = time.monotonic()
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        system.sweep(freqs, steady=SLOW, jobs=1)
    elapsed = time.monotonic() - started
    timer.cancel()
    assert elapsed < 20.0, elapsed
    # The system is usable afterwards.
    assert system.steady_state(48.0).converged


def test_ctrl_c_leaves_no_half_written_report(tmp_path):
    # The report's longest piece (design_plate's layouts on a 46-coordinate model, minutes
    # each) stops at its next simulated period, not at the end of the layout.
    out = tmp_path / "reports"
    timer = threading.Timer(2.0, _thread.interrupt_main)
    started = time.monotonic()
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        sd.report(out)
    elapsed = time.monotonic() - started
    timer.cancel()
    assert elapsed < 30.0, elapsed
    assert not out.exists()
    assert [p.name for p in tmp_path.iterdir()] == []


def test_progress_is_reported_and_may_stop_the_run():
    system = slow_system()
    seen = []
    system.sweep(np.linspace(44.0, 56.0, 30), steady=SLOW, jobs=1, progress=lambda d, t: seen.append((d, t)))
    assert seen[-1] == (30, 30)
    assert all(t == 30 for _, t in seen)

    def stop(done, total):
        raise RuntimeError("enough")

    with pytest.raises(RuntimeError, match="enough"):
        system.sweep(np.linspace(44.0, 56.0, 400), steady=SLOW, jobs=1, progress=stop)


def test_ctrl_c_stops_a_study_shard_inside_its_sample(tmp_path):
    # Samples of about 25 s each (Fig. 8 on a 2 mHz grid): Ctrl-C stops the shard at its next
    # simulated point, not at the end of the sample, and no part is written.
    experiment = (sd_root() / "experiments" / "fig08_number_of_dampers.toml").resolve()
    study = tmp_path / "long.toml"
    study.write_text(
        f"""[study]
id = "long"
title = "one long sample"
experiment = "{experiment}"

[study.set]
"analysis.freq_hz" = {{ start = 8.0, stop = 60.0, step = 0.002 }}

[[vary]]
name = "force_n"
key = "excitation.force_n"
values = [2.6]
"""
    )
    out = tmp_path / "out"
    timer = threading.Timer(1.5, _thread.interrupt_main)
    started = time.monotonic()
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        sd.study(study, out=out, jobs=1)
    elapsed = time.monotonic() - started
    timer.cancel()
    assert elapsed < 6.0, elapsed
    assert not list(tmp_path.rglob("part-*.parquet"))


def sd_root():
    from pathlib import Path

    return Path(__file__).resolve().parents[2]

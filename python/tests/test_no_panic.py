"""Nothing panics across the boundary: the odd values of the Rust fuzz properties
(tests/fuzz.rs: huge, tiny, non-finite, negative, wrongly typed) put into every argument,
alone and in pairs, give a result or a Python exception (ValueError, TypeError,
OverflowError), never a Rust panic (pyo3's PanicException, a BaseException)."""

import random

import numpy as np
import pytest

import shotdamp as sd

ODD = [1e308, -1e308, 1e-320, float("nan"), float("inf"), float("-inf"), -0.0, 0, -1, 10**23, "text", True, [], {"a": 1}]

STRUCTURE = dict(
    masses_kg=[0.74, 0.71, 0.64],
    chain_stiffness_n_per_m=[24.3e3, 21.8e3, 19.8e3],
    modal_ratios=[0.01, 0.01, 0.01],
)
DAMPER = dict(mass=2, mass_ratio=0.1, clearance_mm=0.3, bed="restitution", restitution=0.3, stick_speed_m_s=1e-3)
CALL = dict(force_n=2.6, freq_hz=48.0, velocity=0.5)
CHEAP = {"min_periods": 5, "max_periods": 40, "record_periods": 2}
ALLOWED = (ValueError, TypeError, OverflowError)


def slots():
    """Every place a value can go: (where, key, index or None)."""
    out = []
    for k, v in STRUCTURE.items():
        out += [("structure", k, i) for i in range(len(v))] + [("structure", k, None)]
    out += [("damper", k, None) for k in DAMPER]
    out += [("call", k, None) for k in CALL]
    return out


def attempt(changes):
    structure = {k: list(v) for k, v in STRUCTURE.items()}
    damper, call = dict(DAMPER), dict(CALL)
    # Elements first, whole values last (a whole value may replace the list an element is in).
    for (where, key, i), value in sorted(changes, key=lambda c: c[0][2] is None):
        if where == "structure":
            if i is None:
                structure[key] = value
            else:
                structure[key][i] = value
        elif where == "damper":
            damper[key] = value
        else:
            call[key] = value
    try:
        s = sd.Structure(**structure)
        s.modes()
        s.frf([call["freq_hz"]] if not isinstance(call["freq_hz"], (list, dict)) else call["freq_hz"])
        system = sd.System(s, [sd.Damper(**damper)], force_n=call["force_n"])
        system.steady_state(call["freq_hz"], steady=CHEAP)
        system.impulse(initial_velocity_m_s=call["velocity"], duration_s=0.02, sample_rate_hz=1000)
    except ALLOWED:
        pass
    except BaseException as e:  # a PanicException, or anything else unexpected
        pytest.fail(f"{type(e).__name__}: {e} with {changes}")


@pytest.mark.parametrize("slot", slots(), ids=lambda s: f"{s[0]}.{s[1]}[{s[2]}]")
def test_every_odd_value_in_every_argument(slot):
    for value in ODD:
        attempt([(slot, value)])


def test_odd_values_in_pairs():
    rng = random.Random(20261125)
    places = slots()
    for _ in range(300):
        a, b = rng.sample(places, 2)
        attempt([(a, rng.choice(ODD)), (b, rng.choice(ODD))])


def test_odd_arrays():
    s = sd.Structure(**STRUCTURE)
    system = sd.System(s, [sd.Damper(mass=2, mass_ratio=0.1, clearance_mm=0.3)], force_n=2.6)
    for freqs in ([], np.zeros((0,)), np.array([[1.0]]), np.array(["a"]), np.array([1e308]), np.array([1e-300]), None, "44"):
        try:
            system.sweep(freqs, steady=CHEAP)
        except ALLOWED:
            pass

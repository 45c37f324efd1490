"""The package's physics against closed forms and the library's own invariants."""

import doctest
import math

import numpy as np
import pytest

import shotdamp as sd
from conftest import paper_structure


def test_the_package_docstring_runs():
    failed, tried = doctest.testmod(sd, verbose=False)
    assert tried > 0 and failed == 0


def test_one_mass_frf_is_the_closed_form():
    m, k, zeta = 2.0, 8.0e4, 0.02
    s = sd.Structure(masses_kg=[m], chain_stiffness_n_per_m=[k], modal_ratios=[zeta])
    f = np.linspace(5.0, 60.0, 56)
    w = 2 * math.pi * f
    c = 2 * zeta * math.sqrt(k * m)
    exact = 1.0 / np.sqrt((k - m * w**2) ** 2 + (c * w) ** 2)
    got = s.frf(f)[:, 0]
    assert np.max(np.abs(got / exact - 1)) < 1e-12


def test_modes_of_the_paper_structure():
    modes = paper_structure().modes()
    assert modes["freq_hz"].shape == (3,)
    assert np.all(np.diff(modes["freq_hz"]) > 0)
    assert np.allclose(modes["damping_ratio"], 0.01, rtol=1e-10)
    assert np.allclose(np.abs(modes["shape"]).max(axis=1), 1.0)
    # Eq. 13: with a damper of mass m_d on mass j, mu_i = |phibar_ij| m_d / M_i.
    d = sd.Damper(mass=2, mass_kg=0.071, clearance_mm="inf")
    mu = paper_structure().modes([d])["mass_ratio"]
    expected = np.abs(modes["shape"][:, 1]) * 0.071 / modes["modal_mass_kg"]
    assert np.allclose(mu, expected, rtol=1e-12)


def test_a_bare_oscillator_on_shaken_supports_is_the_closed_form():
    # m u'' + c u' + k u = -m A sin(w t): |u / A| = 1 / |wn^2 - w^2 + 2 i zeta wn w|.
    m, k, zeta = 2.0, 8.0e4, 0.02
    wn = math.sqrt(k / m)
    s = sd.Structure(masses_kg=[m], chain_stiffness_n_per_m=[k], modal_ratios=[zeta])
    system = sd.System(s, base_acceleration_m_s2=3.0)
    assert "base_acceleration_m_s2=3" in repr(system)
    for f in (10.0, 30.0, 45.0):
        w = 2 * math.pi * f
        exact = 1.0 / abs(complex(wn**2 - w**2, 2 * zeta * wn * w))
        got = system.steady_state(f).compliance[0]
        assert abs(got / exact - 1) < 1e-9
    with pytest.raises(ValueError, match="give no force"):
        sd.System(s, force_n=1.0, base_acceleration_m_s2=3.0)
    with pytest.raises(ValueError, match="base_acceleration_m_s2"):
        sd.System(s)


def test_a_full_mass_matrix_in_coordinates_that_keep_the_host_gives_the_chain_s_motion():
    # q3 = x3 - 0.4 x1 - 0.3 x2: M_q = T^T M T is full; the driven mass and the host stay
    # physical, so their steady motion is the lumped chain's (docs/model.md section 5).
    lumped = paper_structure()
    t = np.eye(3)
    t[2, 0], t[2, 1] = 0.4, 0.3
    m = t.T @ lumped.mass_matrix @ t
    k = t.T @ lumped.stiffness @ t
    coupled = sd.Structure(mass_matrix_kg=m, stiffness_matrix_n_per_m=k, modal_ratios=[0.01] * 3)
    assert np.allclose(coupled.mass_matrix, m, rtol=0, atol=0)
    d = sd.Damper(mass=2, mass_kg=0.071, clearance_mm=0.5)
    for f in (46.0, 48.8, 51.0):
        a = sd.System(lumped, [d], force_n=2.6).steady_state(f)
        b = sd.System(coupled, [d], force_n=2.6).steady_state(f)
        assert a.converged and b.converged
        assert np.max(np.abs(b.compliance[:2] / a.compliance[:2] - 1)) < 1e-9


def test_a_finite_element_plate_from_calculix_reduces_to_its_points(tmp_path, monkeypatch):
    # The plate CalculiX meshed (examples/plate): four points and the fixed-interface modes
    # below 2.5 kHz; its first mode is CalculiX's 38.633 Hz from above, within 2e-6.
    import pathlib

    repo = pathlib.Path(__file__).resolve().parents[2]
    monkeypatch.chdir(repo / "examples" / "plate")
    points = [{"node": n, "dof": 3} for n in (224, 290, 257, 252)]
    fe = dict(format="calculix", stiffness="data/plate.sti", mass="data/plate.mas", dofs="data/plate.dof", up="z", points=points, cutoff_hz=2500.0)
    s = sd.Structure(finite_element=fe, modal_ratios=[0.01])
    assert s.dof == 20
    f1 = s.modes()["freq_hz"][0]
    assert 0 < f1 / 38.63284950725794 - 1 < 2e-6
    with pytest.raises(ValueError, match="node = 99999"):
        sd.Structure(finite_element=dict(fe, points=[{"node": 99999, "dof": 3}]), modal_ratios=[0.01])
    # The reduction against the full model: the first bending band, a force at the corner.
    r = s.reduction(np.linspace(33.0, 43.0, 21), force_point=1)
    freqs = r["frequencies"]
    assert freqs.columns == ["mode", "full_hz", "reduced_hz", "rel_diff"]
    assert abs(freqs["full_hz"][0] / 38.63284950725794 - 1) < 1e-6
    assert np.all(freqs["rel_diff"] >= -1e-12)  # the reduced model is stiffer: from above
    c = r["compliance"]
    assert len(c["freq_hz"]) == 21 * 4 and set(c["point"]) == {f"node {n} z" for n in (224, 290, 257, 252)}
    assert 0 < r["largest"] < 1e-3 and r["largest"] == np.max(c["rel_diff"])
    assert "compliance" not in s.reduction()
    with pytest.raises(ValueError, match="not reduced"):
        paper_structure().reduction([10.0])
    with pytest.raises(ValueError, match="force_point = 5"):
        s.reduction([10.0], force_point=5)
    # A sweep tabulates the points alone, as the command line does (the modal coordinates are
    # no displacement of any point): the same compliances as the steady state that follows
    # every coordinate.
    system = sd.System(s, [sd.Damper(mass=1, mass_kg=0.05, clearance_mm=1.0)], force_n=0.2)
    f = [36.0, 38.5]
    t = system.sweep(f)
    assert [c for c in t.columns if c.startswith("c") and c[1:].isdigit()] == ["c1", "c2", "c3", "c4"]
    for i, fi in enumerate(f):
        st = system.steady_state(fi)
        assert len(st.compliance) == 20
        for k in range(4):
            assert t[f"c{k + 1}"][i] == st.compliance[k], (fi, k)
    # More coordinates than the simulator takes: a structure for modes and responses, refused
    # as a system, named by its points and modes.
    big_fe = {k: v for k, v in fe.items() if k != "cutoff_hz"}
    big = sd.Structure(finite_element=dict(big_fe, modes=300), modal_ratios=[0.01])
    assert big.dof == 304
    with pytest.raises(ValueError, match=r"structure.finite_element = 304 coordinates \(4 points and 300 fixed-interface modes\).*keeping at most 252 modes"):
        sd.System(big, [sd.Damper(mass=1, mass_kg=0.05, clearance_mm=1.0)], force_n=0.2)


def test_infinite_clearance_far_above_the_flight_equals_stuck_masses_below_lift_off():
    # Far below resonance the bed never lifts off (acceleration below g): the response is the
    # linear one of the structure with the damper mass rigidly added.
    s = paper_structure()
    d = sd.Damper(mass=1, mass_ratio=0.1, clearance_mm="inf")
    system = sd.System(s, [d], force_n=0.01)
    st = system.steady_state(5.0)
    stuck = s.frf([5.0], dampers=[d])[0]
    assert st.converged
    assert np.max(np.abs(st.compliance / stuck - 1)) < 1e-9


def test_a_certified_orbit_has_its_multipliers():
    system = sd.System(paper_structure(), [sd.Damper(mass=2, mass_ratio=0.1, clearance_mm=0.3)], force_n=2.6)
    st = system.steady_state(48.0)
    o = st.orbit
    assert st.converged and o is not None and o.stable and o.residual < 1e-10
    assert o.multipliers.dtype == np.complex128
    assert np.all(np.abs(o.multipliers) < 1.0)
    assert o.spectral_radius == pytest.approx(np.abs(o.multipliers).max(), rel=1e-15)
    x, v = o.section
    assert x.shape == (3,) and v.shape == (3,)
    assert st.motion == "periodic" and st.lyapunov_per_s is None and st.measured_periods == 0
    assert np.all(np.isnan(st.compliance_half_width))


def test_a_point_with_no_orbit_is_classified_and_measured():
    # Fig. 8's chain, one bed on m1 without a lid, 33.6 Hz: a torus (tests/irregular.rs).
    system = sd.System(paper_structure(), [sd.Damper(mass=1, mass_ratio=0.1, clearance_mm="inf")], force_n=2.6)
    st = system.steady_state(33.6)
    assert not st.converged and st.orbit is None
    assert st.motion == "quasi-periodic", st.motion
    assert abs(st.lyapunov_per_s) <= st.lyapunov_half_width
    assert st.measured_periods >= 400 and st.interval_met
    hw = st.compliance_half_width
    assert np.all(np.isfinite(hw)) and np.all(hw <= 0.01 * st.compliance.max())


def test_impulse_energy_balance_for_every_bed_model():
    for d in (
        sd.Damper(mass=1, mass_ratio=0.1, clearance_mm=0.5),
        sd.Damper(mass=1, mass_ratio=0.1, clearance_mm=0.5, bed="restitution", restitution=0.4),
        sd.Damper(mass=1, mass_ratio=0.1, clearance_mm=0.5, bed="column", grains=5, restitution=0.3),
        sd.Damper(mass=1, mass_ratio=0.1, clearance_mm=0.5, bed="restitution", restitution=0.4, direction="horizontal"),
    ):
        system = sd.System(paper_structure(), [d], force_n=1.0)
        r = system.impulse(struck_mass=1, initial_velocity_m_s=0.3, duration_s=0.3, sample_rate_hz=2000)
        assert r["energy_residual"] < 1e-9
        assert r["x_m"].shape == (r["t_s"].shape[0], 3)
        assert r["initial_energy_j"] == pytest.approx(
            r["final_energy_j"] + r["viscous_loss_j"] + r["impact_loss_j"], rel=1e-9
        )


def test_sweeps_are_the_same_for_any_number_of_threads():
    system = sd.System(paper_structure(), [sd.Damper(mass=m, mass_ratio=0.1, clearance_mm=0.3) for m in (1, 2, 3)], force_n=2.6)
    f = np.round(np.arange(46.0, 52.01, 0.25), 2)
    one, two = system.sweep(f, jobs=1), system.sweep(f, jobs=2)
    for k in one:
        if isinstance(one[k], list):
            assert one[k] == two[k]
        else:
            assert np.array_equal(one[k], two[k], equal_nan=True), k


def test_tables_convert_when_the_libraries_are_there():
    system = sd.System(paper_structure(), [sd.Damper(mass=2, mass_ratio=0.1, clearance_mm=0.3)], force_n=2.6)
    t = system.sweep([47.0, 48.0])
    assert t.rows == 2 and t.name == "compliance"
    try:
        import pandas  # noqa: F401
    except ImportError:
        pandas = None
    if pandas is not None:
        assert list(t.to_pandas().columns) == t.columns


def test_experiments_load_with_their_models():
    exps = sd.load("experiments/fig05_hysteresis.toml")
    assert [e.model for e in exps] == ["stated", "coil", "fitted"]
    e = exps[0]
    assert e.kind == "sweep" and e.cases == ["single"] and e.force_mass == 1 and e.force_n == 2.6
    assert e.structure.dof == 3
    with pytest.raises(ValueError, match="one of the file's cases"):
        e.system("nothing")
    scan = sd.load("experiments/fig05_clearance_scan.toml")[0]
    with pytest.raises(ValueError, match="set by a run"):
        scan.system("single")


def test_a_column_certified_by_the_certify_method():
    # Five plastic grains on m2 move as the single plastic mass: the transient's settled
    # motion certified (Jacobian by central differences) has the single mass's multiplier.
    column = sd.System(paper_structure(), [sd.Damper(mass=2, mass_ratio=0.1, clearance_mm=0.35, bed="column", grains=5)], force_n=2.6)
    single = sd.System(paper_structure(), [sd.Damper(mass=2, mass_ratio=0.1, clearance_mm=0.35)], force_n=2.6)
    transient = column.steady_state(52.0, steady={"method": "transient"})
    certified = column.steady_state(52.0, steady={"method": "certify"})
    assert transient.orbit is None and certified.orbit is not None
    assert np.array_equal(transient.compliance, certified.compliance)
    exact = single.steady_state(52.0).orbit
    assert certified.orbit.spectral_radius == pytest.approx(exact.spectral_radius, abs=1e-6)
    assert certified.orbit.stable and certified.orbit.residual < 1e-11


def _duhamel(w, zeta, dt, ag):
    """u'' + 2 zeta w u' + w^2 u = -a_g(t), a_g linear between samples: the exact recurrence
    (Chopra, Dynamics of Structures, Table 5.2.1 with k = w^2, p = -a_g)."""
    k, r = w * w, math.sqrt(1 - zeta * zeta)
    wd, e = w * r, math.exp(-zeta * w * dt)
    s, c = math.sin(wd * dt), math.cos(wd * dt)
    a = e * (zeta / r * s + c)
    b = e * s / wd
    cc = (2 * zeta / (w * dt) + e * (((1 - 2 * zeta**2) / (wd * dt) - zeta / r) * s - (1 + 2 * zeta / (w * dt)) * c)) / k
    d = (1 - 2 * zeta / (w * dt) + e * ((2 * zeta**2 - 1) / (wd * dt) * s + 2 * zeta / (w * dt) * c)) / k
    a1, b1 = -e * w / r * s, e * (c - zeta / r * s)
    c1 = (-1 / dt + e * ((w / r + zeta / (dt * r)) * s + c / dt)) / k
    d1 = (1 - e * (zeta / r * s + c)) / (k * dt)
    u, v, out = 0.0, 0.0, [0.0]
    for p0, p1 in zip(-ag[:-1], -ag[1:]):
        u, v = a * u + b * v + cc * p0 + d * p1, a1 * u + b1 * v + c1 * p0 + d1 * p1
        out.append(u)
    return np.array(out)


def test_a_storey_under_a_record_is_the_piecewise_linear_duhamel_solution():
    m, period, zeta, dt = 1000.0, 0.5, 0.05, 0.01
    w = 2 * math.pi / period
    s = sd.Structure(masses_kg=[m], chain_stiffness_n_per_m=[m * w * w], modal_ratios=[zeta])
    t = np.arange(1500) * dt
    ag = 3.0 * np.sin(9.0 * t) * np.exp(-0.3 * t) + 1.5 * np.sin(23.0 * t + 0.4)
    r = sd.System(s, base_acceleration_m_s2=1.0).ground_motion(ag, dt)
    want = _duhamel(w, zeta, dt, ag)
    assert r["completed"] and r["events"] == 0
    assert r["u_m"].shape == (1500, 1)
    assert np.max(np.abs(r["u_m"][:, 0] - want)) < 1e-10 * np.max(np.abs(want))
    # The peak between samples is at least every sample's; the energy balances.
    assert r["peak_displacement_m"][0] >= np.max(np.abs(want)) * (1 - 1e-12)
    assert abs(r["energy_balance_j"]) < 1e-8 * r["energy_input_j"]
    # A horizontal bed: impacts, and the energy still balances.
    d = sd.Damper(mass=1, mass_kg=50.0, clearance_mm=20.0, direction="horizontal")
    beds = sd.System(s, [d], base_acceleration_m_s2=1.0).ground_motion(ag, dt)
    assert beds["impacts"][0] > 0 and beds["energy_impacts_j"] > 0
    assert abs(beds["energy_balance_j"]) < 1e-8 * beds["energy_input_j"]
    with pytest.raises(ValueError, match="dt_s"):
        sd.System(s, base_acceleration_m_s2=1.0).ground_motion(ag, 0.0)
    with pytest.raises(ValueError, match="accel_m_s2"):
        sd.System(s, base_acceleration_m_s2=1.0).ground_motion([1.0], dt)

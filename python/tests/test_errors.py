"""Bad arguments raise ValueError with the command line's text: each case is written as an
experiment file and run by the binary, and the message after the file's name must equal
the package's after its origin (a damper's key is relative to its case: `dampers[0].KEY`
where the file says `cases[0].dampers[0].KEY`)."""

import subprocess

import pytest

import shotdamp as sd

GOOD_STRUCTURE = dict(
    masses_kg=[0.74, 0.71, 0.64],
    chain_stiffness_n_per_m=[24.3e3, 21.8e3, 19.8e3],
    modal_ratios=[0.01, 0.01, 0.01],
)
GOOD_DAMPER = dict(mass=2, mass_ratio=0.1, clearance_mm=0.3)


def toml_value(v):
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, str):
        return f'"{v}"'
    if isinstance(v, float):
        if v != v:
            return "nan"
        if v in (float("inf"), float("-inf")):
            return "inf" if v > 0 else "-inf"
        return repr(v)
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(toml_value(x) for x in v) + "]"
    return str(v)


def experiment_file(path, structure, damper, force_n=2.6):
    damping = {k: structure[k] for k in ("modal_ratios", "rayleigh_alpha", "rayleigh_beta") if k in structure}
    rest = {k: v for k, v in structure.items() if k not in damping}
    lines = [
        "[experiment]",
        'id = "bad"',
        'title = "bad input"',
        'figure = "none"',
        'caption = "a bad value"',
        'claim = "none"',
        "[structure]",
        *[f"{k} = {toml_value(v)}" for k, v in rest.items()],
        "[structure.damping]",
        *[f"{k} = {toml_value(v)}" for k, v in damping.items()],
        "[excitation]",
        "mass = 1",
        f"force_n = {toml_value(force_n)}",
        "[analysis]",
        'kind = "sweep"',
        "freq_hz = { start = 44.0, stop = 45.0, step = 0.5 }",
        "[[cases]]",
        'id = "one"',
        'label = "one damper"',
        "dampers = [{ " + ", ".join(f"{k} = {toml_value(v)}" for k, v in damper.items()) + " }]",
    ]
    path.write_text("\n".join(lines) + "\n")


def cli_message(cli, tmp_path, structure, damper, force_n=2.6):
    f = tmp_path / "bad.toml"
    experiment_file(f, structure, damper, force_n)
    p = subprocess.run([str(cli), "run", str(f), "--out", str(tmp_path / "out")], capture_output=True, text=True)
    assert p.returncode == 2, p.stderr
    line = p.stderr.strip().splitlines()[-1]
    prefix = f"error: {f}: "
    assert line.startswith(prefix), line
    return line[len(prefix):].replace("cases[0].dampers", "dampers")


def python_message(structure, damper, force_n=2.6):
    with pytest.raises(ValueError) as e:
        s = sd.Structure(**structure)
        sd.System(s, [sd.Damper(**damper)], force_n=force_n)
    text = str(e.value)
    origin, _, rest = text.partition(": ")
    assert origin in ("shotdamp.Structure", "shotdamp.Damper", "shotdamp.System"), text
    # A Damper is checked when it is built, before it is in a case: its keys are `damper.KEY`.
    return rest.replace("damper.", "dampers[0].") if origin == "shotdamp.Damper" else rest


CASES = [
    ("negative mass", dict(GOOD_STRUCTURE, masses_kg=[0.74, -0.71, 0.64]), GOOD_DAMPER, 2.6),
    ("NaN damping", dict(GOOD_STRUCTURE, modal_ratios=[0.01, float("nan"), 0.01]), GOOD_DAMPER, 2.6),
    ("too few stiffnesses", dict(GOOD_STRUCTURE, chain_stiffness_n_per_m=[24.3e3, 21.8e3]), GOOD_DAMPER, 2.6),
    ("infinite stiffness", dict(GOOD_STRUCTURE, chain_stiffness_n_per_m=[24.3e3, float("inf"), 1.0]), GOOD_DAMPER, 2.6),
    (
        "matrix of the wrong shape",
        {k: v for k, v in GOOD_STRUCTURE.items() if k != "chain_stiffness_n_per_m"}
        | {"stiffness_matrix_n_per_m": [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]},
        GOOD_DAMPER,
        2.6,
    ),
    (
        "masses and a mass matrix both",
        dict(GOOD_STRUCTURE, mass_matrix_kg=[[0.74, 0.0, 0.0], [0.0, 0.71, 0.0], [0.0, 0.0, 0.64]]),
        GOOD_DAMPER,
        2.6,
    ),
    (
        "mass matrix not symmetric",
        {k: v for k, v in GOOD_STRUCTURE.items() if k != "masses_kg"}
        | {"mass_matrix_kg": [[0.74, 0.1, 0.0], [0.0, 0.71, 0.0], [0.0, 0.0, 0.64]]},
        GOOD_DAMPER,
        2.6,
    ),
    ("no damping", {k: v for k, v in GOOD_STRUCTURE.items() if k != "modal_ratios"}, GOOD_DAMPER, 2.6),
    ("negative mass ratio", GOOD_STRUCTURE, dict(GOOD_DAMPER, mass_ratio=-0.1), 2.6),
    ("host mass 4 of 3", GOOD_STRUCTURE, dict(GOOD_DAMPER, mass=4), 2.6),
    ("negative clearance", GOOD_STRUCTURE, dict(GOOD_DAMPER, clearance_mm=-0.3), 2.6),
    ("unknown bed", GOOD_STRUCTURE, dict(GOOD_DAMPER, bed="foam"), 2.6),
    ("half a grain", GOOD_STRUCTURE, dict(GOOD_DAMPER, bed="column", grains=0.5), 2.6),
    ("restitution above 1", GOOD_STRUCTURE, dict(GOOD_DAMPER, bed="restitution", restitution=1.5), 2.6),
    ("negative force", GOOD_STRUCTURE, GOOD_DAMPER, -1.0),
    ("NaN force", GOOD_STRUCTURE, GOOD_DAMPER, float("nan")),
]


@pytest.mark.parametrize("name,structure,damper,force_n", CASES, ids=[c[0] for c in CASES])
def test_bad_arguments_raise_the_command_lines_message(cli, tmp_path, name, structure, damper, force_n):
    assert python_message(structure, damper, force_n) == cli_message(cli, tmp_path, structure, damper, force_n)


def test_unknown_keys_and_wrong_types_name_the_key():
    with pytest.raises(ValueError, match=r"shotdamp\.Damper: damper\.mass_ratio"):
        sd.Damper(mass=2, mass_ratio="much", clearance_mm=0.3)
    with pytest.raises(TypeError):
        sd.Structure(**GOOD_STRUCTURE, mases_kg=[1.0])  # a misspelt keyword


DAMPER_ALONE = [
    (dict(GOOD_DAMPER, mass_ratio=-0.1), r"damper\.mass_ratio = -0\.1: a mass ratio must be positive"),
    (dict(GOOD_DAMPER, mass=0), r"damper\.mass = 0: masses are numbered from 1"),
    (dict(mass=2, clearance_mm=0.3), r"damper\.mass_ratio = \(missing\): give exactly one of mass_ratio and mass_kg"),
    (dict(GOOD_DAMPER, mass_kg=0.1), r"damper\.mass_ratio = \(both mass_ratio and mass_kg\): give exactly one"),
    (dict(GOOD_DAMPER, clearance_mm=-0.3), r"damper\.clearance_mm = -0\.3"),
    (dict(GOOD_DAMPER, clearance_mm="scan"), r"damper\.clearance_mm = \(scan or @EXPERIMENT\.KEY\)"),
    (dict(GOOD_DAMPER, bed="foam"), r"damper\.bed"),
    (dict(GOOD_DAMPER, bed="restitution", restitution=1.5), r"damper\.restitution = 1\.5"),
    (dict(GOOD_DAMPER, bed="column", grains=0), r"damper\.grains"),
    (dict(GOOD_DAMPER, direction="sideways"), r"damper\.direction = \"sideways\""),
    (dict(GOOD_DAMPER, clearance_mm="inf", direction="horizontal"), r"damper\.clearance_mm = \"inf\": a horizontal"),
]


@pytest.mark.parametrize("damper,message", DAMPER_ALONE, ids=[m for _, m in DAMPER_ALONE])
def test_a_damper_is_checked_when_it_is_built(damper, message):
    with pytest.raises(ValueError, match=r"^shotdamp\.Damper: " + message):
        sd.Damper(**damper)
    with pytest.raises(ValueError, match=r"^shotdamp\.Damper\.from_dict: " + message):
        sd.Damper.from_dict(damper)


def test_bad_frequencies_and_options_name_the_argument():
    s = sd.System(sd.Structure(**GOOD_STRUCTURE), [sd.Damper(**GOOD_DAMPER)], force_n=2.6)
    with pytest.raises(ValueError, match=r"freq_hz\[1\] = NaN: frequencies must be positive and finite"):
        s.sweep([44.0, float("nan")])
    with pytest.raises(ValueError, match=r"freq_hz: a one-dimensional sequence"):
        s.sweep([[44.0, 45.0], [46.0, 47.0]])
    with pytest.raises(ValueError, match=r"steady\.method = \"slow\""):
        s.steady_state(48.0, steady={"method": "slow"})
    with pytest.raises(ValueError, match=r"steady\.min_periods"):
        s.steady_state(48.0, steady={"min_periods": 10, "max_periods": 5})
    with pytest.raises(ValueError, match=r"start = \"sideways\""):
        s.sweep([44.0], start="sideways")
    with pytest.raises(ValueError, match=r"analysis\.initial_velocity_m_s"):
        s.impulse(struck_mass=1)
    with pytest.raises(OSError):
        sd.load("experiments/no_such_file.toml")


def test_jobs_out_of_range_raise_value_error():
    s = sd.System(sd.Structure(**GOOD_STRUCTURE), [sd.Damper(**GOOD_DAMPER)], force_n=2.6)
    for jobs in (-1, 0, 100000, 2**70):
        with pytest.raises(ValueError, match=rf"jobs = {jobs}: give 1 to \d+ worker threads"):
            s.sweep([44.0], jobs=jobs)
    for jobs in (2.0, "2", True):
        with pytest.raises(TypeError, match=r"jobs = .*: a whole number of worker threads, or None"):
            s.sweep([44.0], jobs=jobs)


def test_a_structure_larger_than_the_simulator_takes_is_refused_when_the_system_is_built():
    n = 257
    big = sd.Structure(masses_kg=[1.0] * n, chain_stiffness_n_per_m=[2e4] * n, modal_ratios=[0.02] * n)
    assert len(big.modes()["omega_rad_s"]) == n, "the modal analysis takes any size"
    with pytest.raises(ValueError, match=r"shotdamp\.System: structure\.masses_kg = 257 masses: shotdamp\.System runs the exact simulator, which takes at most 256 degrees of freedom"):
        sd.System(big, [sd.Damper(mass=n, mass_ratio=0.1, clearance_mm=1.0)], force_n=2.0)
    # 64 masses take 9 containers, not 10 (2^10 configurations of 128 terms each).
    n = 64
    chain = sd.Structure(masses_kg=[1.0] * n, chain_stiffness_n_per_m=[2e4] * n, modal_ratios=[0.02] * n)
    beds = [sd.Damper(mass=n - j, mass_ratio=0.01, clearance_mm=1.0) for j in range(10)]
    assert sd.System(chain, beds[:9], force_n=2.0).dof == n
    with pytest.raises(ValueError, match=r"shotdamp\.System: dampers = 10 single beds \(1024 configurations\): shotdamp\.System runs the exact simulator, which decomposes every configuration up front: at most 512 configurations on 64 degrees of freedom"):
        sd.System(chain, beds, force_n=2.0)


def test_an_impulse_outside_the_physical_range_is_refused():
    s = sd.System(sd.Structure(**GOOD_STRUCTURE), [sd.Damper(**GOOD_DAMPER)], force_n=2.6)
    for v in (1e200, 1e-9):
        with pytest.raises(ValueError, match=r"analysis\.initial_velocity_m_s = .*must lie in \[1e-6, 100\] m/s"):
            s.impulse(struck_mass=1, initial_velocity_m_s=v, duration_s=0.01, sample_rate_hz=1000)

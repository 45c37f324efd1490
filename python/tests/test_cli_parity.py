"""The package and the command line give the same numbers and files: sweeps against the
CLI's CSV tables (every column, exactly), an orbit's certificate against the table's, the
whole report byte for byte."""

import csv
import filecmp
import math
import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

import shotdamp as sd


def read_csv(path: Path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    return rows


def same(text: str, value) -> bool:
    """A CSV cell equals a value exactly (floats as written, NaN as NaN, ints, strings)."""
    if isinstance(value, str):
        return text == value
    x = float(text) if text not in ("", "NaN", "nan") else math.nan
    if math.isnan(x) or (isinstance(value, float) and math.isnan(value)):
        return math.isnan(x) and math.isnan(float(value))
    return x == float(value)


def compare_curve(rows, table: "sd.Table", curve: str):
    mine = [r for r in rows if r["curve"] == curve]
    assert len(mine) == table.rows, (curve, len(mine), table.rows)
    # The CLI's table has columns for the most containers of any case in the file.
    header = list(rows[0].keys())
    assert [c for c in header if c in table.columns] == table.columns
    for i, r in enumerate(mine):
        for name in table.columns:
            value = table[name][i]
            if name == "curve":
                continue
            value = value if isinstance(value, str) else value.item()
            assert same(r[name], value), (curve, r["freq_hz"], name, r[name], value)


@pytest.fixture(scope="module")
def cli_run(cli, tmp_path_factory):
    out = tmp_path_factory.mktemp("cli") / "runs"
    files = ["experiments/fig08_number_of_dampers.toml", "experiments/fig05_hysteresis.toml"]
    subprocess.run([str(cli), "run", *files, "--out", str(out), "--full-csv"], check=True, capture_output=True)
    return out


@pytest.mark.parametrize("model", ["stated", "coil", "fitted"])
def test_sweep_from_rest_equals_the_command_lines_csv(cli_run, model):
    rows = read_csv(cli_run / "fig08_number_of_dampers" / model / "data" / "compliance.csv")
    exp = next(e for e in sd.load("experiments/fig08_number_of_dampers.toml") if e.model == model)
    for case in exp.cases:
        freqs = [float(r["freq_hz"]) for r in rows if r["curve"] == case]
        system = exp.system(case)
        if system.containers == 0:
            continue  # the bare structure is the linear FRF, not a sweep
        for jobs in (1, 2):
            compare_curve(rows, system.sweep(np.array(freqs), curve=case, steady=exp.steady, jobs=jobs), case)


def test_continuation_equals_the_command_lines_csv(cli_run):
    rows = read_csv(cli_run / "fig05_hysteresis" / "stated" / "data" / "compliance.csv")
    exp = next(e for e in sd.load("experiments/fig05_hysteresis.toml") if e.model == "stated")
    system = exp.system("single")
    steady = exp.steady
    for word in ("up", "down"):
        curve = f"single:{word}"
        table = system.sweep(exp.freq_hz, start=word, curve=curve, steady=steady)
        # The command line's table is in order of frequency; continuation is in the order run.
        order = np.argsort(table["freq_hz"], kind="stable")
        sorted_table = sd.Table({k: ([v[i] for i in order] if isinstance(v, list) else v[order]) for k, v in table.items()})
        compare_curve(rows, sorted_table, curve)


def test_an_orbits_certificate_equals_the_tables(cli_run):
    rows = read_csv(cli_run / "fig08_number_of_dampers" / "stated" / "data" / "compliance.csv")
    exp = next(e for e in sd.load("experiments/fig08_number_of_dampers.toml") if e.model == "stated")
    case = [c for c in exp.cases if exp.system(c).containers == 3][0]
    system = exp.system(case)
    picked = [r for r in rows if r["curve"] == case and r["max_multiplier"] not in ("", "NaN")][::20]
    assert len(picked) >= 3
    for r in picked:
        st = system.steady_state(float(r["freq_hz"]))
        assert st.orbit is not None
        assert same(r["max_multiplier"], st.orbit.spectral_radius)
        assert same(r["orbit_residual"], st.orbit.residual)
        assert st.orbit.spectral_radius == pytest.approx(np.abs(st.orbit.multipliers).max(), rel=1e-15)
        assert same(r["c1"], st.compliance[0]) and same(r["c3"], st.compliance[2])


def test_the_report_equals_the_command_lines_byte_for_byte(cli, tmp_path):
    # SHOTDAMP_REPORT names a report the command line has already written (CI passes the one
    # it has just regenerated, instead of writing the whole report a second time).
    a, b = Path(os.environ.get("SHOTDAMP_REPORT", tmp_path / "cli")), tmp_path / "lib"
    if "SHOTDAMP_REPORT" not in os.environ:
        subprocess.run([str(cli), "report", "--out", str(a)], check=True, capture_output=True)
    assert (a / "index.html").is_file(), f"no report at {a}"
    done = sd.report(b)
    assert done["passed"] and done["checks"] > 100
    assert Path(done["report"]) == b.resolve()
    left = sorted(p.relative_to(a) for p in a.rglob("*") if p.is_file())
    right = sorted(p.relative_to(b) for p in b.rglob("*") if p.is_file())
    assert left == right
    differ = [str(p) for p in left if not filecmp.cmp(a / p, b / p, shallow=False)]
    assert differ == []


def test_run_experiment_returns_the_tables_it_writes(tmp_path):
    done = sd.run_experiment("experiments/fig05_hysteresis.toml", out=tmp_path / "runs", full_csv=True)
    assert done["passed"]
    stated = next(e for e in done["experiments"] if e["key"] == "fig05_hysteresis/stated")
    table = stated["tables"]["compliance"]
    rows = read_csv(tmp_path / "runs" / "fig05_hysteresis" / "stated" / "data" / "compliance.csv")
    assert table.rows == len(rows)
    for i, r in enumerate(rows):
        assert same(r["c2"], table["c2"][i].item())
    assert all(c["status"] in ("pass", "known deviation") for c in stated["checks"])


def test_study_shards_in_threads_equal_the_command_lines_whole_study(cli, tmp_path):
    import threading

    whole, parts = tmp_path / "whole", tmp_path / "parts"
    subprocess.run([str(cli), "study", "studies/fig08_report.toml", "--out", str(whole)], check=True, capture_output=True)
    threads = [
        threading.Thread(target=sd.study, args=("studies/fig08_report.toml",), kwargs=dict(out=parts, shard=f"{i}/3", jobs=1))
        for i in range(3)
    ]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    merged = sd.study_merge(parts)
    assert merged["rows"] > 0 and merged["summaries"]
    tables = sorted(p.name for p in whole.glob("*.csv"))
    assert tables and tables == sorted(p.name for p in parts.glob("*.csv"))
    for name in tables:
        assert filecmp.cmp(whole / name, parts / name, shallow=False), name
    with pytest.raises(ValueError, match="shard"):
        sd.study("studies/fig08_report.toml", out=tmp_path / "bad", shard="3/3")

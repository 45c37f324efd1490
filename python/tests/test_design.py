"""`shotdamp.design` searches design files as `shotdamp design` does: the same tables, the
same stored answer (its provenance aside), the same refusal of a file that is not a design."""

import json
import shutil
import subprocess
from pathlib import Path

import pytest

import shotdamp as sd
from test_cli_parity import read_csv, same


def tiny_frame(dir: Path) -> Path:
    """The 5-storey frame's design file, made small: two candidate floors, one start, coarse bands."""
    text = (Path("designs") / "five_storey.toml").read_text()
    text = (
        text.replace("candidates = [1, 2, 3, 4, 5]", "candidates = [4, 5]")
        .replace("max_beds = 2", "max_beds = 2\nstarts = 1\nmax_iters = 8")
        .replace("freq_hz = { start = 5.0, stop = 8.0, step = 0.1 }", "freq_hz = { start = 5.0, stop = 8.0, step = 0.5 }")
        .replace("freq_hz = { start = 16.0, stop = 21.0, step = 0.2 }", "freq_hz = { start = 16.0, stop = 21.0, step = 1.0 }")
    )
    assert "candidates = [4, 5]" in text and "step = 0.5" in text
    path = dir / "frame.toml"
    path.write_text(text)
    return path


def test_design_equals_the_command_line_and_stores_the_same_answer(cli, tmp_path):
    design = tiny_frame(tmp_path)
    # Each side stores into a reference folder of its own.
    refs = {}
    for side in ("cli", "py"):
        refs[side] = tmp_path / f"reference-{side}"
        shutil.copytree("reference", refs[side], ignore=shutil.ignore_patterns("baseline", "scans"))
    printed = subprocess.run(
        [str(cli), "--reference", str(refs["cli"]), "design", str(design), "--out", str(tmp_path / "cli"), "--store", "--jobs", "2"],
        check=True,
        capture_output=True,
        text=True,
    ).stdout
    got = sd.design(design, out=tmp_path / "py", reference=refs["py"], jobs=1, store=True)
    assert got["passed"] in (True, False)
    [exp] = got["experiments"]
    answer = exp["design"]
    assert answer["experiment"] == exp["key"] and answer["placements"], answer
    # The answer in one paragraph and the warnings, as the command line prints and pages them.
    assert exp["summary"].startswith("Put ") and "N (the bare hosts' peak acceleration" in exp["summary"], exp["summary"]
    for w in exp["warnings"]:
        assert f"warning: {w}" in printed, (w, printed)
    [stored] = got["stored"]
    stored_py = json.loads(Path(stored).read_text())
    stored_cli = json.loads((refs["cli"] / Path(stored).relative_to(refs["py"])).read_text())
    for s in (stored_py, stored_cli, answer):
        s.pop("provenance")
    # Seeded and deterministic for any thread count: the same answer as the CLI's on 2 threads.
    assert stored_py == stored_cli == answer
    # Every table equals the command line's CSV.
    for name, table in exp["tables"].items():
        rows = read_csv(tmp_path / "cli" / "design_five_storey" / "data" / f"{name}.csv")
        assert len(rows) == table.rows, name
        for i, r in enumerate(rows):
            for col in table.columns:
                value = table[col][i]
                value = value if isinstance(value, str) else value.item()
                assert same(r[col], value), (name, i, col, r[col], value)


def test_a_file_that_is_not_a_design_is_refused_as_the_command_line_does(cli, tmp_path):
    file = "experiments/fig04b_no_damper.toml"
    p = subprocess.run([str(cli), "design", file, "--out", str(tmp_path / "cli")], capture_output=True, text=True)
    assert p.returncode == 2
    with pytest.raises(ValueError) as e:
        sd.design(file, out=tmp_path / "py")
    assert str(e.value) in p.stderr, (str(e.value), p.stderr)
    assert not (tmp_path / "py").exists()


def test_ctrl_c_stops_a_design_search_at_its_next_evaluation(tmp_path):
    # The 3rd-mode search takes minutes on one thread; Ctrl-C stops it at the next layout it
    # evaluates, and no report folder is left.
    import _thread
    import threading
    import time

    out = tmp_path / "runs"
    timer = threading.Timer(1.5, _thread.interrupt_main)
    started = time.monotonic()
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        sd.design("designs/third_mode.toml", out=out, jobs=1)
    elapsed = time.monotonic() - started
    timer.cancel()
    assert elapsed < 6.0, elapsed
    assert [p.name for p in tmp_path.iterdir()] == []


def test_a_time_limit_keeps_the_best_so_far_and_stores_nothing(tmp_path):
    design = tiny_frame(tmp_path)
    refs = tmp_path / "reference"
    shutil.copytree("reference", refs, ignore=shutil.ignore_patterns("baseline", "scans"))
    got = sd.design(design, out=tmp_path / "py", reference=refs, jobs=1, store=True, time_limit=0)
    [exp] = got["experiments"]
    assert "stopped at its time limit" in exp["warnings"][0], exp["warnings"]
    assert "stopped at its time limit" in exp["partial"], exp["partial"]
    assert exp["summary"].startswith("Not a converged answer"), exp["summary"]
    assert exp["design"] is None and got["stored"] == []
    with pytest.raises(ValueError, match="time_limit"):
        sd.design(design, out=tmp_path / "py2", reference=refs, time_limit=-1.0)

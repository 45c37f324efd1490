"""Shared fixtures: the repository's root (tests run there, as the command line does) and
the command line's binary (built by `cargo build --release --locked` when missing)."""

import os
import signal
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def root() -> Path:
    return ROOT


@pytest.fixture(autouse=True)
def at_root(monkeypatch):
    monkeypatch.chdir(ROOT)


@pytest.fixture(autouse=True)
def python_handles_ctrl_c():
    # A process started in the background by a non-interactive shell (a CI job, `cmd &`)
    # inherits SIGINT ignored, and Python then leaves it ignored: `_thread.interrupt_main()`
    # would do nothing. The Ctrl-C tests need Python's own handler, as in a terminal.
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, previous)


@pytest.fixture(scope="session")
def cli() -> Path:
    # Cargo's own target folder: CARGO_TARGET_DIR when set (relative to the checkout).
    target = ROOT / os.environ.get("CARGO_TARGET_DIR", "target")
    binary = Path(os.environ.get("SHOTDAMP_BIN", target / "release" / "shotdamp"))
    if not binary.exists():
        subprocess.run(["cargo", "build", "--release", "--locked"], cwd=ROOT, check=True)
    return binary


def paper_structure(**overrides):
    import shotdamp as sd

    keys = dict(
        masses_kg=[0.74, 0.71, 0.64],
        chain_stiffness_n_per_m=[24.3e3, 21.8e3, 19.8e3],
        modal_ratios=[0.01, 0.01, 0.01],
    )
    keys.update(overrides)
    return sd.Structure(**keys)

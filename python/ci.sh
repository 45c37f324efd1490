#!/usr/bin/env bash
# CI of the Python package: lints the bindings, builds the wheel with maturin, installs it
# into a fresh virtual environment and runs its tests (python/tests). Needs python3 (3.9 or
# later) with venv and pip; the command line's release binary is built by the tests when
# missing.
set -euo pipefail
cd "$(dirname "$0")/.."

scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
python3 -m venv "$scratch/venv"
"$scratch/venv/bin/pip" install -q -r python/requirements-ci.txt

cargo clippy --release --locked -p shotdamp-python -- -D warnings
"$scratch/venv/bin/maturin" build --release --locked -m python/Cargo.toml -o "$scratch/wheels"
"$scratch/venv/bin/pip" install -q "$scratch"/wheels/shotdamp-*.whl
# From the repository root, as the command line runs; not from python/ (the source folder
# would shadow the installed package).
"$scratch/venv/bin/python" -m pytest -q -p no:cacheprovider --durations=12 python/tests

#!/usr/bin/env bash
# Runs CalculiX (ccx; Debian: apt-get install calculix-ccx) on the plate's decks in OUT
# (default: a new temporary folder) and prints OUT. Writes there:
#   plate.sti, plate.mas, plate.dof   the stiffness and mass matrices and their degrees of
#                                     freedom (*FREQUENCY, SOLVER=MATRIXSTORAGE)
#   plate_modes.dat                   CalculiX's own lowest ten natural frequencies
#   plate_free.mas, plate_free.dof    the unsupported plate's mass matrix
#   beam.sti, beam.mas, beam.dof      a cantilevered beam's matrices (against Euler-Bernoulli)
#   square.sti, square.mas, square.dof
#   square_modes.dat                  a square plate clamped on every edge (modes in equal
#                                     pairs): its matrices and CalculiX's own frequencies
# The files in data/ were written so (CalculiX 2.20); shotdamp's tests read them without ccx.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
out="${1:-$(mktemp -d)}"
mkdir -p "$out"
command -v ccx >/dev/null || { echo "ccx (CalculiX) is not installed: apt-get install calculix-ccx" >&2; exit 2; }
cp "$here"/plate_mesh.inp "$here"/plate.inp "$here"/plate_modes.inp "$here"/plate_free.inp \
    "$here"/beam_mesh.inp "$here"/beam.inp "$here"/square_mesh.inp "$here"/square.inp \
    "$here"/square_modes.inp "$out"/
cd "$out"
for job in plate plate_modes plate_free beam square square_modes; do
    # ccx prints its progress; keep it in a log, show it only when it fails.
    if ! OMP_NUM_THREADS=1 ccx -i "$job" > "$job.log" 2>&1; then
        cat "$job.log" >&2
        echo "ccx failed on $job.inp" >&2
        exit 1
    fi
done
for f in plate.sti plate.mas plate.dof plate_modes.dat plate_free.mas plate_free.dof beam.sti beam.mas beam.dof \
    square.sti square.mas square.dof square_modes.dat; do
    [ -s "$f" ] || { echo "ccx did not write $f" >&2; exit 1; }
done
echo "$out"

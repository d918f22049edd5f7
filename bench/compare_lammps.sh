#!/usr/bin/env bash
# Runs LAMMPS (bench/bed.in) and `grainlab bench bed` on the same bed and prints a Markdown table of
# particle-steps per second (median of REPEATS interleaved runs each), their ratio, memory and the physics check.
#   bash bench/compare_lammps.sh [REPEATS]        (needs: apt-get install lammps; a release build)
# Sizes: 100 x 50 (5,000) and 250 x 200 (50,000) discs, each as specified (lattice 2.02 cm, 1.5 cm
# above the floor: the timed window is free fall) and dense (discs touching from the start).
set -euo pipefail
cd "$(dirname "$0")/.."
REPEATS=${1:-3}
GRAINLAB=${GRAINLAB:-build/release/grainlab}
NSETTLE=2000
NRUN=10000
command -v lmp >/dev/null || { echo "lmp not found: apt-get install lammps" >&2; exit 2; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# shellcheck source=lammps_table.sh
source bench/lammps_table.sh

echo "| discs | variant | LAMMPS particle-steps/s | grainlab particle-steps/s | ratio | LAMMPS MB | grainlab B/particle | mean height LAMMPS / grainlab (cm) | KE LAMMPS / grainlab (erg) |"
echo "|---|---|---|---|---|---|---|---|---|"
for size in "100 50" "250 200"; do
  read -r NX NY <<<"$size"
  for variant in specified dense; do
    if [ "$variant" = dense ]; then A=2.0; Y0=1.0; else A=2.02; Y0=2.5; fi
    # Interleaved, one LAMMPS run then one grainlab run, so both see the same machine load.
    : > "$tmp/g.rates"
    for r in $(seq "$REPEATS"); do
      lmp -in bench/bed.in -var NX "$NX" -var NY "$NY" -var NSETTLE $NSETTLE -var NRUN $NRUN -var A $A -var Y0 $Y0 \
        -log none -screen "$tmp/lmp.$r" >/dev/null
      "$GRAINLAB" bench bed --nx "$NX" --ny "$NY" --settle $NSETTLE --steps $NRUN --repeats 1 \
        --spacing $A --first-row $Y0 --json "$tmp/g.json" >/dev/null 2>&1
      record_grainlab_rate
    done
    table_row $((NX*NY)) "$variant"
  done
done

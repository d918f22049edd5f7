#!/usr/bin/env bash
# Runs LAMMPS (bench/bed3d.in) and `grainlab bench bed3d` on the same sphere lattice (issue #15) and prints a
# Markdown table of particle-steps per second (median of REPEATS interleaved runs each), their ratio, memory
# and the physics check (mean height, kinetic energy after the timed steps).
#   bash bench/compare_lammps3d.sh [REPEATS] [SIZES...]   (needs: apt-get install lammps; a release build)
# SIZES are NXxNYxNZ (default 20x20x6 50x50x4 100x100x10: 2,400, 10,000 and 100,000 spheres). Each size runs
# as specified (0 settling steps: the timed window is free fall into first contact) and settled (SETTLE
# untimed steps first, default 50,000: a resting bed where contacts dominate). STEPS timed steps (2,000).
# VARIANTS="specified" (or "settled") runs only those; "poured" adds a dense random bed: the same spheres
# poured into the same box by grainlab (untimed, `bench bed3d --pour-to`), stopped and written for both codes
# (bench/bed3d_data.in reads it), then STEPS timed steps from there (POURED_SETTLE untimed ones first,
# default 0): about six contacts a sphere, loaded springs and spinning grains, as in an impact bed.
# POUR_SECONDS (default 0.3) is the pour's simulated time: a deep bed needs longer to fall into place.
# POURED=BASE times a bed poured before (BASE.toml and BASE.data from `bench bed3d --pour-to BASE`) instead of
# pouring one: a 100,000-sphere pour takes most of an hour.
set -euo pipefail
cd "$(dirname "$0")/.."
REPEATS=${1:-3}
shift || true
SIZES=${*:-20x20x6 50x50x4 100x100x10}
GRAINLAB=${GRAINLAB:-build/release/grainlab}
SETTLE=${SETTLE:-50000}
STEPS=${STEPS:-2000}
VARIANTS=${VARIANTS:-specified settled}
command -v lmp >/dev/null || { echo "lmp not found: apt-get install lammps" >&2; exit 2; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# shellcheck source=lammps_table.sh
source bench/lammps_table.sh

echo "| spheres | variant | LAMMPS particle-steps/s | grainlab particle-steps/s | ratio | LAMMPS MB | grainlab B/particle | mean height LAMMPS / grainlab (cm) | KE LAMMPS / grainlab (erg) |"
echo "|---|---|---|---|---|---|---|---|---|"
for size in $SIZES; do
  IFS=x read -r NX NY NZ <<<"$size"
  for variant in $VARIANTS; do
    case "$variant" in
      settled) S=$SETTLE ;;
      poured) S=${POURED_SETTLE:-0}
        if [ -n "${POURED:-}" ]; then
          cp "$POURED.toml" "$tmp/poured.toml" && cp "$POURED.data" "$tmp/poured.data"
        else
          "$GRAINLAB" bench bed3d --nx "$NX" --ny "$NY" --nz "$NZ" --pour-to "$tmp/poured" \
            --pour-seconds "${POUR_SECONDS:-0.3}" >/dev/null 2>&1
        fi ;;
      *) S=0 ;;
    esac
    # Interleaved, one LAMMPS run then one grainlab run, so both see the same machine load.
    : > "$tmp/g.rates"
    for r in $(seq "$REPEATS"); do
      if [ "$variant" = poured ]; then
        lmp -in bench/bed3d_data.in -var DATA "$tmp/poured.data" -var NSETTLE "$S" -var NRUN "$STEPS" \
          -log none -screen "$tmp/lmp.$r" >/dev/null
        "$GRAINLAB" bench bed3d --bed-scene "$tmp/poured.toml" --settle "$S" --steps "$STEPS" --repeats 1 \
          --json "$tmp/g.json" >/dev/null 2>&1
      else
        lmp -in bench/bed3d.in -var NX "$NX" -var NY "$NY" -var NZ "$NZ" -var NSETTLE "$S" -var NRUN "$STEPS" \
          -log none -screen "$tmp/lmp.$r" >/dev/null
        "$GRAINLAB" bench bed3d --nx "$NX" --ny "$NY" --nz "$NZ" --settle "$S" --steps "$STEPS" --repeats 1 \
          --json "$tmp/g.json" >/dev/null 2>&1
      fi
      record_grainlab_rate
    done
    table_row $((NX*NY*NZ)) "$variant"
  done
done

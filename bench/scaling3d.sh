#!/usr/bin/env bash
# Strong scaling of the distributed 3-D sphere kernel on `grainlab bench bed3d` (docs/parallel.md).
#   bash bench/scaling3d.sh [REPEATS] > bench/scaling3d.md       (a release build; Open MPI's mpirun)
# The issue's lattice (bench/bed3d.in) at 10,000 and 100,000 spheres, as specified (2,000 steps of free fall
# into first contact) and, at 10,000, settled (the same steps after SETTLE untimed ones), on 1 and 2 ranks;
# efficiency T1 / (2 T2). One- and two-rank runs alternate so both see the same machine load; medians of
# REPEATS runs are quoted, and both runs' mean height and kinetic energy are printed to show the same physics.
# The machine's own ceiling is measured beside them: two one-rank runs at once (T1 twin, the slower of the
# two). If the cores slow each other down (shared cache, memory bandwidth, or two vCPUs on one physical
# core), no program can beat T1 / T1twin on 2 ranks; the efficiency is quoted against it too.
set -euo pipefail
cd "$(dirname "$0")/.."
REPEATS=${1:-3}
STEPS=${STEPS:-2000}
SETTLE=${SETTLE:-50000}
GRAINLAB=${GRAINLAB:-build/release/grainlab}
MPIRUN="mpirun --allow-run-as-root --oversubscribe -np"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

median() { sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }
field() { /usr/bin/python3 -c "import json;print(json.load(open('$1'))['$2'])"; }

echo "Measured $(date -u +%Y-%m-%d) on $(nproc) cores, $STEPS timed steps, median of $REPEATS alternating runs."
echo
echo "| spheres | variant | T1 (s) | T2 (s) | efficiency | T1 twin (s) | ceiling T1 / T1 twin | efficiency / ceiling | mean height 1 / 2 ranks (cm) | kinetic energy 1 / 2 ranks (erg) |"
echo "|---|---|---|---|---|---|---|---|---|---|"
for row in "50 50 4 specified 0" "50 50 4 settled $SETTLE" "100 100 10 specified 0"; do
  read -r NX NY NZ VARIANT S <<<"$row"
  : > "$tmp/t1"; : > "$tmp/t2"; : > "$tmp/tt"
  bench() { "$GRAINLAB" bench bed3d --nx "$NX" --ny "$NY" --nz "$NZ" --settle "$S" --steps "$STEPS" --repeats 1 "$@"; }
  for r in $(seq "$REPEATS"); do
    for ranks in 1 2; do
      $MPIRUN "$ranks" "$GRAINLAB" bench bed3d --nx "$NX" --ny "$NY" --nz "$NZ" --settle "$S" --steps "$STEPS" \
        --repeats 1 --json "$tmp/r$ranks.json" >/dev/null 2>&1
      field "$tmp/r$ranks.json" median_seconds >> "$tmp/t$ranks"
    done
    bench --json "$tmp/twin_a.json" >/dev/null 2>&1 &
    bench --json "$tmp/twin_b.json" >/dev/null 2>&1
    wait
    awk -v a="$(field "$tmp/twin_a.json" median_seconds)" -v b="$(field "$tmp/twin_b.json" median_seconds)" \
      'BEGIN {print (a > b ? a : b)}' >> "$tmp/tt"
  done
  t1=$(median < "$tmp/t1"); t2=$(median < "$tmp/t2"); tt=$(median < "$tmp/tt")
  eff=$(awk -v a="$t1" -v b="$t2" 'BEGIN {printf "%.2f", a / (2 * b)}')
  ceil=$(awk -v a="$t1" -v b="$tt" 'BEGIN {printf "%.2f", a / b}')
  rel=$(awk -v e="$eff" -v c="$ceil" 'BEGIN {printf "%.2f", e / c}')
  printf "| %d | %s | %.3f | %.3f | **%s** | %.3f | %s | %s | %.6f / %.6f | %.6g / %.6g |\n" $((NX*NY*NZ)) "$VARIANT" "$t1" "$t2" "$eff" "$tt" "$ceil" "$rel" \
    "$(field "$tmp/r1.json" mean_height)" "$(field "$tmp/r2.json" mean_height)" \
    "$(field "$tmp/r1.json" kinetic_energy)" "$(field "$tmp/r2.json" kinetic_energy)"
done

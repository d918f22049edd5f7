#!/usr/bin/env bash
# Dynamic load balancing on a moving load (docs/parallel.md): scenes/avalanche.toml, 20,000 discs
# sliding down a slope, on one rank, and on two ranks with fixed slabs and with slabs re-split every
# 1,000 steps. Runs alternate; medians of REPEATS wall times (the run's own "wall" figure, rank 0's
# stepping time). All three runs must write the same datasets (h5diff).
#   bash bench/balance.sh [REPEATS] > bench/balance.md
set -euo pipefail
cd "$(dirname "$0")/.."
REPEATS=${1:-3}
GRAINLAB=${GRAINLAB:-build/release/grainlab}
SCENE=${SCENE:-scenes/avalanche.toml}
MPIRUN="mpirun --allow-run-as-root --oversubscribe -np"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
median() { sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }
wall() { grep -o 'wall [0-9.]*' "$1" | awk '{print $2}'; }

for r in $(seq "$REPEATS"); do
  "$GRAINLAB" run "$SCENE" --out "$tmp/one.h5" --force 2> "$tmp/one.log"
  $MPIRUN 2 "$GRAINLAB" run "$SCENE" --out "$tmp/fixed.h5" --force --balance-every 0 2> "$tmp/fixed.log"
  $MPIRUN 2 "$GRAINLAB" run "$SCENE" --out "$tmp/balanced.h5" --force --balance-every 1000 2> "$tmp/balanced.log"
  for k in one fixed balanced; do wall "$tmp/$k.log" >> "$tmp/$k.walls"; done
done
t1=$(median < "$tmp/one.walls"); tf=$(median < "$tmp/fixed.walls"); tb=$(median < "$tmp/balanced.walls")
same=yes
for k in fixed balanced; do
  h5diff --exclude-attribute / --exclude-attribute /diagnostics "$tmp/one.h5" "$tmp/$k.h5" >/dev/null || same=NO
done
echo "Measured $(date -u +%Y-%m-%d) on $(nproc) cores: $SCENE, median of $REPEATS alternating runs."
echo
echo "| run | wall (s) | efficiency T1 / (2 T2) |"
echo "|---|---|---|"
echo "| 1 rank | $t1 | |"
awk -v a="$t1" -v b="$tf" 'BEGIN {printf "| 2 ranks, fixed slabs | %s | **%.3f** |\n", b, a / (2 * b)}'
awk -v a="$t1" -v b="$tb" 'BEGIN {printf "| 2 ranks, slabs re-split every 1,000 steps | %s | **%.3f** |\n", b, a / (2 * b)}'
echo
echo "Same datasets in all three files (h5diff): $same."

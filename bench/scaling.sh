#!/usr/bin/env bash
# Strong and weak scaling of the distributed native engine on `grainlab bench bed` (docs/parallel.md).
#   bash bench/scaling.sh [REPEATS] > bench/scaling.md       (a release build; Open MPI's mpirun)
# Strong: the same bed (20,000 and 100,000 discs, dense and as specified) on 1 and 2 ranks,
# efficiency T1 / (2 T2). Weak: 50,000 discs per rank (1,000 x 50 on one rank, 2,000 x 50 on two),
# efficiency T1 / T2. One- and two-rank runs alternate, so both see the same machine load; medians of
# REPEATS runs are quoted. Communication share and imbalance come from the two-rank run of median time.
set -euo pipefail
cd "$(dirname "$0")/.."
REPEATS=${1:-3}
STEPS=${STEPS:-4000}
SETTLE=${SETTLE:-1000}
GRAINLAB=${GRAINLAB:-build/release/grainlab}
MPIRUN="mpirun --allow-run-as-root --oversubscribe -np"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

median() { sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }
field() { /usr/bin/python3 -c "import json;print(json.load(open('$1'))['$2'])"; }

bed() {  # ranks nx variant json
  local A=2.02 Y0=2.5
  if [ "$3" = dense ]; then A=2.0; Y0=1.0; fi
  $MPIRUN "$1" "$GRAINLAB" bench bed --nx "$2" --ny 50 --settle "$SETTLE" --steps "$STEPS" --repeats 1 \
    --spacing $A --first-row $Y0 --json "$4" >/dev/null 2>&1
}

echo "Measured $(date -u +%Y-%m-%d) on $(nproc) cores, $STEPS timed steps after $SETTLE settling, median of $REPEATS alternating runs."
echo
echo "| kind | variant | discs (1 rank / 2 ranks) | T1 (s) | T2 (s) | efficiency | communication share | load imbalance | ghosts | same physics |"
echo "|---|---|---|---|---|---|---|---|---|---|"
for kind in strong:400 strong:2000 weak:1000; do
  mode=${kind%%:*}; nx1=${kind##*:}; nx2=$nx1
  [ "$mode" = weak ] && nx2=$((2 * nx1))
  for variant in dense specified; do
    : > "$tmp/t1"; : > "$tmp/t2"
    for r in $(seq "$REPEATS"); do
      bed 1 "$nx1" "$variant" "$tmp/one.$r.json"
      bed 2 "$nx2" "$variant" "$tmp/two.$r.json"
      echo "$(field "$tmp/one.$r.json" median_seconds) $r" >> "$tmp/t1"
      echo "$(field "$tmp/two.$r.json" median_seconds) $r" >> "$tmp/t2"
    done
    t1=$(cut -d' ' -f1 "$tmp/t1" | median)
    t2=$(cut -d' ' -f1 "$tmp/t2" | median)
    r2=$(sort -g "$tmp/t2" | awk '{a[NR]=$2} END {print a[int((NR+1)/2)]}')
    two="$tmp/two.$r2.json"
    if [ "$mode" = strong ]; then eff=$(awk -v a="$t1" -v b="$t2" 'BEGIN {printf "%.3f", a / (2 * b)}')
    else eff=$(awk -v a="$t1" -v b="$t2" 'BEGIN {printf "%.3f", a / b}'); fi
    same=n/a
    if [ "$mode" = strong ]; then
      h1=$(field "$tmp/one.1.json" mean_height); h2=$(field "$two" mean_height)
      k1=$(field "$tmp/one.1.json" kinetic_energy); k2=$(field "$two" kinetic_energy)
      [ "$h1" = "$h2" ] && [ "$k1" = "$k2" ] && same="yes (height, KE)" || same="NO: $h1/$h2 $k1/$k2"
    fi
    printf "| %s | %s | %d / %d | %.3f | %.3f | **%s** | %.1f %% | %.3f | %s | %s |\n" "$mode" "$variant" \
      $((nx1 * 50)) $((nx2 * 50)) "$t1" "$t2" "$eff" \
      "$(awk -v s="$(field "$two" share_communication)" 'BEGIN {print 100 * s}')" \
      "$(field "$two" imbalance)" "$(field "$two" ghosts)" "$same"
  done
done

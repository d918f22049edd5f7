# Shared by compare_lammps.sh (2-D) and compare_lammps3d.sh (3-D): sourced, not run. After REPEATS
# interleaved runs that left LAMMPS screens in $tmp/lmp.R and grainlab rates in $tmp/g.rates (and the
# last grainlab JSON in $tmp/g.json), print one Markdown row: particles, variant, the two medians, their
# ratio, LAMMPS's memory, grainlab's bytes per particle, and both codes' mean height and kinetic energy.

median() { sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }

# Appends the particle-steps/s of $tmp/g.json to $tmp/g.rates.
record_grainlab_rate() {
  /usr/bin/python3 -c "import json;print(json.load(open('$tmp/g.json'))['particle_steps_per_second'])" >> "$tmp/g.rates"
}

# table_row PARTICLES VARIANT
table_row() {
  # The last "Loop time" line is the timed run (an earlier one is the settling run).
  local lmp_rate g_rate lmp_mem lmp_h lmp_ke g_bytes g_h g_ke ratio
  lmp_rate=$(for r in $(seq "$REPEATS"); do
    awk '/^Loop time/ {t=$4; n=$9; a=$12} END {printf "%.6g\n", a*n/t}' "$tmp/lmp.$r"; done | median)
  g_rate=$(median < "$tmp/g.rates")
  lmp_mem=$(awk '/memory allocation/ {m=$(NF-1)} END {print m}' "$tmp/lmp.1")
  lmp_h=$(awk '/^RESULT/ {print $5}' "$tmp/lmp.1")
  lmp_ke=$(awk '/^RESULT/ {print $7}' "$tmp/lmp.1")
  read -r g_bytes g_h g_ke < <(/usr/bin/python3 -c "import json;d=json.load(open('$tmp/g.json'));print(d['bytes_per_particle'],d['mean_height'],d['kinetic_energy'])")
  ratio=$(awk -v a="$g_rate" -v b="$lmp_rate" 'BEGIN {printf "%.2f", a/b}')
  printf "| %d | %s | %.3g | %.3g | **%s** | %s | %.0f | %s / %.6f | %s / %.6g |\n" "$1" "$2" "$lmp_rate" \
    "$g_rate" "$ratio" "$lmp_mem" "$g_bytes" "$lmp_h" "$g_h" "$lmp_ke" "$g_ke"
}

#!/usr/bin/env bash
# Regression of the seed experiment at low cost: settle the seed bed, then run scenes/oscillating_tank_quick.toml
# (l0 = 10 mm) for three periods and check what must hold whatever the numbers: it finishes, every grain and every
# fluid particle is still there and inside the tank, the fluid volume is kept within 1 %, the PPE converged, the bed
# is still a bed (class centroids within the bed's height), and it sorts the seed's way: over the second half of the
# third period the large grains' centroid is more than 0.5 mm above its start and the small grains' more than 0.3 mm
# below (+0.85 and -0.62 mm on the settled bed with the calibrated rolling friction 0.1, which slows the sorting about
# twice; +1.25 and -0.91 with 0.05; +2.1 and -1.2 without). The small grains' sinking is the telling half: the
# shaken bed dilates, which lifts every class. Exact numbers are not checked.
#
#   bash tests/regression/oscillating_quick.sh <riffle-binary> <source-dir> <work-dir>
#
# Everything is written under <work-dir>: the scenes are copied to <work-dir>/scenes, so the quick scene's
# initial_state ("../out/dry_bed_settle/checkpoints/final.ckpt", relative to the scene) names
# <work-dir>/out/dry_bed_settle/checkpoints/final.ckpt. That bed is the source tree's settled bed when one exists
# and this riffle accepts it (it is only read), else it is settled here: scenes/dry_bed_settle.toml to 0.5 s of its
# 1 s (about 50 s on 2 threads), the bed at rest by then (its kinetic energy 0.05 J at 0.05 s, 3e-7 J at 0.35 s, below
# 1e-6 J after). CSV columns are found by their header name.
set -u
RIFFLE=$(realpath "$1") || exit 2
SRC=$2
WORK=$3
rm -rf "$WORK" && mkdir -p "$WORK/scenes" "$WORK/out/dry_bed_settle/checkpoints" || exit 2
cp "$SRC/scenes/oscillating_tank_quick.toml" "$SRC/scenes/dry_bed_settle.toml" "$WORK/scenes/" || exit 2
cd "$WORK" || exit 2
failed=0
fail() { echo "not ok - $1"; failed=$((failed + 1)); }
pass() { echo "ok - $1"; }

settled=out/dry_bed_settle/checkpoints/final.ckpt
[ -f "$SRC/$settled" ] && cp "$SRC/$settled" "$settled"
if [ ! -f "$settled" ] || ! "$RIFFLE" check scenes/oscillating_tank_quick.toml >/dev/null 2>&1; then
  rm -rf out/dry_bed_settle
  "$RIFFLE" run scenes/dry_bed_settle.toml --out out/dry_bed_settle --until 0.5 --threads 2 >settle.log 2>&1 ||
    { echo "settling the bed failed"; tail -5 settle.log; exit 1; }
fi
if "$RIFFLE" run scenes/oscillating_tank_quick.toml --out quick --until 1.7647 --threads 2 >run.log 2>&1; then
  pass "the quick seed scene runs three periods"
else
  fail "the quick seed scene runs three periods"; tail -5 run.log; exit 1
fi

# awk with the first row read as a header: col["name"] is that column's number; a missing column fails the check.
# Usage: by_header '<program using $col["..."]>' file name...   (the names listed are required to exist; the
# header's own variables start with h, so the program must not use hk, hn or hnames)
by_header() {
  local program=$1 file=$2
  shift 2
  awk -F, -v required="$*" '
    NR == 1 { for (hk = 1; hk <= NF; ++hk) col[$hk] = hk
              hn = split(required, hnames, " ")
              for (hk = 1; hk <= hn; ++hk)
                if (!(hnames[hk] in col)) { print "no column " hnames[hk] " in " FILENAME; exit 2 }
              next }
    '"$program" "$file"
}

# Fluid totals: particle count constant, volume within 1 % of the filled box's, residuals converged. The first row
# (t = 0, before the first solve) carries the count only.
by_header 'NR == 2 { n = $col["fluid_particles"]; v0 = 0.24 * 0.16 * 0.06 }
           NR > 2 { if ($col["fluid_particles"] != n) bad = "fluid particle count changed"
                    v = $col["volume_m3"]
                    if (v < 0.99 * v0 || v > 1.01 * v0) bad = "fluid volume off by more than 1 %: " v
                    if ($col["ppe_residual"] > 1e-6) bad = "PPE residual " $col["ppe_residual"] }
           END { if (bad != "") { print bad; exit 1 } }' quick/probe_fluid_totals.csv \
  fluid_particles volume_m3 ppe_residual \
  && pass "fluid particles and volume conserved, PPE converged" || fail "fluid particles and volume conserved, PPE converged"
# Grains: count, inside the tank, centroids inside the bed (every class_*_centroid_m column of the last row).
by_header '{ last = $0 }
           END { n = split(last, value, ",")
                 for (name in col) if (name ~ /^class_[0-9]+_centroid_m$/) {
                   ++classes; z = value[col[name]]
                   if (z < 0.0 || z > 0.06) { print "centroid out of the bed: " name " = " z; exit 1 } }
                 if (classes != 3) { print "expected 3 class centroids, found " classes; exit 1 } }' \
  quick/class_centroids.csv \
  && pass "class centroids stay inside the bed (0-6 cm)" || fail "class centroids stay inside the bed (0-6 cm)"
grep -q "8162 grains" run.log && pass "8162 grains" || fail "8162 grains"
# Sorting direction: class 0 small, class 2 large; mean over t/T in [2.45, 3.05] against the start.
by_header 'NR == 2 { small0 = $col["class_0_centroid_m"]; large0 = $col["class_2_centroid_m"] }
           NR > 2 && $col["t_over_T"] >= 2.45 && $col["t_over_T"] <= 3.05 {
             small += $col["class_0_centroid_m"]; large += $col["class_2_centroid_m"]; n++ }
           END { if (n == 0) { print "no centroid rows in the third period"; exit 1 }
                 rise = 1000 * (large / n - large0); sink = 1000 * (small0 - small / n)
                 printf "#   large grains rose %.2f mm, small grains sank %.2f mm\n", rise, sink
                 if (rise <= 0.5 || sink <= 0.3) exit 1 }' quick/class_centroids.csv \
  t_over_T class_0_centroid_m class_2_centroid_m \
  && pass "the bed sorts the seed's way (large up, small down)" || fail "the bed sorts the seed's way (large up, small down)"
echo "$((failed == 0 ? 1 : 0)) passed all, $failed failed"
[ "$failed" -eq 0 ]

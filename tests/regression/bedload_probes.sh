#!/usr/bin/env bash
# The bed-load probes on the seed bed: scenes/oscillating_tank_quick.toml with the five bed-load probes added runs
# 0.05 s, and each probe file has its header (the columns of the bed's three size classes) and one row per 0.01 s
# (the velocity profile one line per layer: 20 layers of 1 cm over the 20 cm tank); the values are sane (fractions
# and lambda in [0, 1], the solid fraction of the lowest layers that of a packed bed). Then tools/riffle-tools
# bedload-plots draws its figures from them.
#
#   bash tests/regression/bedload_probes.sh <riffle-binary> <source-dir> <work-dir> [<seed-quick-work-dir>]
#
# Needs the settled seed bed: <source-dir>/out/dry_bed_settle/checkpoints/final.ckpt, or else the one
# tests/regression/oscillating_quick.sh settled in its work directory (the optional 4th argument); without either
# the test is skipped (exit 77).
set -u
RIFFLE=$(realpath "$1") || exit 2
SRC=$(realpath "$2") || exit 2
WORK=$3
settled="$SRC/out/dry_bed_settle/checkpoints/final.ckpt"
if [ ! -f "$settled" ] && [ $# -ge 4 ]; then settled="$(realpath "$4")/out/dry_bed_settle/checkpoints/final.ckpt"; fi
[ -f "$settled" ] || { echo "skipped: no settled bed at $settled"; exit 77; }
rm -rf "$WORK" && mkdir -p "$WORK/scenes" "$WORK/out/dry_bed_settle/checkpoints" || exit 2
cp "$SRC/scenes/oscillating_tank_quick.toml" "$WORK/scenes/" || exit 2
ln -s "$settled" "$WORK/out/dry_bed_settle/checkpoints/final.ckpt" || exit 2
cat >>"$WORK/scenes/oscillating_tank_quick.toml" <<'PROBES'

[[output.probes]]
kind = "moving_fraction"
interval = 0.01

[[output.probes]]
kind = "packing_density"
interval = 0.01

[[output.probes]]
kind = "bedload_flux"
interval = 0.01

[[output.probes]]
kind = "velocity_profile"
interval = 0.01

[[output.probes]]
kind = "bed_shear_stress"
interval = 0.01
PROBES
cd "$WORK" || exit 2
failed=0
fail() { echo "not ok - $1"; failed=$((failed + 1)); }
pass() { echo "ok - $1"; }
if "$RIFFLE" run scenes/oscillating_tank_quick.toml --out run --until 0.05 --threads 1 >run.log 2>&1; then
  pass "the quick seed scene with the bed-load probes runs 0.05 s"
else
  fail "the quick seed scene with the bed-load probes runs 0.05 s"; tail -5 run.log; exit 1
fi

# header_is FILE EXPECTED: the first line of FILE is EXPECTED.
header_is() {
  local got
  got=$(head -1 "$1")
  [ "$got" = "$2" ] && pass "$1 header" || { fail "$1 header"; echo "#   got      $got"; echo "#   expected $2"; }
}
# rows_are FILE N: FILE has N lines after its header.
rows_are() {
  local got
  got=$(($(wc -l <"$1") - 1))
  [ "$got" -eq "$2" ] && pass "$1 has $2 rows" || fail "$1 has $got rows, expected $2"
}
header_is run/probe_moving_fraction.csv \
  "time_s,step,class_0_moving_fraction,class_1_moving_fraction,class_2_moving_fraction,all_moving_fraction"
header_is run/probe_packing_density.csv "time_s,step,lambda,top_layer_grains"
header_is run/probe_bedload_flux.csv "time_s,step,class_0_q_m2_s,class_1_q_m2_s,class_2_q_m2_s,all_q_m2_s,\
class_0_q_mean_m2_s,class_1_q_mean_m2_s,class_2_q_mean_m2_s,all_q_mean_m2_s"
header_is run/probe_velocity_profile.csv \
  "time_s,step,layer,z_low_m,z_high_m,fluid_particles,fluid_ux_m_s,grain_ux_m_s,solid_fraction"
header_is run/probe_bed_shear_stress.csv "time_s,step,grains_fx_N,floor_fx_N,tau_b_Pa,class_0_diameter_m,\
class_1_diameter_m,class_2_diameter_m,class_0_shields_b,class_1_shields_b,class_2_shields_b"
for probe in moving_fraction packing_density bedload_flux bed_shear_stress; do rows_are "run/probe_$probe.csv" 6; done
rows_are run/probe_velocity_profile.csv 120
awk -F, 'NR > 1 { for (k = 3; k <= NF; ++k) if ($k == "" || $k < 0 || $k > 1) bad = 1 } END { exit bad }' \
  run/probe_moving_fraction.csv && pass "moving fractions in [0, 1]" || fail "moving fractions in [0, 1]"
awk -F, 'NR > 1 { if ($3 < 0.3 || $3 > 1 || $4 < 100) bad = 1 } END { exit bad }' run/probe_packing_density.csv \
  && pass "lambda of the top layer in [0.3, 1], over 100 grains in it" \
  || fail "lambda of the top layer in [0.3, 1], over 100 grains in it"
# The bed fills the lowest 3 cm: its lowest layers hold a packed bed's solid fraction (0.5-0.7), the top layer none.
awk -F, 'NR > 1 && $3 == 1 { if ($9 < 0.45 || $9 > 0.7) bad = 1 } NR > 1 && $3 == 19 { if ($9 != 0) bad = 1 }
         END { exit bad }' run/probe_velocity_profile.csv \
  && pass "solid fraction of a packed bed low down, none at the top" \
  || fail "solid fraction of a packed bed low down, none at the top"
awk -F, 'NR > 1 { for (k = 3; k <= NF; ++k) if ($k == "") bad = 1 } END { exit bad }' run/probe_bed_shear_stress.csv \
  && pass "bed shear stress rows complete" || fail "bed shear stress rows complete"
if [ -x /usr/bin/python3 ]; then
  /usr/bin/python3 "$SRC/tools/riffle-tools" bedload-plots run >plots.log 2>&1 \
    && [ "$(grep -c '^wrote' plots.log)" -eq 5 ] \
    && pass "tools/riffle-tools bedload-plots draws its five figures" \
    || { fail "tools/riffle-tools bedload-plots draws its five figures"; cat plots.log; }
fi
echo "$((failed == 0 ? 1 : 0)) passed all, $failed failed"
[ "$failed" -eq 0 ]

#!/usr/bin/env bash
# Verification of the drag coupling against Ergun's equation (a fixed bed): water driven by a falling head through a
# fixed plug of 5 mm grains (scenes/ergun_plug.toml) must lose Ergun's pressure drop at the flux it carries, within
# 20 % (docs/COUPLING.md derives the tolerance: the voidage reading's tested 2 % is up to 10 % of the resistance,
# the voidage smoothing at the plug's faces takes off 8 %). The seed's pore reading of the water in the bed must
# fail the same check (it lets 6x the flux through: the check can tell a wrong coupling from a right one).
#
#   bash tests/verification/coupling/ergun_plug.sh <riffle-binary> <source-dir> <work-dir>
set -u
RIFFLE=$1 SOURCE=$2 WORK=$3
rm -rf "$WORK" && mkdir -p "$WORK"
failed=0
run() {  # scene, output directory, more riffle run options
  "$RIFFLE" run "$1" --out "$2" --threads 2 "${@:3}" >"$2.log" 2>&1 ||
    { echo "not ok - $1 did not run"; tail -5 "$2.log"; exit 1; }
}
run "$SOURCE/scenes/ergun_plug.toml" "$WORK/mixture"
if /usr/bin/python3 "$SOURCE/tools/riffle-tools" ergun-plug "$WORK/mixture" --scene "$SOURCE/scenes/ergun_plug.toml" \
    --check 0.2; then
  echo "ok - the mixture reading gives Ergun's pressure drop within 20 %"
else
  echo "not ok - the mixture reading gives Ergun's pressure drop within 20 %"; failed=1
fi
sed 's/^fluid_velocity = "mixture"/fluid_velocity = "pore"/' "$SOURCE/scenes/ergun_plug.toml" >"$WORK/ergun_pore.toml"
grep -q '^fluid_velocity = "pore"' "$WORK/ergun_pore.toml" || { echo "not ok - could not switch the scene to the pore reading"; exit 1; }
# The negative control needs only to miss by far: half the run and half the window (the same -88 % as over 0.1-0.45 s).
run "$WORK/ergun_pore.toml" "$WORK/pore" --until 0.26
# It must fail on the drop itself, not for want of frames or a tool error.
if /usr/bin/python3 "$SOURCE/tools/riffle-tools" ergun-plug "$WORK/pore" --scene "$WORK/ergun_pore.toml" \
    --window 0.1 0.25 --check 0.2 >"$WORK/pore_check.txt" 2>&1; then
  echo "not ok - the pore reading fails the check (it should be about 6x too permeable)"; failed=1
elif grep -q "^FAIL: the drop departs from Ergun's" "$WORK/pore_check.txt"; then
  echo "ok - the pore reading fails the check (6x too permeable)"
else
  echo "not ok - the pore reading's check failed for another reason:"; tail -3 "$WORK/pore_check.txt"; failed=1
fi
exit $failed

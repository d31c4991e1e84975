#!/usr/bin/python3
"""Self-test of tools/riffle-tools hindered-settling's scenes: the periodic column's listed beads are the count asked
for, inside the column, in the fill's height range, and no two overlap with the nearest image across x and y (a bead
by a seam must be seen by its neighbours across it); the walled column still uses riffle's own fill and no contact law;
the window sets the run's end; given riffle's binary and a work folder, both scenes pass `riffle check`.

Usage: /usr/bin/python3 tests/tools/test_hindered_settling.py [RIFFLE WORK]   (exit 0 = pass)
"""
import pathlib
import re
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools"))
from riffle_tools import hindered_settling as hs  # noqa: E402

failures = []


def check(condition, message):
    if not condition:
        failures.append(message)
        print("FAIL:", message)


def centres(scene_text):
    return [tuple(float(v) for v in m.groups())
            for m in re.finditer(r"position = \[([^,]+), ([^,]+), ([^\]]+)\]", scene_text)]


def main():
    count = 400
    listed = centres(hs.periodic_spheres(count, seed=3))
    check(len(listed) == count, f"{len(listed)} beads listed, {count} asked")
    radius = hs.DIAMETER / 2.0
    inside = all(0.0 <= x < hs.COLUMN and 0.0 <= y < hs.COLUMN and
                 hs.FILL_LOW + radius <= z <= hs.FILL_HIGH - radius for x, y, z in listed)
    check(inside, "every bead's centre inside the column and the fill's height range")
    closest = float("inf")
    near_seam = 0
    for a in range(len(listed)):
        xa, ya, za = listed[a]
        near_seam += 1 if min(xa, hs.COLUMN - xa, ya, hs.COLUMN - ya) < radius else 0
        for b in range(a):
            xb, yb, zb = listed[b]
            dx = (xa - xb) - hs.COLUMN * round((xa - xb) / hs.COLUMN)
            dy = (ya - yb) - hs.COLUMN * round((ya - yb) / hs.COLUMN)
            closest = min(closest, (dx * dx + dy * dy + (za - zb) ** 2) ** 0.5)
    check(closest >= hs.DIAMETER * (1.0 - 1e-9), f"closest pair {closest} m apart across the seams, diameter {hs.DIAMETER}")
    # Uniform across the seams: beads whose centre lies within a radius of a seam (riffle's fills would have none).
    check(near_seam > 0, "no bead reaches across a seam")

    walled = hs.scene(0.05, "mixture", "", 0.005, (0.15, 0.3), periodic=False)
    check("[[solids.fills]]" in walled and "[contact]" not in walled and "periodic" not in walled,
          "the walled column: riffle's fill, no contact law, no periodic axis")
    check("end_time = 0.301" in walled, "the run ends just after the window")
    periodic = hs.scene(0.05, "mixture", "", 0.005, (0.6, 1.0), periodic=True)
    check('periodic = ["x", "y"]' in periodic and "[contact]" in periodic and "[[solids.fills]]" not in periodic,
          "the periodic column: periodic along x and y, a contact law, listed beads")
    check("end_time = 1.001" in periodic, "the window's end sets the run's end")
    if len(sys.argv) == 3:
        work = pathlib.Path(sys.argv[2])
        work.mkdir(parents=True, exist_ok=True)
        for name, text in (("walled", walled), ("periodic", periodic)):
            path = work / f"{name}.toml"
            path.write_text(text)
            result = subprocess.run([sys.argv[1], "check", str(path)], capture_output=True, text=True)
            check(result.returncode == 0, f"riffle check {name}: {result.stdout}{result.stderr}")
    if failures:
        print(f"{len(failures)} check(s) failed")
        return 1
    print("hindered-settling tool: all checks passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())

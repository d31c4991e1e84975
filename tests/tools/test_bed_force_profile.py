#!/usr/bin/python3
"""Self-test of tools/riffle-tools bed-force-profile on a synthetic run directory whose answers are known by
construction.

Usage: /usr/bin/python3 tests/tools/test_bed_force_profile.py WORK_DIR   (exit 0 = pass)
"""
import pathlib
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools"))
sys.path.insert(0, str(ROOT / "tests" / "tools"))
import numpy as np  # noqa: E402
from riffle_tools import bed_force_profile  # noqa: E402
from test_seed_figures import write_pvd, write_vtp  # noqa: E402


def main():
    work = pathlib.Path(sys.argv[1])
    work.mkdir(parents=True, exist_ok=True)
    # A 0.1 x 0.1 m plan, d = 2 mm: 3 fixed grains at z = 1.5 mm, four layers of 100 free grains at 3.5 ... 9.5 mm,
    # two free grains at 11.5 mm. The bed top lies between 9.5 and 11.5 mm (the layers' count, averaged over d, is even
    # up to the last layer and zero 1 mm above it). Forces along x: 1e-5 N on each grain at 9.5 mm, 5e-6 N at 7.5 mm
    # (drag and pressure halves), 2e-5 N (viscous) on each of the two above: in all 1.54e-3 N, 0.154 Pa over the plan.
    # The fixed grains' contact forces add to the same, so the floor carries 1.0 of it. The two above move at 0.1 m/s
    # and read 0.2 m/s. A frame at t = 0 with forces 1000 times larger lies before --from and must not count.
    rng = np.random.default_rng(3)
    heights = [0.0015] * 3 + [z for z in (0.0035, 0.0055, 0.0075, 0.0095) for _ in range(100)] + [0.0115] * 2
    count = len(heights)
    points = np.column_stack([rng.uniform(0, 0.1, count), rng.uniform(0, 0.1, count), heights])
    fixed = np.array([1] * 3 + [0] * (count - 3))
    drag, pressure, viscous, contact = (np.zeros((count, 3)) for _ in range(4))
    at = np.array(heights)
    drag[at == 0.0095, 0] = 5e-6
    pressure[at == 0.0095, 0] = 5e-6
    drag[at == 0.0075, 0] = 5e-6
    viscous[at == 0.0115, 0] = 2e-5
    contact[:3, 0] = 1.54e-3 / 3
    contact[at == 0.0095, 0] = -1e-5
    velocity, read = np.zeros((count, 3)), np.zeros((count, 3))
    velocity[at == 0.0115, 0] = 0.1
    read[at == 0.0115, 0] = 0.2
    entries = []
    # Frame times as a run writes them (the steps' times, a little off the nominal 0, 1, 2 s): --from 0.6 takes the
    # last two (0.6 lies more than half the 1 s interval after 0); --from 1.0 must take the frame stamped 0.99995 s
    # too (within half the frames' interval).
    for index, (t, scale) in enumerate(((0.0, 1000.0), (0.99995, 1.0), (2.0, 1.0))):
        name = f"solids_{index}.vtp"
        write_vtp(work / name, points,
                  {"drag_force": (scale * drag, "Float64"), "pressure_force": (scale * pressure, "Float64"),
                   "viscous_force": (scale * viscous, "Float64"), "contact_force": (contact, "Float64"),
                   "velocity": (velocity, "Float64"), "fluid_velocity": (read, "Float64"), "fixed": (fixed, "Int32")})
        entries.append(f'<DataSet timestep="{t}" file="{name}"/>')
    write_pvd(work / "solids.pvd", entries)

    result = bed_force_profile.profile(str(work), 0.002, start=0.6, band=0.001, area=0.01)
    assert result["frames"] == 2, result["frames"]
    assert abs(result["total"] - 0.154) < 1e-12, result["total"]
    assert 0.0095 < result["top"] < 0.0115, result["top"]
    expected = np.array([4e-5, 1e-3, 5e-4, 0.0, 0.0]) / 1.54e-3
    assert np.allclose(result["shares"], expected, atol=1e-12), result["shares"]
    assert abs(result["floor"] - 1.0) < 1e-12 and abs(result["floor_Pa"] - 0.154) < 1e-12, result["floor"]
    assert result["frames"] == 2 and bed_force_profile.profile(str(work), 0.002, start=1.0, area=0.01)["frames"] == 2
    # The moving grains: the two above, at 0.1 m/s, reading 0.2 m/s, 11.5 mm less the top above it.
    assert result["moving"] == 2 and abs(result["moving_u"] - 0.1) < 1e-12, result["moving"]
    assert abs(result["moving_read"] - 0.2) < 1e-12, result["moving_read"]
    assert abs(result["moving_height"] - (0.0115 - result["top"])) < 1e-12, result["moving_height"]
    assert result["above"] == 2 and abs(result["above_u"] - 0.1) < 1e-12 and abs(result["above_read"] - 0.2) < 1e-12
    rows = {round(row["z_low"] * 1e3): row for row in result["rows"]}
    assert rows[1]["fixed"] == 3 and rows[1]["grains"] == 0, rows[1]
    assert rows[9]["grains"] == 100 and abs(rows[9]["fluid"] - 0.1) < 1e-12, rows[9]
    assert abs(rows[9]["from_top"] - 0.104) < 1e-12 and abs(rows[9]["contact"] + 0.1) < 1e-12, rows[9]
    assert abs(rows[11]["u_grain"] - 0.1) < 1e-12 and abs(rows[11]["u_read"] - 0.2) < 1e-12, rows[11]
    assert abs(rows[3]["from_top"] - 0.154) < 1e-12, rows[3]

    # The bed top on randomly packed beds with a known top: centres uniform in height up to 10 mm (their count,
    # averaged over a box centred on each height, falls to half exactly at 10 mm), within d / 16; the same with a
    # stray grain 10 mm below the floor, and with a thin bed (a 6 mm bed: 3 d, the seed's large bed). Movers above at
    # 1/8 of the packed count raise it to where the averaging box (9/8 d tall) holds half the packed count, the bed's
    # and theirs together: (1000 (11.125 - z) + 125 (z - 8.875)) / 2.25 = 500 per 0.25 mm at z = 10.161 mm.
    d = 0.002
    packed = rng.uniform(0.0, 0.010, 40000)
    for heights, top in ((packed, 0.010), (np.append(packed, -0.010), 0.010), (rng.uniform(0.0, 0.006, 24000), 0.006),
                         (np.concatenate([packed, rng.uniform(0.010, 0.014, 2000)]), 0.010161)):
        found = bed_force_profile.bed_top(heights, d)
        assert abs(found - top) <= d / 16, (found, top)
    print("bed_force_profile: all checks passed")


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""Self-test of tools/vtp.py and tools/seed_figures.py on a small synthetic run directory whose answers are known.

Usage: /usr/bin/python3 tests/tools/test_seed_figures.py [WORK_DIR]   (exit 0 = pass)
"""
import base64
import csv
import math
import pathlib
import struct
import sys
import tempfile

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools"))
import numpy as np  # noqa: E402
import seed_figures  # noqa: E402
import vtp  # noqa: E402


def array(name, values, kind, components=1):
    raw = np.ascontiguousarray(values, dtype={"Float64": "<f8", "Int32": "<i4", "UInt64": "<u8"}[kind]).tobytes()
    text = base64.b64encode(struct.pack("<I", len(raw)) + raw).decode()
    return (f'<DataArray type="{kind}" Name="{name}" NumberOfComponents="{components}" format="binary">\n'
            f"{text}\n</DataArray>\n")


def write_vtp(path, points, data):
    n = len(points)
    body = "".join(array(name, values, kind, 3 if np.ndim(values) == 2 else 1) for name, (values, kind) in data.items())
    path.write_text('<?xml version="1.0"?>\n<VTKFile type="PolyData" version="1.0" byte_order="LittleEndian" '
                    'header_type="UInt32">\n<PolyData>\n'
                    f'<Piece NumberOfPoints="{n}" NumberOfVerts="{n}" NumberOfLines="0" NumberOfStrips="0" '
                    f'NumberOfPolys="0">\n<PointData>\n{body}</PointData>\n<Points>\n'
                    + array("Points", points, "Float64", 3) + "</Points>\n</Piece>\n</PolyData>\n</VTKFile>\n")


def main():
    work = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else tempfile.mkdtemp(prefix="seed_figures_"))
    run = work / "run"
    (run / "vtk").mkdir(parents=True, exist_ok=True)
    f, amplitude = 1.7, 0.01
    scene = run / "scene.toml"
    scene.write_text('[tank]\nsize = [0.24, 0.16, 0.20]\n[tank.motion]\nkind = "sinusoidal"\n'
                     f"direction = [1.0, 0.0, 0.0]\namplitude = {amplitude}\nfrequency = {f}\nramp_time = 0.0\n")
    # One small grain at 10 mm, two medium at 20 mm, one large at 50 mm; all move with velocity u(t) = 0.1 m/s + tank
    radius = np.array([0.0025, 0.005, 0.005, 0.0075])
    size_class = np.array([0, 1, 1, 2], dtype=np.int32)
    points = np.array([[0.05, 0.05, 0.010], [0.10, 0.05, 0.020], [0.15, 0.05, 0.020], [0.2, 0.05, 0.050]])
    period = 1.0 / f
    times = [k * period / 8 for k in range(17)]  # two periods, frames at every eighth
    solids_pvd, fluid_pvd = [], []
    for k, t in enumerate(times):
        shift = np.array([-amplitude * math.sin(2 * math.pi * f * t), 0, 0])
        v_tank = -amplitude * 2 * math.pi * f * math.cos(2 * math.pi * f * t)
        velocity = np.tile([0.1 + v_tank, 0.0, 0.0], (4, 1))
        velocity[1, 2] = 0.3  # one medium grain moves up: T_g of layer 4 (20-25 mm) = (1/3)(0.15^2) per grain
        velocity[2, 2] = 0.0
        mass = 1318.0 * 4 / 3 * math.pi * radius ** 3
        force = np.zeros((4, 3))
        force[:, 2] = mass * 9.81  # balanced
        # The small grain drifts +10 mm along x over the two periods (in the tank's frame): the drift analysis
        # must find it; nothing else depends on x.
        drifted = points.copy()
        drifted[0, 0] += 0.01 * k / 16
        write_vtp(run / "vtk" / f"solids_{k:06d}.vtp", drifted + shift, {
            "id": (np.arange(4), "UInt64"), "velocity": (velocity, "Float64"), "radius": (radius, "Float64"),
            "mass": (mass, "Float64"), "force": (force, "Float64"), "contact_force": (force * 0.25, "Float64"),
            "drag_force": (np.zeros((4, 3)), "Float64"), "pressure_force": (force * 0.75, "Float64"),
            "size_class": (size_class, "Int32")})
        fluid_points = np.array([[0.1, 0.08, 0.0025], [0.1, 0.08, 0.0475], [0.0, 0.0, 0.0]]) + shift
        fluid_velocity = np.array([[v_tank, 0, 0], [v_tank - 0.2, 0, 0], [v_tank, 0, 0]])
        write_vtp(run / "vtk" / f"fluid_{k:06d}.vtp", fluid_points, {
            "kind": (np.array([0, 0, 1], dtype=np.int32), "Int32"), "velocity": (fluid_velocity, "Float64")})
        solids_pvd.append(f'<DataSet timestep="{t!r}" group="" part="0" file="vtk/solids_{k:06d}.vtp"/>')
        fluid_pvd.append(f'<DataSet timestep="{t!r}" group="" part="0" file="vtk/fluid_{k:06d}.vtp"/>')
    for name, entries in (("solids.pvd", solids_pvd), ("fluid.pvd", fluid_pvd)):
        (run / name).write_text('<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1">\n<Collection>\n'
                                + "\n".join(entries) + "\n</Collection>\n</VTKFile>\n")

    frame = vtp.read_vtp(run / "vtk" / "solids_000000.vtp")
    assert np.allclose(frame["points"], points) and frame["size_class"].tolist() == [0, 1, 1, 2]  # k = 0: no drift
    assert frame["id"].dtype == np.uint64 and frame["velocity"].shape == (4, 3)

    code = seed_figures.main([str(run), "--scene", str(scene), "--stages", "2", "--conc-times", "0", "1",
                               "--drift-windows", "0-2"])
    assert code == 0, code
    out = run / "figures"

    def rows(name):
        with open(out / name, newline="") as handle:
            return list(csv.DictReader(handle))

    area = 0.24 * 0.16 * 0.015
    for row in rows("fig11_concentration.csv"):
        k, layer = int(row["size_class"]), int(row["sublayer"])
        expected = {(0, 0): radius[0] ** 3, (1, 1): 2 * radius[1] ** 3, (2, 3): radius[3] ** 3}.get((k, layer), 0)
        assert math.isclose(float(row["volume_concentration"]), 4 / 3 * math.pi * expected / area, rel_tol=1e-6,
                            abs_tol=1e-12), row
    speeds = rows("fig14_velocity_phases.csv")
    assert len({r["phase_index"] for r in speeds}) == 4
    for row in speeds:
        assert abs(float(row["mean_vx_relative_to_tank_m_s"]) - 0.1) < 1e-9, row
        assert float(row["mean_abs_phase_error_deg"]) < 1e-6, row
    fluid = {int(r["sublayer"]): float(r["mean_vx_relative_to_tank_m_s"]) for r in rows("fig15_fluid_velocity.csv")}
    assert set(fluid) == {0, 9} and all(abs(fluid[k] - v) < 1e-9 for k, v in {0: 0.0, 9: -0.2}.items()), fluid
    temperature = rows("fig20_granular_temperature.csv")
    assert abs(float(temperature[3]["Tg_class_1_m2_s2"]) - 0.15 ** 2 / 3) < 1e-12, temperature[3]
    assert abs(float(temperature[3]["Tg_class_0_m2_s2"])) < 1e-12
    forces = rows("fig17_19_force_balance.csv")
    for row in forces:
        assert abs(float(row["total_z_over_m_g"])) < 1e-9 and abs(float(row["pressure_force_z_over_m_g"]) - 0.75) < 1e-9
    # Fig. 19: pressure 0.75 m g and contact 0.25 m g upward on every grain, no drag, at all four phases; the
    # small grain (10 mm) is in sub-layer 2, the medium ones (20 mm) in 4, the large one (50 mm) in 10.
    profiles = rows("fig19_z_force_profiles.csv")
    assert len({r["phase_index"] for r in profiles}) == 4, profiles
    assert {(int(r["size_class"]), int(r["sublayer"])) for r in profiles} == {(0, 2), (1, 4), (2, 10)}, profiles
    for row in profiles:
        assert abs(float(row["pressure_force_z_over_m_g"]) - 0.75) < 1e-9, row
        assert abs(float(row["contact_force_z_over_m_g"]) - 0.25) < 1e-9, row
        assert abs(float(row["drag_force_z_over_m_g"])) < 1e-12 and abs(float(row["total_z_over_m_g"]) - 1) < 1e-9
    assert int([r for r in profiles if r["size_class"] == "1"][0]["samples"]) == 2 * int(profiles[0]["frames"])
    # Drift over t/T 0-2: the small grain (x = 50 mm: column 2 of ten 24 mm columns, z = 10 mm: layer 0) moved
    # +10 mm in x; the large one (x = 200 mm, z = 50 mm: column 8, layer 3) did not move.
    moved = {(r["group"], int(r["column"]), int(r["layer"])): (float(r["mean_dx_m"]), float(r["mean_dz_m"]))
             for r in rows("drift.csv")}
    assert np.allclose(moved[("0", 2, 0)], (0.01, 0.0), atol=1e-12) and moved[("all", 2, 0)] == moved[("0", 2, 0)]
    assert np.allclose(moved[("2", 8, 3)], (0.0, 0.0), atol=1e-12), moved
    assert len([key for key in moved if key[0] == "all"]) == 4  # one cell per grain
    # The grains never move vertically here: no segregation. A bed of height 60 mm in three layers of volumes
    # 1 : 2 : 1 (centroids 7.5, 30, 52.5 mm) is fully sorted from a mixed start (all at 30 mm): index 1.
    assert all(abs(float(row["segregation_index"])) < 1e-12 for row in rows("fig06_centroids.csv"))
    assert math.isclose(seed_figures.segregation_index([1, 2, 1], [0.03, 0.03, 0.03], [0.0075, 0.03, 0.0525]), 1.0)
    assert math.isclose(seed_figures.segregation_index([1, 2, 1], [0.03, 0.03, 0.03], [0.01875, 0.03, 0.04125]), 0.5)
    for name in ("fig03_snapshot_tT0.png", "fig06_centroids.png", "fig11_concentration.png", "fig14_velocity_phases.png",
                 "fig15_fluid_velocity.png", "fig17_19_force_balance.png", "fig19_z_force_profiles.png", "fig20_granular_temperature.png", "drift.png"):
        assert (out / name).stat().st_size > 1000, name
    print(f"test_seed_figures: passed ({work})")
    return 0


if __name__ == "__main__":
    sys.exit(main())

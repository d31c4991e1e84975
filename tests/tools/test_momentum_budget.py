#!/usr/bin/python3
"""Self-test of tools/riffle-tools momentum-budget on a synthetic run directory whose budget is known by construction.

Usage: /usr/bin/python3 tests/tools/test_momentum_budget.py WORK_DIR   (exit 0 = pass)
"""
import pathlib
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools"))
sys.path.insert(0, str(ROOT / "tests" / "tools"))
import numpy as np  # noqa: E402
from riffle_tools import momentum_budget  # noqa: E402
from test_seed_figures import write_pvd, write_vtp  # noqa: E402


def main():
    work = pathlib.Path(sys.argv[1])
    work.mkdir(parents=True, exist_ok=True)
    # A 0.1 x 0.1 m plan, l0 = 0.01 m (V = 1e-6 m^3): 4 water particles at z = 1, 3, 11, 13 mm and 2 wall particles,
    # 3 frames at t = 0, 1, 2 s. dp/dx = 100 Pa/m at the two upper particles, 0 below: the pressure term is
    # -2 * 1e-6 * 100 / 0.01 = -0.02 Pa, all in the band 10-20 mm. u_x = 0.1 t at each water particle: dP/dt =
    # 4 * 1000 * 1e-6 * 0.1 / 0.01 = 0.04 Pa. Two grains with drag 1e-4 and pressure force 5e-5 N along x: grains =
    # 1.5e-4 / 0.01 = 0.015 Pa (the force on the bed). tau_lid 0.1 Pa at every row.
    # The wall particles carry a huge gradient that must not count.
    points = np.array([[0.01, 0.01, 0.001], [0.02, 0.02, 0.003], [0.03, 0.03, 0.011], [0.04, 0.04, 0.013],
                       [0.05, 0.05, -0.005], [0.06, 0.06, 0.025]])
    kind = np.array([0, 0, 0, 0, 1, 1])
    fluid_entries, solid_entries = [], []
    for t in (0.0, 1.0, 2.0):
        velocity = np.zeros((6, 3))
        velocity[:4, 0] = 0.1 * t
        gradient = np.zeros((6, 3))
        gradient[2:4, 0] = 100.0
        gradient[4:, 0] = 1e9
        name = f"fluid_{int(t)}.vtp"
        write_vtp(work / name, points, {"kind": (kind, "Int32"), "velocity": (velocity, "Float64"),
                                        "pressure_gradient": (gradient, "Float64")})
        fluid_entries.append(f'<DataSet timestep="{t}" file="{name}"/>')
        grains = np.array([[0.05, 0.05, 0.002], [0.06, 0.06, 0.004]])
        drag = np.array([[1e-4, 0.0, 0.0], [0.0, 0.0, 0.0]])
        pressure = np.array([[0.0, 0.0, 0.0], [5e-5, 0.0, 0.0]])
        name = f"solids_{int(t)}.vtp"
        voidage = np.array([0.5, 0.8])
        write_vtp(work / name, grains, {"drag_force": (drag, "Float64"), "pressure_force": (pressure, "Float64"),
                                        "voidage": (voidage, "Float64")})
        solid_entries.append(f'<DataSet timestep="{t}" file="{name}"/>')
    write_pvd(work / "fluid.pvd", fluid_entries)
    write_pvd(work / "solids.pvd", solid_entries)
    (work / "probe_driven_flow.csv").write_text("time_s,step,lid0_shear_Pa\n0,0,\n0.5,1,0.1\n1.5,2,0.1\n")
    # The water loses the drag's reaction: 1e-4 / 0.5 / 0.01 = 0.02 Pa in the mixture reading (drag over eps), 0.01 Pa
    # in the pore reading; the grains' pressure force has no reaction. Residual 0.1 - 0.02 - r - 0.04.
    for reading, reaction in (("mixture", 0.02), ("pore", 0.01)):
        r = momentum_budget.budget(str(work), 0.0, 2.0, band=0.01, spacing=0.01, plan_area=0.01, reading=reading)
        expected = {"tau_lid": 0.1, "pressure": -0.02, "grains": 0.015, "reaction": reaction, "momentum_rate": 0.04,
                    "residual": 0.1 - 0.02 - reaction - 0.04}
        for key, value in expected.items():
            assert abs(r[key] - value) < 1e-12, (reading, key, r[key], value)
    assert r["frames"] == 3
    assert np.allclose(r["pressure_bands"], [0.0, -0.02], atol=1e-15), r["pressure_bands"]
    # Frames with applied_pressure_gradient (the gradient the water moved with; the grains' pressure_gradient differs
    # under the conservative form): the pressure term is the applied one's.
    for t in (0.0, 1.0, 2.0):
        velocity = np.zeros((6, 3))
        velocity[:4, 0] = 0.1 * t
        applied = np.zeros((6, 3))
        applied[0:2, 0] = 50.0
        applied[4:, 0] = 1e9
        write_vtp(work / f"fluid_{int(t)}.vtp", points,
                  {"kind": (kind, "Int32"), "velocity": (velocity, "Float64"),
                   "pressure_gradient": (np.full((6, 3), 7.0), "Float64"), "applied_pressure_gradient": (applied, "Float64")})
        # and grains with a viscous stress force ([coupling] viscous_stress): 2e-5 N more on the bed, 0.002 Pa.
        write_vtp(work / f"solids_{int(t)}.vtp", grains,
                  {"drag_force": (drag, "Float64"), "pressure_force": (pressure, "Float64"),
                   "viscous_force": (np.array([[2e-5, 0.0, 0.0], [0.0, 0.0, 0.0]]), "Float64"),
                   "voidage": (voidage, "Float64")})
    r = momentum_budget.budget(str(work), 0.0, 2.0, band=0.01, spacing=0.01, plan_area=0.01, reading="mixture")
    assert abs(r["pressure"] - (-0.01)) < 1e-12, r["pressure"]
    assert abs(r["grains"] - 0.017) < 1e-12, r["grains"]
    assert np.allclose(r["pressure_bands"], [-0.01, 0.0], atol=1e-15), r["pressure_bands"]
    print("momentum_budget: all checks passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())

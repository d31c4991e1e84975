"""Plot a run's diagnostics.csv: energies, largest grain speed and CFL, tank motion, and wall time per step.

Usage: tools/riffle-tools plot-diagnostics OUT_DIR [--output FILE.png]

Needs Debian's python3-matplotlib and python3-numpy (installed by tools/setup.sh); run it with /usr/bin/python3,
since another python3 first on PATH may not see Debian's packages.
"""
import argparse
import pathlib
import sys

from . import plotting, run_outputs

plt = plotting.pyplot("plot_diagnostics")


def read_columns(path):
    rows = run_outputs.read_rows(path)
    if not rows:
        sys.exit(f"plot_diagnostics: {path} has no rows yet")
    return {key: [float(row[key]) for row in rows] for key in rows[0]}


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("out_dir", type=pathlib.Path, help="a run's output directory")
    parser.add_argument("--output", type=pathlib.Path, help="PNG to write (default OUT_DIR/diagnostics.png)")
    args = parser.parse_args(argv)
    columns = read_columns(args.out_dir / "diagnostics.csv")
    time = columns["time_s"]

    figure, axes = plt.subplots(2, 2, figsize=(11, 7), constrained_layout=True)
    ax = axes[0][0]
    ax.plot(time, columns["solid_translational_energy_J"], label="translational")
    ax.plot(time, columns["solid_rotational_energy_J"], label="rotational")
    ax.plot(time, columns["solid_potential_energy_J"], label="potential (-m g.x)")
    total = [a + b + c for a, b, c in zip(columns["solid_translational_energy_J"],
                                          columns["solid_rotational_energy_J"],
                                          columns["solid_potential_energy_J"])]
    ax.plot(time, total, "k--", label="total")
    ax.set(xlabel="t [s]", ylabel="energy [J]", title="grain energy")
    ax.legend()

    ax = axes[0][1]
    ax.plot(time, columns["solid_max_speed_m_s"], label="max |v| [m/s]")
    ax.plot(time, columns["solid_cfl"], label="CFL = max|v| dt_solid / r_min")
    ax.set(xlabel="t [s]", title="largest grain speed")
    ax.legend()

    ax = axes[1][0]
    ax.plot(time, columns["tank_displacement_m"], label="displacement [m]")
    ax.plot(time, columns["tank_velocity_m_s"], label="velocity [m/s]")
    ax.set(xlabel="t [s]", title="tank motion along its direction")
    ax.legend()

    ax = axes[1][1]
    for key in columns:
        if key.startswith("wall_") and key.endswith("_s"):
            ax.plot(time, [1e3 * value for value in columns[key]], label=key[5:-2])
    ax.set(xlabel="t [s]", ylabel="wall time per step [ms]", title="time per system", yscale="log")
    ax.legend(fontsize="small")

    plotting.write(figure, args.output or args.out_dir / "diagnostics.png", "plot_diagnostics")


if __name__ == "__main__":
    sys.exit(main())

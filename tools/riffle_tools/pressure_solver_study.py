"""The pressure solve of one scene under each of riffle's solvers, run interleaved: iterations and time per solve.

The choice the fluid's `preconditioner` key makes: the in-house PCG with Jacobi or with the two-level aggregation
preconditioner (systems/physics/mps/pressure_preconditioner.hpp), or hypre's PCG with one BoomerAMG V-cycle
(systems/physics/mps/hypre_pressure_solver.hpp; builds with libhypre-dev), the solver a run over several machines
would hand its pressure equation to. Every solver stops at the same |r| <= tol |b|, from the same warm start.

For each repetition the tool runs the scene once per solver, in turn (A, B, A, B, ...: a machine whose speed drifts
shifts both alike), with `--set fluid.preconditioner=...`, and reads per run:
  - timings.csv: fluid_pressure's mean time per call (the assembly and the solve: the in-house assembly is shared,
    hypre's adds its IJ copy and its set-up), and the stepping's wall time;
  - diagnostics.csv: the solver's iterations (mean and largest over the rows), its unknowns, the largest relative
    residual, and whether any row failed to converge.
It prints one row per solver with the medians over the repetitions, and the spread (max - min) / median of the time.

Usage:
    tools/riffle-tools pressure-solver-study [--riffle build/riffle] [--scene scenes/oscillating_tank.toml]
        [--until 0.3] [--threads 1] [--reps 3] [--solvers two_level,boomeramg] [--set KEY=VALUE ...] [--out DIR]
"""
import argparse
import csv
import os
import statistics
import subprocess
import sys


def read_timings(folder):
    pressure = stepping = None
    calls = 0
    with open(os.path.join(folder, "timings.csv"), newline="") as f:
        for row in csv.DictReader(f):
            if row["system"] == "fluid_pressure":
                pressure = float(row["mean_s"])
                calls = int(row["calls"])
            elif row["system"] == "stepping":
                stepping = float(row["total_s"])
    if pressure is None:
        sys.exit(f"pressure_solver_study: {folder}/timings.csv has no fluid_pressure row (a scene without MPS water?)")
    return pressure, stepping, calls


def read_solver(folder):
    iterations, unknowns, residuals, converged = [], [], [], True
    with open(os.path.join(folder, "diagnostics.csv"), newline="") as f:
        for row in csv.DictReader(f):
            iterations.append(float(row["ppe_iterations"]))
            unknowns.append(float(row["ppe_unknowns"]))
            residuals.append(float(row["ppe_relative_residual"]))
    return {
        "iterations_mean": statistics.mean(iterations) if iterations else float("nan"),
        "iterations_max": max(iterations) if iterations else float("nan"),
        "unknowns": statistics.mean(unknowns) if unknowns else float("nan"),
        "residual_max": max(residuals) if residuals else float("nan"),
    }


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter, epilog=__doc__)
    parser.add_argument("--riffle", default="build/riffle")
    parser.add_argument("--scene", default="scenes/oscillating_tank.toml")
    parser.add_argument("--until", type=float, default=0.3, help="end time [s] of each run")
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--reps", type=int, default=3)
    parser.add_argument("--solvers", default="two_level,boomeramg",
                        help="comma-separated values of fluid.preconditioner")
    parser.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                        help="another scene override for every run (riffle run --set)")
    parser.add_argument("--out", default="out/pressure_solver_study")
    args = parser.parse_args(argv)
    solvers = [s for s in args.solvers.split(",") if s]
    results = {solver: [] for solver in solvers}
    for rep in range(1, args.reps + 1):
        for solver in solvers:
            folder = os.path.join(args.out, f"{solver}_{rep}")
            command = [args.riffle, "run", args.scene, "--out", folder, "--threads", str(args.threads),
                       "--until", str(args.until), "--log-level", "warn", "--set", f"fluid.preconditioner={solver}"]
            for extra in args.set:
                command += ["--set", extra]
            done = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
            if done.returncode != 0:
                sys.stderr.write(done.stdout)
                sys.exit(f"pressure_solver_study: {' '.join(command)} exited {done.returncode}")
            pressure, stepping, calls = read_timings(folder)
            results[solver].append(dict(read_solver(folder), pressure=pressure, stepping=stepping, calls=calls))
            print(f"# rep {rep} {solver}: {1e3 * pressure:.2f} ms a solve, stepping {stepping:.1f} s", flush=True)
    print(f"\n{args.scene}, --until {args.until}, {args.threads} thread(s), {args.reps} repetitions (medians)\n")
    print("| solver | unknowns | iterations, mean / largest | time a solve [ms] (spread) | stepping [s] | "
          "largest residual |")
    print("|---|---|---|---|---|---|")
    for solver in solvers:
        runs = results[solver]
        times = [r["pressure"] for r in runs]
        median = statistics.median(times)
        spread = (max(times) - min(times)) / median if median > 0 else 0.0
        print(f"| {solver} | {statistics.median(r['unknowns'] for r in runs):.0f} | "
              f"{statistics.median(r['iterations_mean'] for r in runs):.1f} / "
              f"{max(r['iterations_max'] for r in runs):.0f} | {1e3 * median:.2f} ({100 * spread:.0f} %) | "
              f"{statistics.median(r['stepping'] for r in runs):.1f} | "
              f"{max(r['residual_max'] for r in runs):.1e} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""The water's streamwise (x) momentum budget of a sheared-bed run (scenes/sheared_bed_*.toml: a lid driving water
over a bed in a box periodic along x and y), per unit plan area, from the run's frames and probes:

  tau_lid        the lid's viscous traction on the water (probe_driven_flow.csv, lid0_shear_Pa);
  pressure       the net force of the MPS pressure gradient on the water, -sum_j V_j (dp/dx)_j / A (fluid frames,
                 field applied_pressure_gradient, the gradient the water moved with, or pressure_gradient in
                 frames older than that field, V = l0^3): zero for a pressure that is periodic along x, whatever the flow,
                 in the continuum (the integral of dp/dx over a period vanishes); printed per height band too;
  grains         the grains' drag, pressure and viscous stress forces along x, sum / A (solids frames): the force on
                 the bed, the bed shear stress tau_b of the bed_shear_stress probe;
  reaction       what the water loses to the grains: their drag's reaction, sum F_d / eps in the mixture reading
                 (the water takes the drag over eps, docs/COUPLING.md), sum F_d in the pore reading; the pressure
                 force on the grains has no reaction in the water (by design);
  dP/dt          the water's momentum change, sum_j rho V u_x,j / A, a least-squares slope over the frames;
  residual       tau_lid + pressure - reaction - dP/dt: what the budget misses (the floor's traction, the wall
                 particles' collision/stabilisation forces, the frames' sampling).
In steady flow tau_lid = tau_b, the bed shear stress, exactly when the pressure term is zero; a nonzero pressure term
is momentum the water's pressure solve makes or destroys (docs/RESULTS.md, the sheared beds).

Usage: tools/riffle-tools momentum-budget RUN_DIR [--from T] [--to T] [--band 0.0025] [--spacing L0]
           [--density 1000] [--area A] [--reading mixture|pore]
RUN_DIR holds fluid.pvd, solids.pvd and probe_driven_flow.csv. --spacing: l0 [m], --area: the plan area [m^2]
(default: both read from the scene the run's riffle.log names); --reading: coupling.fluid_velocity (default: the
scene's, else "mixture"). Prints the mean of each term over the frames with --from <= t <= --to (default: the second
half of the run), and the pressure term per band of --band metres. numpy only.
"""
import argparse
import csv
import os
import sys
import tomllib

import numpy as np

from . import vtp


def lid_traction(run_dir):
    """(times, tau_lid [Pa]) from probe_driven_flow.csv; empty arrays without a lid column."""
    path = os.path.join(run_dir, "probe_driven_flow.csv")
    times, values = [], []
    with open(path, newline="") as handle:
        for row in csv.DictReader(handle):
            text = row.get("lid0_shear_Pa", "")
            if text:
                times.append(float(row["time_s"]))
                values.append(float(text))
    return np.array(times), np.array(values)


def frame_terms(fluid, solids, volume, density, area, band_edges, mixture=True):
    """One frame pair: (water momentum / A, pressure force / A, grains' force / A, the water's loss to the grains / A,
    pressure force / A per band)."""
    water = fluid["kind"] == 0 if "kind" in fluid else np.ones(len(fluid["points"]), bool)
    z = fluid["points"][water, 2]
    # The water moves with applied_pressure_gradient (the conservative form where the scene sets it; the grains sample
    # pressure_gradient, GC's); frames written before that field hold only pressure_gradient, then the same thing.
    applied = fluid["applied_pressure_gradient"] if "applied_pressure_gradient" in fluid else fluid["pressure_gradient"]
    pressure_x = -volume * applied[water, 0] / area
    momentum = density * volume * fluid["velocity"][water, 0].sum() / area
    per_band, _ = np.histogram(z, band_edges, weights=pressure_x)
    grains = reaction = 0.0
    if solids is not None and len(solids["points"]):
        drag = solids["drag_force"][:, 0]
        grains = (drag.sum() + solids["pressure_force"][:, 0].sum()) / area
        if "viscous_force" in solids:  # [coupling] viscous_stress (zero without it; absent in older frames)
            grains += solids["viscous_force"][:, 0].sum() / area
        reaction = (drag / solids["voidage"]).sum() / area if mixture else drag.sum() / area
    return momentum, pressure_x.sum(), grains, reaction, per_band


def budget(run_dir, start=None, end=None, band=0.0025, spacing=None, density=1000.0, plan_area=None, reading=None):
    """The budget's terms (a dict) over the frames in [start, end]; see the module's docstring."""
    fluid_frames = vtp.read_pvd(os.path.join(run_dir, "fluid.pvd"))
    solids_path = os.path.join(run_dir, "solids.pvd")
    solids_frames = dict(vtp.read_pvd(solids_path)) if os.path.exists(solids_path) else {}
    if spacing is None or plan_area is None or reading is None:
        path, _ = vtp.run_scene(run_dir)
        if path is None:
            raise SystemExit(f"{run_dir}: no scene found through riffle.log; give --spacing")
        with open(path, "rb") as handle:
            scene = tomllib.load(handle)
        if spacing is None:
            spacing = float(scene["fluid"]["spacing"])
        if plan_area is None:
            size = scene["tank"]["size"]
            plan_area = float(size[0]) * float(size[1])
        if reading is None:
            reading = scene.get("coupling", {}).get("fluid_velocity", "mixture")
    if reading not in ("mixture", "pore"):
        raise SystemExit(f"{run_dir}: reading {reading!r} is neither 'mixture' nor 'pore'")
    last = fluid_frames[-1][0]
    start = 0.5 * last if start is None else start
    end = last if end is None else end
    chosen = [(t, path) for t, path in fluid_frames if start - 1e-9 <= t <= end + 1e-9]
    if len(chosen) < 2:
        raise SystemExit(f"{run_dir}: fewer than two fluid frames between {start} and {end} s")
    volume = spacing ** 3
    first = vtp.read_vtp(chosen[0][1])
    water = first["kind"] == 0 if "kind" in first else np.ones(len(first["points"]), bool)
    top = max(first["points"][water, 2].max(), band)
    edges = np.arange(0.0, top + band, band)
    times, momenta, pressures, grains, reactions, bands = [], [], [], [], [], []
    for t, path in chosen:
        # The solids frame of the same output time (both written at one step; matched to 1 ns); a run with grains
        # whose frame is missing is refused rather than read as grain-free.
        match = [s for ts, s in solids_frames.items() if abs(ts - t) < 1e-9]
        if solids_frames and not match:
            raise SystemExit(f"{run_dir}: no solids frame at t = {t} s")
        solids = vtp.read_vtp(match[0]) if match else None
        m, p, g, r, b = frame_terms(vtp.read_vtp(path), solids, volume, density, plan_area, edges,
                                    reading == "mixture")
        times.append(t), momenta.append(m), pressures.append(p), grains.append(g), reactions.append(r)
        bands.append(b)
    times = np.array(times)
    rate = np.polyfit(times, np.array(momenta), 1)[0]
    lid_times, lid_values = lid_traction(run_dir)
    window = (lid_times >= start - 1e-9) & (lid_times <= end + 1e-9)
    tau_lid = float(lid_values[window].mean()) if window.any() else float("nan")
    result = {
        "start": start, "end": end, "frames": len(chosen), "tau_lid": tau_lid,
        "pressure": float(np.mean(pressures)), "grains": float(np.mean(grains)),
        "reaction": float(np.mean(reactions)), "momentum_rate": float(rate), "reading": reading,
        "band_edges": edges, "pressure_bands": np.mean(bands, axis=0),
    }
    result["residual"] = result["tau_lid"] + result["pressure"] - result["reaction"] - result["momentum_rate"]
    return result


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("run_dir")
    parser.add_argument("--from", dest="start", type=float)
    parser.add_argument("--to", dest="end", type=float)
    parser.add_argument("--band", type=float, default=0.0025)
    parser.add_argument("--spacing", type=float)
    parser.add_argument("--density", type=float, default=1000.0)
    parser.add_argument("--area", type=float, help="plan area [m^2] (default: the scene's tank, x times y)")
    parser.add_argument("--reading", choices=("mixture", "pore"), help="default: the scene's coupling.fluid_velocity")
    args = parser.parse_args(argv)
    r = budget(args.run_dir, args.start, args.end, args.band, args.spacing, args.density, args.area, args.reading)
    print(f"{args.run_dir}: x momentum of the water per plan area, {r['frames']} frames, "
          f"t = {r['start']:.3g} to {r['end']:.3g} s [Pa]")
    print(f"  tau_lid {r['tau_lid']:+.4f}   pressure {r['pressure']:+.4f}   reaction ({r['reading']}) "
          f"{r['reaction']:+.4f}   dP/dt {r['momentum_rate']:+.4f}   residual {r['residual']:+.4f}   "
          f"(force on the bed, tau_b: {r['grains']:+.4f})")
    print("  pressure per band (z from-to mm: Pa)")
    edges = r["band_edges"]
    for low, high, value in zip(edges[:-1], edges[1:], r["pressure_bands"]):
        print(f"    {low * 1e3:6.2f}-{high * 1e3:6.2f}  {value:+.4f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

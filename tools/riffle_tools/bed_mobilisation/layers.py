"""Sloshing against pore-water locking in a coupled run of the sloshing tank, per fluid frame: the bed surface at the
end walls, the fluid's and the grains' x-velocity relative to the tank per depth below the local bed surface, the
voidage, the top layer's forces over its weight and over its submerged weight, and the drag-reaction impulse on the
bed water against the grains' drag; the rows are kept in OUT_DIR/analysis_rows.npy. The fluid frames must carry
pressure_gradient and drag_reaction.

Usage: tools/riffle-tools mobilisation-layers OUT_DIR [L0]   (L0 the water spacing [m], default 0.01)
"""
import argparse
import math
import pathlib
import sys

import numpy as np

from .. import vtp
from . import add_motion_arguments, motion_of

RHO, RHOS, G = 1000.0, 1318.0, 9.81


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("out", type=pathlib.Path, metavar="OUT_DIR", help="a coupled run's output directory")
    parser.add_argument("l0", type=float, nargs="?", default=0.01, metavar="L0", help="water spacing [m]")
    add_motion_arguments(parser)
    args = parser.parse_args(argv)
    out, l0 = args.out, args.l0
    motion = motion_of(args)
    T = 1 / motion.frequency
    solids = vtp.read_pvd(out / "solids.pvd") if (out / "solids.pvd").exists() else []
    fluids = vtp.read_pvd(out / "fluid.pvd")
    nbin = 12
    edges = np.linspace(0, 0.24, nbin + 1)

    rows = []
    print("  t/T | surf L  surf R  tilt(mm) | layer dz(mm): u_f-u_tank  u_s-u_tank (mm/s) ... | eps_bed eps_top | top grains |F|/(m g): drag press contact | "
          "bed water: drag-reaction impulse/step vs beta*slip*V*dt")
    for k, (t, fpath) in enumerate(fluids):
        xt, vt, at = motion.at(t)
        fl = vtp.read_vtp(fpath, ["kind", "velocity", "drag_reaction", "pressure_gradient", "pressure"])
        m = fl["kind"] == 0
        fp = fl["points"][m].copy(); fp[:, 0] -= xt
        fv = fl["velocity"][m][:, 0] - vt
        fdr = fl["drag_reaction"][m]
        row = {"t": t, "tT": t / T, "fluid_vmax": np.abs(fl["velocity"][m] - np.array([vt, 0, 0])).max()}
        if not solids:
            rows.append(row); continue
        st, spath = solids[min(k, len(solids) - 1)]
        assert abs(st - t) < 1e-6, (st, t)
        s = vtp.read_vtp(spath, ["velocity", "radius", "mass", "drag_force", "pressure_force", "contact_force",
                                 "voidage", "size_class", "fluid_velocity", "fluid_weight"])
        p = s["points"].copy(); p[:, 0] -= xt
        r = s["radius"]; mass = s["mass"]; vol = 4 / 3 * math.pi * r**3
        top = p[:, 2] + r
        # local bed surface: 90th percentile of grain tops in 2 cm x-bins, interpolated
        ib = np.clip(np.digitize(p[:, 0], edges) - 1, 0, nbin - 1)
        surf = np.array([np.percentile(top[ib == b], 90) if np.any(ib == b) else np.nan for b in range(nbin)])
        centres = 0.5 * (edges[1:] + edges[:-1])
        S_g = np.interp(p[:, 0], centres, surf)
        S_f = np.interp(fp[:, 0], centres, surf)
        dg = S_g - p[:, 2]   # depth of grain centre below local surface
        df = S_f - fp[:, 2]
        row.update(surfL=surf[0], surfR=surf[-1], surf1=surf[1], surf10=surf[-2], tilt=surf[-1] - surf[0],
                   tilt_in=surf[-2] - surf[1])
        us = s["velocity"][:, 0] - vt
        layers = [(-1.0, 0.0), (0.0, 0.01), (0.01, 0.02), (0.02, 0.03), (0.03, 0.06)]
        lay = []
        for lo, hi in layers:
            mf = (df >= lo) & (df < hi)
            mg = (dg >= lo) & (dg < hi)
            uf = fv[mf].mean() if mf.any() else np.nan
            ug = np.average(us[mg], weights=vol[mg]) if mg.any() else np.nan
            lay.append((uf, ug, mf.sum(), mg.sum()))
        row["layers"] = lay
        inbed = dg > 0.01
        row["eps_bed"] = s["voidage"][inbed].mean()
        topm = dg < 0.0075
        row["eps_top"] = s["voidage"][topm].mean()
        wgt = mass[topm] * G
        for name in ("drag_force", "pressure_force", "contact_force"):
            F = s[name][topm]
            row[name] = np.mean(np.linalg.norm(F, axis=1) / wgt)
            row[name + "_x"] = np.mean(np.abs(F[:, 0]) / wgt)
            row[name + "_z"] = np.mean(F[:, 2] / wgt)
        # submerged-weight-normalised lift: pressure_z + drag_z - (m - rho V) g ... net of gravity
        # drag reaction check over bed water (depth > l0): impulse per volume -> total impulse
        dt = 1e-3
        fb = df > l0
        imp_water = (fdr[fb] * l0**3).sum(axis=0)     # N s received by bed water last step
        imp_all = (fdr * l0**3).sum(axis=0)
        grains_drag = s["drag_force"].sum(axis=0) * dt  # N s (last sub-step force x dt)
        gb = dg > l0
        row["imp_water_bed_x"] = imp_water[0]; row["imp_water_all_x"] = imp_all[0]; row["grain_drag_dt_x"] = grains_drag[0]
        row["grain_drag_bed_dt_x"] = s["drag_force"][gb, 0].sum() * dt
        # Ergun estimate: beta*slip*V*dt with slip = mean grain u - mean fluid u in the bed, V the bed water volume
        slip = (np.average(s["velocity"][gb, 0], weights=vol[gb]) - fl["velocity"][m][fb, 0].mean())
        row["slip_bed"] = slip
        row["slip_sampled"] = np.average(s["fluid_velocity"][gb, 0] - s["velocity"][gb, 0], weights=vol[gb])
        row["fluid_weight_bed"] = s["fluid_weight"][gb].mean()
        # horizontal pressure gradient in bed water vs rigid -rho a_tank; pressure force x on bed grains / submerged weight
        row["a_tank_g"] = at / G
        row["dpdx_bed"] = fl["pressure_gradient"][m][fb, 0].mean() / (RHO * G)
        sub = (RHOS - RHO) * vol * G
        row["Fpx_sub_bed"] = np.mean(s["pressure_force"][gb, 0] / sub[gb])
        row["Fpx_sub_top"] = np.mean(s["pressure_force"][topm, 0] / sub[topm])
        row["Fdx_sub_top"] = np.mean(s["drag_force"][topm, 0] / sub[topm])
        row["Fdz_sub_top"] = np.mean(s["drag_force"][topm, 2] / sub[topm])
        row["Fpz_sub_top"] = np.mean(s["pressure_force"][topm, 2] / sub[topm]) - RHO / (RHOS - RHO)
        rows.append(row)
        lays = " ".join(f"{a*1e3:6.1f}/{b*1e3:6.1f}" for a, b, _, _ in lay)
        print(f"{t/T:5.2f} | {surf[0]*1e3:5.1f} {surf[-1]*1e3:5.1f} {(surf[-1]-surf[0])*1e3:6.1f} | {lays} | "
              f"{row['eps_bed']:.3f} {row['eps_top']:.3f} | {row['drag_force']:.3f} {row['pressure_force']:.3f} "
              f"{row['contact_force']:.3f} | Iw_bed {imp_water[0]*1e6:8.2f} Iw_all {imp_all[0]*1e6:8.2f} "
              f"Ig {grains_drag[0]*1e6:8.2f} uS-uF {slip*1e3:6.1f} sampled(uF-uS) {row['slip_sampled']*1e3:6.1f} mm/s"
              f" | a/g {at/G:6.3f} dpdx/rho g {row['dpdx_bed']:6.3f} Fpx/Wsub bed {row['Fpx_sub_bed']:6.3f} top {row['Fpx_sub_top']:6.3f}"
              f" Fdx/Wsub top {row['Fdx_sub_top']:6.3f} (Fpz-buoy)/Wsub {row['Fpz_sub_top']:6.3f} Fdz/Wsub {row['Fdz_sub_top']:6.3f}")

    np.save(out / "analysis_rows.npy", np.array(rows, dtype=object), allow_pickle=True)

    return 0


if __name__ == "__main__":
    sys.exit(main())

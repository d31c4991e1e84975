"""Wet restitution against Stokes number, coupled (docs/COUPLING.md "Lubrication").

A steel sphere (d = 10 mm, rho_p = 7800, the softened E = 1e8 Pa of the seed scenes, e_dry = 0.9) is thrown at
the floor of a small tank of MPS water (l0 = 10 mm by default: d/l0 = 1) without gravity, whose viscosity sets the
Stokes number St = (rho_p + C_a rho_f) d V / (9 mu), C_a = 0.5. From a grains probe written every engine step
(dt = 0.25 ms): V = the speed where the gap falls below the lubrication cut-off, the rebound speed = the speed
where it rises above it again (both interpolated between rows). e_dry comes from the same run without water. The ratio e/e_dry is compared with
Legendre, Zenit, Daniel & Guiraud (2006, Chem. Eng. Sci. 61): exp(-35/St).

  tools/riffle-tools wet-restitution --riffle build/riffle --work /tmp/wet [--st 5,10,20,50,100,200,500]
      [--spacing 0.01] [--roughness 1e-3] [--cutoff 1] [--no-lubrication] [--check 0.15]

--check TOL: exit 1 unless |e/e_dry - fit| <= TOL wherever St >= 15 and e/e_dry < 0.1 wherever St < 8.
"""
import argparse
import csv
import math
import os
import subprocess
import sys

RHO_P, RHO_F, D, E_DRY, SPEED = 7800.0, 1000.0, 0.010, 0.9, 0.5
CUTOFF_RADII = [1.0]  # the cut-off in radii (a* = a for a wall); set from --cutoff
C_A = 0.5


def scene(viscosity, spacing, lubrication, roughness, cutoff, wet):
    start = D / 2 + 1.5 * D  # centre height: the grain starts 1.5 d above the floor
    end_time = 0.1
    fluid = f"""
[fluid]
spacing = {spacing}
density = {RHO_F}
kinematic_viscosity = {viscosity / RHO_F}
[[fluid.boxes]]
low = [0.0, 0.0, 0.0]
high = [0.06, 0.06, 0.05]
[coupling]
lubrication = {str(lubrication).lower()}
lubrication_cutoff = {cutoff}
roughness = {roughness}
""" if wet else ""
    return f"""
[run]
name = "wet_restitution"
end_time = {end_time}
dt = 2.5e-4
gravity = [0.0, 0.0, 0.0]
[materials.steel]
density = {RHO_P}
young_modulus = 1.0e8
poisson_ratio = 0.3
[tank]
size = [0.06, 0.06, 0.12]
open_faces = ["z_max"]
wall_material = "steel"
[contact]
restitution = {E_DRY}
friction = 0.3
max_impact_speed = 1.0
[solids]
[[solids.spheres]]
position = [0.03, 0.03, {start}]
velocity = [0.0, 0.0, {-SPEED}]
radius = {D / 2}
material = "steel"
{fluid}
[output]
[[output.probes]]
kind = "grains"
name = "ball"
file = "ball.csv"
ids = [0]
interval = 0.0
"""


def bounce(riffle, work, name, text):
    os.makedirs(work, exist_ok=True)
    path = os.path.join(work, name + ".toml")
    with open(path, "w") as f:
        f.write(text)
    out = os.path.join(work, name)
    subprocess.run([riffle, "run", path, "--out", out, "--threads", "1"], check=True, stdout=subprocess.DEVNULL,
                   stderr=subprocess.DEVNULL)
    with open(os.path.join(out, "ball.csv")) as f:
        rows = [(float(r["time_s"]), float(r["grain0_z_m"]), float(r["grain0_vz_m_s"])) for r in csv.DictReader(f)]
    # Speeds where the gap crosses the cut-off h_c (linear between rows): on the way in, and on the way out after
    # the first bounce (no gravity in the scene, so nothing but the water and the wall changes the speed).
    cutoff = CUTOFF_RADII[0] * D / 2
    gaps = [(t, z - D / 2, vz) for t, z, vz in rows]

    def crossing(start, inward):
        for k in range(max(start, 1), len(gaps)):
            (_, g0, v0), (_, g1, v1) = gaps[k - 1], gaps[k]
            if (g0 >= cutoff > g1) if inward else (g0 <= cutoff < g1):
                w = (g0 - cutoff) / (g0 - g1)
                return k, v0 + w * (v1 - v0)
        return None, 0.0

    k_in, v_in = crossing(0, True)
    if k_in is None:
        raise SystemExit(f"{name}: the grain never came within the cut-off of the floor")
    _, v_out = crossing(k_in, False)
    return -v_in, max(v_out, 0.0)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--riffle", default="build/riffle")
    parser.add_argument("--work", default="/tmp/wet_restitution")
    parser.add_argument("--st", default="5,10,20,50,100,200,500")
    parser.add_argument("--spacing", type=float, default=0.01)
    parser.add_argument("--roughness", type=float, default=1e-3)
    parser.add_argument("--cutoff", type=float, default=1.0)
    parser.add_argument("--no-lubrication", action="store_true")
    parser.add_argument("--check", type=float, default=None)
    args = parser.parse_args(argv)
    CUTOFF_RADII[0] = args.cutoff
    dry_impact, dry_rebound = bounce(args.riffle, args.work, "dry", scene(0.0, 0.0, False, 0.0, 0.0, False))
    e_dry = dry_rebound / dry_impact
    print(f"dry: impact {dry_impact:.4f} m/s, rebound {dry_rebound:.4f} m/s, e_dry {e_dry:.4f}")
    print("| St (nominal) | mu [Pa s] | impact V [m/s] | St at V | e/e_dry | exp(-35/St) | difference |")
    print("|---|---|---|---|---|---|---|")
    ok = True
    for nominal in [float(s) for s in args.st.split(",")]:
        viscosity = (RHO_P + C_A * RHO_F) * D * SPEED / (9.0 * nominal)
        impact, rebound = bounce(args.riffle, args.work, f"st{nominal:g}",
                                 scene(viscosity, args.spacing, not args.no_lubrication, args.roughness,
                                       args.cutoff, True))
        st = (RHO_P + C_A * RHO_F) * D * impact / (9.0 * viscosity)
        ratio = rebound / impact / e_dry
        fit = math.exp(-35.0 / st)
        print(f"| {nominal:g} | {viscosity:.4g} | {impact:.3f} | {st:.1f} | {ratio:.3f} | {fit:.3f} | "
              f"{ratio - fit:+.3f} |")
        if args.check is not None:
            if st >= 15.0 and abs(ratio - fit) > args.check:
                ok = False
            if st < 8.0 and ratio >= 0.1:
                ok = False
    sys.stdout.flush()
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())

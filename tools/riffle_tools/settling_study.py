"""A lone sphere settling from rest in a closed box of still liquid (docs/COUPLING.md "The undisturbed fluid
velocity"): terminal speed against the Schiller-Naumann law, the approach against the point-particle equation.

For each case (Re, d/l0) the tool writes a scene, runs riffle, reads the grain's probe and reports:
  - the terminal speed (mean over the window before the floor's influence) against Schiller-Naumann at eps = 1,
    corrected for the box's walls by Di Felice (1996, Int. J. Multiphase Flow 22, 527-533):
    U/U_inf = ((1 - lam)/(1 - 0.33 lam))^alpha, (3.3 - alpha)/(alpha - 0.85) = 0.1 Re, lam = d / D (D: the box's
    side, the tube's diameter in Di Felice's fit; a square duct's wall effect is within a tenth of that of the
    inscribed tube at small lam, Happel & Brenner 1965, Table 7-4.1, so the side is the closer one);
  - the RMS over the approach (t = 0 up to the window's end) of v_sim - v_ode over the law's speed, where v_ode
    solves (m + C_a m_f) dv/dt = (m - m_f) g - F_SN(v) / K_wall from rest (C_a = 0 without added mass, 0.5 with it).
The sphere's own disturbance and the box's walls are the only departures the correction leaves: the drag law is
riffle's (Wen & Yu at eps = 1 is Schiller-Naumann), so a lone grain must read eps = 1 (see --voidage-radius).

Usage:
  tools/riffle-tools settling-study [--riffle build/riffle] [--out out/settling] [--cases quick|matrix|RE:D]
      [--correction on|off|both] [--added-mass 0|0.5] [--voidage-radius METRES] [--threads 1]
Prints one table row per case and run; --check TOL_TERMINAL TOL_RMS exits 1 when a corrected case misses them.
"""
import argparse
import csv
import math
import pathlib
import subprocess
import sys

GRAVITY = 9.81
RHO = 1000.0
RHO_S = 1120.0          # a 1120 kg/m^3 sphere; the liquid at 1000
RATIO_RE = 2.4          # r_e / l0, riffle's default
KERNEL_BOX = 5.0        # the box's side over the sampling kernel's radius, at least


def schiller_naumann_speed(d, nu, ratio=RHO_S / RHO):
    """Terminal speed of a lone sphere with C_D Re = 24 (1 + 0.15 Re^0.687), by bisection."""
    weight = (ratio - 1.0) * GRAVITY * d * d / (18.0 * nu)  # Stokes speed
    low, high = 0.0, weight
    for _ in range(200):
        u = 0.5 * (low + high)
        re = u * d / nu
        if u * (1.0 + 0.15 * re ** 0.687) > weight:
            high = u
        else:
            low = u
    return 0.5 * (low + high)


def di_felice_factor(lam, reynolds):
    alpha = (3.3 + 0.085 * reynolds) / (1.0 + 0.1 * reynolds)
    return ((1.0 - lam) / (1.0 - 0.33 * lam)) ** alpha


def viscosity_for(reynolds, d, ratio=RHO_S / RHO):
    """nu giving a Schiller-Naumann terminal Reynolds number `reynolds` for a sphere of diameter d."""
    archimedes = 18.0 * reynolds * (1.0 + 0.15 * reynolds ** 0.687)  # (ratio - 1) g d^3 / nu^2
    return math.sqrt((ratio - 1.0) * GRAVITY * d ** 3 / archimedes)


def point_particle(d, nu, wall, added_mass, t_end, dt):
    """v(t) of (m + C_a m_f) dv/dt = (m - m_f) g - F_SN(v) / wall, from rest (speeds positive downwards)."""
    volume = math.pi / 6.0 * d ** 3
    mass, fluid = RHO_S * volume, RHO * volume
    mu = nu * RHO

    def accel(v):
        re = abs(v) * d / nu
        drag = 3.0 * math.pi * mu * d * v * (1.0 + 0.15 * re ** 0.687) / wall
        return ((mass - fluid) * GRAVITY - drag) / (mass + added_mass * fluid)

    times, speeds, v, t = [0.0], [0.0], 0.0, 0.0
    while t < t_end:
        k1 = accel(v)
        k2 = accel(v + 0.5 * dt * k1)
        k3 = accel(v + 0.5 * dt * k2)
        k4 = accel(v + dt * k3)
        v += dt / 6.0 * (k1 + 2 * k2 + 2 * k3 + k4)
        t += dt
        times.append(t)
        speeds.append(v)
    return times, speeds


def case_geometry(reynolds, d_over_l0, box_over_d):
    """Scene numbers for one case: d = 10 mm, l0 = d / (d/l0), the box's side D = box_over_d d (rounded to l0)."""
    d = 0.01
    l0 = d / d_over_l0
    nu = viscosity_for(reynolds, d)
    side = max(round(box_over_d * d / l0), 8) * l0
    u = schiller_naumann_speed(d, nu)
    relax = (RHO_S / RHO + 0.5) * d * d / (18.0 * nu * (1.0 + 0.15 * reynolds ** 0.687))
    kernel = d / 2 + RATIO_RE * l0
    # Run long enough for the slowest mode of the disturbance's build-up (8 R^2 / nu, shortened by the Oseen
    # factor ~ 3.5 / Re_R) and ten relaxation times; the fall then sets the height (plus room at both ends).
    # The run: twelve relaxation times (the window is the last half). The box's walls are met by the sphere's
    # diffusing disturbance after about (D/2)^2 / (4 nu) (it spreads as sqrt(4 nu t)); the side D keeps that beyond
    # the run, so the reference is the unbounded law. The side is at least 8 d and 5 R (R the kernel's radius: in a
    # box of 3 R the walls already confine the spread force's immediate, solenoidal answer).
    t_end = 12.0 * relax
    side = max(side, math.ceil(max(KERNEL_BOX * kernel, 2.0 * math.sqrt(4.0 * nu * t_end) * 2.0) / l0) * l0)
    fall = u * t_end
    clearance = max(side / 2.0, 2.0 * kernel)  # the window ends this far above the floor
    height = (math.ceil((fall * 1.1 + clearance + kernel) / l0) + 3) * l0
    return dict(d=d, l0=l0, nu=nu, side=side, u=u, relax=relax, t_end=t_end, height=height, kernel=kernel,
                clearance=clearance)


def scene_text(g, correction, added_mass, voidage_radius):
    d, l0, nu, side, height = g["d"], g["l0"], g["nu"], g["side"], g["height"]
    dt = min(0.2 * l0 * l0 / nu, 0.2 * l0 / max(g["u"], 1e-9), 2e-3)
    release = height - g["kernel"] - l0  # the sampling sphere under the surface
    lines = [
        "[run]", f"end_time = {g['t_end']:.15g}", f"dt = {dt:.15g}", "solid_substeps = 20", "",
        "[materials.grain]", f"density = {RHO_S}", "", "[materials.glass]", "density = 2500.0", "",
        "[tank]", f"size = [{side:.15g}, {side:.15g}, {height + l0:.15g}]", 'open_faces = ["z_max"]',
        'wall_material = "glass"', "",
        "[solids]", "[[solids.spheres]]", f"position = [{side / 2:.15g}, {side / 2:.15g}, {release:.15g}]",
        f"radius = {d / 2:.15g}", 'material = "grain"', "",
        "[fluid]", f"spacing = {l0:.15g}", f"kinematic_viscosity = {nu:.15g}", f"density = {RHO}",
        "[[fluid.boxes]]", "low = [0.0, 0.0, 0.0]", f"high = [{side:.15g}, {side:.15g}, {height:.15g}]", "",
        "[coupling]", f"self_induced_velocity = {'true' if correction else 'false'}",
    ]
    if voidage_radius > 0.0:
        lines.append(f"voidage_radius = {voidage_radius:.15g}")
    if added_mass > 0.0:
        lines.append("added_mass = true")
    lines += ["", "[output]", "vtk_interval = 0", "", "[[output.probes]]", 'kind = "grains"', "ids = [0]",
              "interval = 0", ""]
    return "\n".join(lines), release


def read_probe(path):
    times, heights, speeds = [], [], []
    with open(path) as handle:
        for row in csv.DictReader(handle):
            times.append(float(row["time_s"]))
            heights.append(float(row["grain0_z_m"]))
            speeds.append(-float(row["grain0_vz_m_s"]))
    return times, heights, speeds


def analyse(g, times, heights, speeds, added_mass):
    d, side = g["d"], g["side"]
    u_law = g["u"]
    reynolds = u_law * d / g["nu"]
    wall = di_felice_factor(d / side, reynolds)
    # The window: the last third of the run above one box half-width (plus the kernel) from the floor, where the
    # floor's own correction (Brenner 1961: 1 + 9/8 (d/2)/h) is below 1.5 % at h >= D/2 >= 4 d... keep h >= D/2.
    floor_clear = g["clearance"]
    usable = [k for k, z in enumerate(heights) if z > floor_clear]
    end = usable[-1] if usable else len(times) - 1
    start = next(k for k in range(end + 1) if times[k] >= 0.5 * times[end])
    window = speeds[start:end + 1]
    terminal = sum(window) / max(len(window), 1)
    expected = u_law  # the run ends before the disturbance reaches the walls (case_geometry): unbounded
    ode_t, ode_v = point_particle(d, g["nu"], 1.0, added_mass, times[end], min(g["relax"] / 50.0, times[1]))
    # RMS of v_sim - v_ode over [0, t_end of window], on the probe's rows (ODE interpolated)
    squares, count, j = 0.0, 0, 0
    for k in range(end + 1):
        while j + 1 < len(ode_t) and ode_t[j + 1] < times[k]:
            j += 1
        if j + 1 < len(ode_t):
            f = (times[k] - ode_t[j]) / (ode_t[j + 1] - ode_t[j])
            v = ode_v[j] + f * (ode_v[j + 1] - ode_v[j])
        else:
            v = ode_v[-1]
        squares += (speeds[k] - v) ** 2
        count += 1
    rms = math.sqrt(squares / max(count, 1)) / expected
    return dict(reynolds=reynolds, wall=wall, terminal=terminal, expected=expected,
                error=terminal / expected - 1.0, rms=rms, window=(times[start], times[end]))


def run_case(riffle, out, reynolds, d_over_l0, box_over_d, correction, added_mass, voidage_radius, threads):
    g = case_geometry(reynolds, d_over_l0, box_over_d)
    name = f"re{reynolds:g}_dl{d_over_l0:g}_{'on' if correction else 'off'}"
    case_dir = pathlib.Path(out) / name
    case_dir.mkdir(parents=True, exist_ok=True)
    text, _ = scene_text(g, correction, added_mass, voidage_radius)
    scene = case_dir / "scene.toml"
    scene.write_text(text)
    run_dir = case_dir / "run"
    subprocess.run([riffle, "run", str(scene), "--out", str(run_dir), "--threads", str(threads)],
                   check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    times, heights, speeds = read_probe(run_dir / "probe_grains.csv")
    result = analyse(g, times, heights, speeds, added_mass)
    result.update(name=name, d_over_l0=d_over_l0, correction=correction, geometry=g)
    return result


CASES = {
    "quick": [(1.0, 1.0), (10.0, 2.0)],
    "matrix": [(re, dl) for re in (0.1, 1.0, 10.0, 50.0) for dl in (0.5, 1.0, 2.0, 3.0)],
}


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--riffle", default="build/riffle")
    parser.add_argument("--out", default="out/settling")
    parser.add_argument("--cases", default="quick", help="quick, matrix, or RE:D/L0[,RE:D/L0...]")
    parser.add_argument("--box", type=float, default=8.0, help="box side over the diameter")
    parser.add_argument("--correction", default="both", choices=["on", "off", "both"])
    parser.add_argument("--added-mass", type=float, default=0.0, help="C_a of the reference ODE (and the scene)")
    parser.add_argument("--voidage-radius", type=float, default=0.0,
                        help="[coupling] voidage_radius (m); a huge one makes a lone grain read eps = 1")
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--check", nargs=2, type=float, metavar=("TERMINAL", "RMS"))
    args = parser.parse_args(argv)
    if args.cases in CASES:
        cases = CASES[args.cases]
    else:
        cases = [tuple(float(x) for x in item.split(":")) for item in args.cases.split(",")]
    switches = {"on": [True], "off": [False], "both": [False, True]}[args.correction]
    print("| Re | d/l0 | D/d | correction | terminal / law (walls) | error | approach RMS | window [s] |")
    print("|---|---|---|---|---|---|---|---|")
    failed = False
    for reynolds, d_over_l0 in cases:
        for correction in switches:
            r = run_case(args.riffle, args.out, reynolds, d_over_l0, args.box, correction, args.added_mass,
                         args.voidage_radius, args.threads)
            g = r["geometry"]
            print(f"| {reynolds:g} | {d_over_l0:g} | {g['side'] / g['d']:.1f} | {'on' if correction else 'off'} | "
                  f"{r['terminal'] * 1e3:.3f} / {r['expected'] * 1e3:.3f} mm/s (x{r['wall']:.3f}) | "
                  f"{100 * r['error']:+.1f} % | {100 * r['rms']:.1f} % | {r['window'][0]:.3g}-{r['window'][1]:.3g} |",
                  flush=True)
            if args.check and correction and (abs(r["error"]) > args.check[0] or r["rms"] > args.check[1]):
                failed = True
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())

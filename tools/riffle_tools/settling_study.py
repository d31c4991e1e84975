"""A lone sphere settling from rest in a closed box of still liquid (docs/COUPLING.md "The undisturbed fluid
velocity"): terminal speed against the Schiller-Naumann law, the approach against the point-particle equation.

For each case (Re, d/l0) the tool writes a scene, runs riffle, reads the grain's probe and reports:
  - the terminal speed (mean over the window before the floor's influence) against Schiller-Naumann at eps = 1
    (with the history force: against the point-particle equation's mean over the same window, below),
    corrected for the box's walls by Di Felice (1996, Int. J. Multiphase Flow 22, 527-533):
    U/U_inf = ((1 - lam)/(1 - 0.33 lam))^alpha, (3.3 - alpha)/(alpha - 0.85) = 0.1 Re, lam = d / D (D: the box's
    side, the tube's diameter in Di Felice's fit; a square duct's wall effect is within a tenth of that of the
    inscribed tube at small lam, Happel & Brenner 1965, Table 7-4.1, so the side is the closer one);
  - the RMS over the approach (t = 0 up to the window's end) of v_sim - v_ode over the law's speed, where v_ode
    solves (m + C_a m_f) dv/dt = (m - m_f) g - F_SN(v) / K_wall - F_H from rest (C_a = 0 without added mass, 0.5 with
    it; F_H the history force where the run has it, riffle's default with added mass and the correction: Mei &
    Adrian's 1992 kernel, unwindowed).
The sphere's own disturbance and the box's walls are the only departures the correction leaves: the drag law is
riffle's (Wen & Yu at eps = 1 is Schiller-Naumann), so a lone grain must read eps = 1 (see --voidage-radius).

Usage:
  tools/riffle-tools settling-study [--riffle build/riffle] [--out out/settling] [--cases quick|matrix|RE:D]
      [--correction on|off|both] [--added-mass 0|0.5 (default: the scene's default, on)] [--voidage-radius METRES]
      [--threads 1]
Prints one table row per case and run; --check TOL_TERMINAL TOL_RMS exits 1 when a corrected case misses them.
"""
import argparse
import csv
import math
import pathlib
import shutil
import subprocess
import sys

GRAVITY = 9.81
RHO = 1000.0
RHO_S = 1120.0          # a 1120 kg/m^3 sphere; the liquid at 1000
RATIO_RE = 2.4          # r_e / l0, riffle's default
KERNEL_BOX = 5.0        # the box's side over the sampling kernel's radius, at least
APPROACH_BOX = 15.0     # the box's side over the diameter, at least, for the long fall of --approach


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


def wall_resistance(gap_over_radius):
    """Brenner's (1961) resistance of a sphere moving towards a no-slip plane, F / (6 pi mu a V), at gap h/a: Cox &
    Brenner (1967) near contact, Schaffer, Norrelykke & Howard (2007) beyond h/a = 0.0756 (within 0.15 % of
    Brenner's series; the same forms as systems/physics/coupling/lubrication.hpp)."""
    x = max(gap_over_radius, 1e-6)
    if x < 0.07555570638673673:
        return 1.0 / x + 0.2 * math.log(1.0 / x) + 0.9713
    s = 1.0 / (1.0 + x)
    return 1.0 / (1.0 - 9.0 / 8.0 * s + 0.5 * s ** 3 - 0.57 * s ** 4 + 0.2 * s ** 5 + 0.035 * s ** 11 - 0.04 * s ** 12)


def approach_reference(d, nu, added_mass, start_gap, end_gap):
    """(gap, v) of a sphere approaching a no-slip floor: (m + C_a m_f) dv/dt = (m - m_f) g - F_SN(v) lambda(h/a),
    from `start_gap` at its quasi-steady speed there, Brenner's lambda (a Stokes-flow result: the reference holds at
    Re <~ 1, where the wall effect is not yet screened by inertia). RK4 in time, speeds positive downwards."""
    a = d / 2.0
    volume = math.pi / 6.0 * d ** 3
    mass, fluid = RHO_S * volume, RHO * volume
    mu = nu * RHO

    def accel(gap, v):
        re = abs(v) * d / nu
        drag = 3.0 * math.pi * mu * d * v * (1.0 + 0.15 * re ** 0.687) * wall_resistance(gap / a)
        return ((mass - fluid) * GRAVITY - drag) / (mass + added_mass * fluid)

    v = 0.0  # quasi-steady start: bisection on accel(start_gap, v) = 0
    low, high = 0.0, schiller_naumann_speed(d, nu) * 2.0
    for _ in range(100):
        v = 0.5 * (low + high)
        low, high = (v, high) if accel(start_gap, v) > 0.0 else (low, v)
    gap, out = start_gap, [(start_gap, v)]
    dt = 1e-3 * a / max(v, 1e-12)
    while gap > end_gap:
        def f(state):
            return (-state[1], accel(state[0], state[1]))
        k1 = f((gap, v))
        k2 = f((gap + 0.5 * dt * k1[0], v + 0.5 * dt * k1[1]))
        k3 = f((gap + 0.5 * dt * k2[0], v + 0.5 * dt * k2[1]))
        k4 = f((gap + dt * k3[0], v + dt * k3[1]))
        gap += dt / 6.0 * (k1[0] + 2 * k2[0] + 2 * k3[0] + k4[0])
        v += dt / 6.0 * (k1[1] + 2 * k2[1] + 2 * k3[1] + k4[1])
        dt = 1e-3 * a / max(v, 1e-12) if v > 0 else dt
        out.append((gap, v))
    return out


def mei_adrian_factor(age, slip, d, nu):
    """Mei & Adrian's (1992) history kernel over Basset's t^(-1/2) at a time `age` after a change of the slip:
    {1 + (age / t_H)^(3/4)}^(-2), t_H = (4/pi)^(1/3) nu f_H^2 / slip^2, f_H = 0.75 + 0.105 Re (their two-term kernel
    {(4 pi nu t / d^2)^(1/4) + (pi |w|^3 t^2 / (d nu f_H^3))^(1/2)}^(-2) rewritten; 1 for a grain at rest)."""
    if slip <= 0.0:
        return 1.0
    f_h = 0.75 + 0.105 * slip * d / nu
    t_h = (4.0 / math.pi) ** (1.0 / 3.0) * nu * f_h * f_h / (slip * slip)
    return (1.0 + (age / t_h) ** 0.75) ** -2


def point_particle_with_history(d, nu, wall, added_mass, kernel, t_end, dt):
    """v(t) of (m + C_a m_f) dv/dt = (m - m_f) g - F_SN(v) / wall - F_H, from rest, with the history force
    F_H = 3/2 d^2 (pi rho mu)^(1/2) int K(t - tau) dv/dtau dtau of Basset's kernel (t - tau)^(-1/2) or Mei & Adrian's
    (the slip's current magnitude sets t_H), unwindowed: the physics, not riffle's modes. dv/dtau is constant over
    each step and the kernel integrated exactly over it (Basset's part; Mei & Adrian's factor at the step's middle
    age); this step's own part is implicit. First order in dt: the caller's dt is a fiftieth of the relaxation time
    or less (0.5 % of the law's speed, checked against dt/2)."""
    volume = math.pi / 6.0 * d ** 3
    mass, fluid = RHO_S * volume, RHO * volume
    mu = nu * RHO
    prefactor = 1.5 * d * d * math.sqrt(math.pi * RHO * mu)
    times, speeds, changes = [0.0], [0.0], []
    v, t = 0.0, 0.0
    while t < t_end:
        factor = (lambda age: mei_adrian_factor(age, v, d, nu)) if kernel == "mei_adrian" else (lambda age: 1.0)
        n = len(changes)
        past = 0.0  # the earlier steps' part: step j spans [t_j, t_j + dt], ages (n - j) dt down to (n - j - 1) dt
        for j, change in enumerate(changes):
            older, newer = (n - j + 1) * dt, (n - j) * dt
            past += change / dt * 2.0 * (math.sqrt(older) - math.sqrt(newer)) * factor(0.5 * (older + newer))
        own = 2.0 * math.sqrt(dt) * factor(0.5 * dt) / dt  # this step's: times its change of v
        re = abs(v) * d / nu
        drag = 3.0 * math.pi * mu * d * v * (1.0 + 0.15 * re ** 0.687) / wall
        change = dt * ((mass - fluid) * GRAVITY - drag - prefactor * past) / (
            mass + added_mass * fluid + dt * prefactor * own)
        changes.append(change)
        v += change
        t += dt
        times.append(t)
        speeds.append(v)
    return times, speeds


def point_particle(d, nu, wall, added_mass, t_end, dt, history=None):
    """v(t) of (m + C_a m_f) dv/dt = (m - m_f) g - F_SN(v) / wall, from rest (speeds positive downwards); with
    `history` ("basset" or "mei_adrian") the history force too (point_particle_with_history)."""
    if history:
        return point_particle_with_history(d, nu, wall, added_mass, history, t_end, min(dt, t_end / 2000.0))
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


APPROACH_START = 8.0    # the approach's reference starts this many diameters of gap above the floor
APPROACH_WINDOW = (1.0, 6.0)  # the approach is compared over these gaps [diameters]


def case_geometry(reynolds, d_over_l0, box_over_d, approach=False):
    """Scene numbers for one case: d = 10 mm, l0 = d / (d/l0), the box's side D = box_over_d d (rounded to l0).
    With `approach` the run goes on until the sphere has come down to the floor: released so that it is still
    APPROACH_START + 2 diameters of gap above it after the terminal window, the run long enough to land."""
    d = 0.01
    l0 = d / d_over_l0
    nu = viscosity_for(reynolds, d)
    if approach:  # the long fall lets the disturbance reach the side walls: in a box of 8.5 d they hinder the
        # sphere as Di Felice's tube does (0.77 of the law at Re 1), and the drift with l0 hides behind them
        box_over_d = max(box_over_d, APPROACH_BOX)
    side = max(round(box_over_d * d / l0), 8) * l0
    u = schiller_naumann_speed(d, nu)
    relax = (RHO_S / RHO + 0.5) * d * d / (18.0 * nu * (1.0 + 0.15 * reynolds ** 0.687))
    kernel = d / 2 + RATIO_RE * max(l0, d / 2)  # the lone grain's kernel: no narrower than at l0 = r (riffle's rule)
    # Run long enough for the slowest mode of the disturbance's build-up (8 R^2 / nu, shortened by the Oseen
    # factor ~ 3.5 / Re_R) and ten relaxation times; the fall then sets the height (plus room at both ends).
    # The run: twelve relaxation times (the window is the last half). The box's walls are met by the sphere's
    # diffusing disturbance after about (D/2)^2 / (4 nu) (it spreads as sqrt(4 nu t)); the side D keeps that beyond
    # the run, so the reference is the unbounded law. The side is at least 8 d and 5 R (R the kernel's radius: in a
    # box of 3 R the walls already confine the spread force's immediate, solenoidal answer).
    t_end = 12.0 * relax
    side = max(side, math.ceil(max(KERNEL_BOX * kernel, 2.0 * math.sqrt(4.0 * nu * t_end) * 2.0) / l0) * l0)
    extra = 0.0
    if approach:  # from the terminal window's end to the floor at the law's speed, and as long again to slow down
        # (the box as for the terminal speed: its side walls join the floor in the approach's last part)
        extra = (APPROACH_START + 2.0) * d
        t_end += 2.0 * extra / u
    fall = u * 12.0 * relax
    clearance = max(side / 2.0, 2.0 * kernel, extra + d / 2.0)  # the window ends this far above the floor
    height = (math.ceil((fall * 1.1 + clearance + kernel) / l0) + 3) * l0
    return dict(d=d, l0=l0, nu=nu, side=side, u=u, relax=relax, t_end=t_end, height=height, kernel=kernel,
                clearance=clearance, approach=approach)


def scene_text(g, correction, added_mass, voidage_radius, extra=(), dt_scale=1.0, fluid_extra=()):
    """The scene; `correction` is "on", "off" or "default" (no `self_induced_velocity` key: what a user gets);
    `extra` holds more `[coupling]` lines ("key = value"), `fluid_extra` more `[fluid]` lines; `dt_scale`
    multiplies the step (its convergence)."""
    d, l0, nu, side, height = g["d"], g["l0"], g["nu"], g["side"], g["height"]
    dt = dt_scale * min(0.2 * l0 * l0 / nu, 0.2 * l0 / max(g["u"], 1e-9), 2e-3)
    release = height - g["kernel"] - l0  # the sampling sphere under the surface
    lines = [
        "[run]", f"end_time = {g['t_end']:.15g}", f"dt = {dt:.15g}", "solid_substeps = 20", "",
        "[materials.grain]", f"density = {RHO_S}", "young_modulus = 1.0e6", "poisson_ratio = 0.3", "",
        "[materials.glass]", "density = 2500.0", "young_modulus = 1.0e6", "poisson_ratio = 0.3", "",
        "[tank]", f"size = [{side:.15g}, {side:.15g}, {height + l0:.15g}]", 'open_faces = ["z_max"]',
        'wall_material = "glass"', "",
        "[solids]", "[[solids.spheres]]", f"position = [{side / 2:.15g}, {side / 2:.15g}, {release:.15g}]",
        f"radius = {d / 2:.15g}", 'material = "grain"', "",
        "[fluid]", f"spacing = {l0:.15g}", f"kinematic_viscosity = {nu:.15g}", f"density = {RHO}",
        *fluid_extra,
        "[[fluid.boxes]]", "low = [0.0, 0.0, 0.0]", f"high = [{side:.15g}, {side:.15g}, {height:.15g}]", "",
    ]
    if g["approach"]:  # the floor stops the sphere (the window ends a diameter above it)
        lines += ["[contact]", "restitution = 0.5", "friction = 0.3", "max_impact_speed = 1.0", ""]
    lines += [
        "[coupling]",
    ]
    if correction != "default":
        lines.append(f"self_induced_velocity = {'true' if correction == 'on' else 'false'}")
    lines += list(extra)
    if voidage_radius > 0.0:
        lines.append(f"voidage_radius = {voidage_radius:.15g}")
    # None: no key, the scene's default (added mass on with the MPS water: C_a = 1/2 for a lone grain).
    if added_mass is not None:
        lines.append(f"added_mass = {'true' if added_mass > 0.0 else 'false'}")
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


def history_in_run(correction, added_mass, extra):
    """The history kernel the run has ("basset", "mei_adrian") or None, by riffle's rule: a `history_force` line
    decides; without one it is on where added mass and the self-induced correction are (the MPS water)."""
    keys = {}
    for line in extra:
        key, _, value = line.partition("=")
        keys[key.strip()] = value.strip().strip('"')
    if "history_force" in keys:
        on = keys["history_force"] == "true"
    else:
        on = added_mass > 0.0 and correction != "off"
    return keys.get("history_kernel", "mei_adrian") if on else None


def analyse(g, times, heights, speeds, added_mass, history=None):
    d, side = g["d"], g["side"]
    u_law = g["u"]
    reynolds = u_law * d / g["nu"]
    wall = di_felice_factor(d / side, reynolds)
    # The window: the last third of the run above one box half-width (plus the kernel) from the floor, where the
    # floor's own correction (Brenner 1961: 1 + 9/8 (d/2)/h) is below 1.5 % at h >= D/2 >= 4 d... keep h >= D/2.
    floor_clear = g["clearance"]
    usable = [k for k, z in enumerate(heights) if z > floor_clear and times[k] <= 12.0 * g["relax"] * (1 + 1e-9)]
    end = usable[-1] if usable else len(times) - 1
    start = next(k for k in range(end + 1) if times[k] >= 0.5 * times[end])
    window = speeds[start:end + 1]
    terminal = sum(window) / max(len(window), 1)
    expected = u_law  # the run ends before the disturbance reaches the walls (case_geometry): unbounded
    ode_t, ode_v = point_particle(d, g["nu"], 1.0, added_mass, times[end], min(g["relax"] / 50.0, times[1]), history)
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
    if history:
        # With the history force the memory of the start still holds the sphere back over the window (at Re 1 Mei &
        # Adrian's t_H is a third of a second): the reference is the equation's mean over the same window, which
        # tends to the law as the memory fades.
        in_window = [v for t, v in zip(ode_t, ode_v) if times[start] <= t <= times[end]]
        expected = sum(in_window) / max(len(in_window), 1)
    result = dict(reynolds=reynolds, wall=wall, terminal=terminal, expected=expected,
                  error=terminal / expected - 1.0, rms=rms, window=(times[start], times[end]))
    if g["approach"]:
        result.update(analyse_approach(g, heights, speeds, added_mass))
    return result


def analyse_approach(g, heights, speeds, added_mass):
    """The approach to the floor. `arrival`: the mean speed over gaps of APPROACH_START to APPROACH_START + 2
    diameters over the law's (the speed after the long fall, before the floor matters: a drift of the terminal speed
    shows here). Over gaps APPROACH_WINDOW (in diameters): the RMS of v / v(APPROACH_START) of the run minus the
    same ratio of the reference (approach_reference), and the mean of both ratios from 6 to 2 diameters."""
    d = g["d"]
    arrival_speeds = [v for z, v in zip(heights, speeds)
                      if APPROACH_START * d <= z - d / 2.0 <= (APPROACH_START + 2.0) * d]
    arrival = sum(arrival_speeds) / len(arrival_speeds) if arrival_speeds else float("nan")
    start_speeds = [v for z, v in zip(heights, speeds)
                    if APPROACH_START * d <= z - d / 2.0 <= (APPROACH_START + 0.5) * d]
    terminal = sum(start_speeds) / len(start_speeds) if start_speeds else float("nan")
    reference = approach_reference(d, g["nu"], added_mass, APPROACH_START * d, 0.5 * APPROACH_WINDOW[0] * d)
    reference.reverse()  # increasing gap

    def reference_speed(gap):
        low, high = 0, len(reference) - 1
        while high - low > 1:
            mid = (low + high) // 2
            low, high = (mid, high) if reference[mid][0] <= gap else (low, mid)
        (g0, v0), (g1, v1) = reference[low], reference[high]
        return v0 + (v1 - v0) * (gap - g0) / (g1 - g0) if g1 > g0 else v0

    squares, count, sim_mean, ref_mean, mean_count = 0.0, 0, 0.0, 0.0, 0
    for z, v in zip(heights, speeds):
        gap = z - d / 2.0
        if APPROACH_WINDOW[0] * d <= gap <= APPROACH_WINDOW[1] * d:
            v_ref = reference_speed(gap) / reference[-1][1]
            squares += (v / terminal - v_ref) ** 2
            count += 1
            if gap >= 2.0 * d:
                sim_mean += v / terminal
                ref_mean += v_ref
                mean_count += 1
    arrival /= g["u"]
    if count == 0:
        return dict(approach_rms=float("nan"), approach_mean=float("nan"), approach_reference_mean=float("nan"),
                    arrival=arrival)
    return dict(approach_rms=math.sqrt(squares / count), approach_mean=sim_mean / max(mean_count, 1),
                approach_reference_mean=ref_mean / max(mean_count, 1), arrival=arrival)


def run_case(riffle, out, reynolds, d_over_l0, box_over_d, correction, added_mass, voidage_radius, threads,
             approach=False, extra=(), dt_scale=1.0, fluid_extra=()):
    g = case_geometry(reynolds, d_over_l0, box_over_d, approach)
    name = f"re{reynolds:g}_dl{d_over_l0:g}_{correction}{'_approach' if approach else ''}"
    if dt_scale != 1.0:
        name += f"_dt{dt_scale:g}"
    case_dir = pathlib.Path(out) / name
    case_dir.mkdir(parents=True, exist_ok=True)
    text, _ = scene_text(g, correction, added_mass, voidage_radius, extra, dt_scale, fluid_extra)
    scene = case_dir / "scene.toml"
    scene.write_text(text)
    run_dir = case_dir / "run"
    shutil.rmtree(run_dir, ignore_errors=True)
    subprocess.run([riffle, "run", str(scene), "--out", str(run_dir), "--threads", str(threads)],
                   check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    times, heights, speeds = read_probe(run_dir / "probe_grains.csv")
    # The reference's C_a: riffle's default for a lone grain in the MPS water (on, 1/2) when the scene names none.
    reference_added_mass = 0.5 if added_mass is None else added_mass
    result = analyse(g, times, heights, speeds, reference_added_mass,
                     history_in_run(correction, reference_added_mass, extra))
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
    parser.add_argument("--box", type=float, default=8.0, help="box side over the diameter (at least 15 with --approach)")
    parser.add_argument("--correction", default="both", choices=["on", "off", "default", "both", "all"],
                        help="self_induced_velocity on, off, unset (the default), off and on, or all three")
    parser.add_argument("--approach", action="store_true",
                        help="run on to the floor and compare the approach (gaps of 1-6 diameters) with a sphere "
                             "approaching a no-slip plane (Brenner 1961's resistance)")
    parser.add_argument("--coupling", action="append", default=[], metavar="'KEY = VALUE'",
                        help="another [coupling] line for every case (repeatable)")
    parser.add_argument("--fluid", action="append", default=[], metavar="'KEY = VALUE'",
                        help="another [fluid] line for every case (repeatable), e.g. 'initial_arrangement = \"packed\"'")
    parser.add_argument("--added-mass", type=float, default=None,
                        help="C_a of the reference ODE, and the scene's added_mass (0: false, else true); without "
                             "it the scene has no key (riffle's default, on) and the reference C_a = 1/2")
    parser.add_argument("--voidage-radius", type=float, default=0.0,
                        help="[coupling] voidage_radius (m); a huge one makes a lone grain read eps = 1")
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--dt-scale", type=float, default=1.0,
                        help="the step over the study's own (min(0.2 l0^2/nu, 0.2 l0/U, 2 ms)): its convergence")
    parser.add_argument("--check", nargs="+", type=float, metavar="TOL",
                        help="TERMINAL RMS [APPROACH_RMS]: exit 1 when a case (not off) misses them")
    args = parser.parse_args(argv)
    if args.check and len(args.check) not in (2, 3) or (args.check and len(args.check) == 3 and not args.approach):
        parser.error("--check takes TERMINAL RMS, and APPROACH_RMS only with --approach")
    if args.cases in CASES:
        cases = CASES[args.cases]
    else:
        cases = [tuple(float(x) for x in item.split(":")) for item in args.cases.split(",")]
    switches = {"on": ["on"], "off": ["off"], "default": ["default"], "both": ["off", "on"],
                "all": ["off", "on", "default"]}[args.correction]
    header = "| Re | d/l0 | D/d | correction | terminal / law (walls) | error | approach RMS | window [s] |"
    if args.approach:
        header += " speed at 8-10 d / law | floor approach RMS (1-6 d) | mean v/v(8 d) 2-6 d (reference) |"
    print(header)
    print("|---" * header.count(" |") + "|")
    failed = False
    for reynolds, d_over_l0 in cases:
        for correction in switches:
            r = run_case(args.riffle, args.out, reynolds, d_over_l0, args.box, correction, args.added_mass,
                         args.voidage_radius, args.threads, args.approach, args.coupling, args.dt_scale,
                         args.fluid)
            g = r["geometry"]
            row = (f"| {reynolds:g} | {d_over_l0:g} | {g['side'] / g['d']:.1f} | {correction} | "
                   f"{r['terminal'] * 1e3:.3f} / {r['expected'] * 1e3:.3f} mm/s (x{r['wall']:.3f}) | "
                   f"{100 * r['error']:+.1f} % | {100 * r['rms']:.1f} % | {r['window'][0]:.3g}-{r['window'][1]:.3g} |")
            if args.approach:
                row += (f" {r['arrival']:.3f} | {100 * r['approach_rms']:.1f} % | {r['approach_mean']:.3f} "
                        f"({r['approach_reference_mean']:.3f}) |")
            print(row, flush=True)
            if args.check and correction != "off":
                missed = abs(r["error"]) > args.check[0] or r["rms"] > args.check[1]
                if len(args.check) > 2 and args.approach:  # the arrival speed within the terminal tolerance too
                    missed = missed or not (r["approach_rms"] <= args.check[2])
                    missed = missed or not (abs(r["arrival"] - 1.0) <= args.check[0])
                failed = failed or missed
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())

"""Driven-flow verification sweeps (docs/FLUID.md, "Driven flows"): each case is a scene written here, run
with riffle at several spacings, and its velocity profile (from the fluid's VTK frames) compared with the analytic
one in a stated norm, with the order of convergence in l0.

Cases that run in a closed box now:
  closed_lid     a lid at U over a layer h in a long closed box (free-slip side boxes: plane flow). Steady profile
                 u = U (3 s^2 - 2 s), s = z/h (Couette with the return flow a closed box forces), lid traction
                 4 mu U / h (the `driven_flow` probe, middle third of the lid).
  closed_tilt    water at rest under a constant body force f: grad p = rho (f, 0, -g) (time mean of a plane fit).
Cases in a channel periodic along x and y ([tank] periodic = ["x", "y"]; 8 x 6 l0 of it, the flow is plane):
  poiseuille     body force f between no-slip walls z = 0, H: u = f z (H - z) / (2 nu)
  couette        lid at U, floor fixed: u = U z / H; lid traction mu U / H
  stokes2        f = F sin(omega t) over a fixed floor under a free-slip lid at H (Stokes' second problem for a
                 pressure-driven oscillation, finite depth): u = Re[(F^/(i omega)) (1 - cosh(k (H - z)) / cosh(k H))
                 e^(i omega t)], k = (1 + i) / delta, delta = sqrt(2 nu / omega) (H / delta = 2.2: the deep-layer
                 answer 1 - exp(-k z) is 10 % off at the lid); amplitude and phase per layer by least squares over
                 the last periods.

A turbulent channel (water, nu = 1e-6 m^2/s; the scene defaults, so the SPS eddy viscosity as a scene sets it):
  turbulent_couette
                 a no-slip lid at U = 1 m/s over water H = 2 cm deep above a no-slip floor, periodic along x and y
                 over 20 x 15 mm at every l0 (plane Couette at U H / nu = 2e4, turbulent), started from the linear
                 profile, dt at the Courant limit 0.2 l0 / U, 3 s (--end). Measured over the last second: the shear
                 stress tau (the mean of the lid's and the floor's; their sum says how far from steady), the effective
                 viscosities nu_gap = tau H / (rho U) and nu_core = tau / (rho du/dz) (du/dz the mean profile's slope
                 over the middle half), the velocity scatter about each layer's mean (u', w' over the middle half) and
                 the SPS eddy viscosity there, against the smooth-wall log law carried to the centre line
                 (U/2 = u* (ln(u* H / (2 nu)) / kappa + B), kappa = 0.41, B = 5.2): does the water's own scatter carry
                 the stress as a viscosity that falls as l0 shrinks?

Norm: e = sqrt(mean over layers of (u_layer - u_exact(z_layer))^2) / U_ref, u_layer the mean u_x of the fluid
particles of one l0 layer (closed boxes: middle third in x only), U_ref the profile's maximum |u|; the order is the
least-squares slope of log e against log l0. Poiseuille and Couette also give the L2 error relative over the fluid
particles, e_2 = sqrt(sum_i (u_x,i - u(z_i))^2 / sum_i u(z_i)^2), each particle at its own z.

    tools/riffle-tools driven-flow-study closed_lid --riffle build/riffle --out /tmp/driven --spacings 0.01 0.005
    tools/riffle-tools driven-flow-study poiseuille --spacings 0.004 0.002 0.001 [--dt-factor 0.5]
        [--set fluid.schemes.conservative_gradient=true]
numpy only (tools/riffle_tools/vtp.py reads the frames).
"""
import argparse
import csv
import math
import pathlib
import subprocess
import sys

import numpy as np

from . import vtp

NU = 1.0e-3  # [m^2/s] laminar cases: a viscous fluid keeps the runs short (Re ~ 1)


def lid_scene(l0, periodic=None):
    """The closed-box lid case of tests/verification/mps/driven_flow_test.cpp at spacing l0 (the same physical sizes):
    water h = 0.08 m deep, 0.48 m long, 0.04 m wide; free-slip side boxes, end walls under the lid and a no-slip
    floor lid at rest, each 3 l0 thick; the top lid cut into three at the water's middle third. nu = 2e-3,
    U = 25 mm/s (Re = 1), t = 5 h^2 / (pi^2 nu). periodic: not None = a periodic channel (no end walls)."""
    h, length, width, wall = 0.08, 0.48, 0.04, 3 * l0
    speed, nu = 0.025, 2.0e-3
    end = 5.0 * h * h / (math.pi ** 2 * nu)
    ends = 0.0 if periodic else wall
    x_total, y_total, z_total = length + 2 * ends, width + 2 * wall, h + 2 * wall
    x0, y0, z0 = ends, wall, wall
    r = lambda v: round(v, 12)  # noqa: E731
    lines = [f'[run]\nname = "lid"\nend_time = {r(end)}\ndt = {r(min(5e-3, 0.2 * l0 * l0 / nu))}\n'
             'gravity = [0.0, 0.0, 0.0]\n',
             '[materials.glass]\ndensity = 2500.0\n',
             f'[tank]\nsize = [{r(x_total)}, {r(y_total)}, {r(z_total)}]\nwall_material = "glass"\n',
             f'[fluid]\nspacing = {l0}\nkinematic_viscosity = {nu}\nclamp_negative_pressure = false\n',
             f'[[fluid.boxes]]\nlow = [{r(x0)}, {r(y0)}, {r(z0)}]\nhigh = [{r(x0 + length)}, {r(y0 + width)}, {r(z0 + h)}]\n',
             f'[[fluid.wall_boxes]]\nlow = [0.0, 0.0, {r(z0)}]\nhigh = [{r(x_total)}, {r(y0)}, {r(z0 + h)}]\nlid = "free_slip"\n',
             f'[[fluid.wall_boxes]]\nlow = [0.0, {r(y0 + width)}, {r(z0)}]\nhigh = [{r(x_total)}, {r(y_total)}, {r(z0 + h)}]\n'
             'lid = "free_slip"\n']
    if not periodic:
        lines += [f'[[fluid.wall_boxes]]\nlow = [0.0, {r(y0)}, {r(z0)}]\nhigh = [{r(x0)}, {r(y0 + width)}, {r(z0 + h)}]\n',
                  f'[[fluid.wall_boxes]]\nlow = [{r(x0 + length)}, {r(y0)}, {r(z0)}]\nhigh = [{r(x_total)}, {r(y0 + width)}, '
                  f'{r(z0 + h)}]\n']
    lines.append(f'[[fluid.wall_boxes]]\nlow = [0.0, 0.0, 0.0]\nhigh = [{r(x_total)}, {r(y_total)}, {r(z0)}]\nlid = "no_slip"\n')
    cuts = [0.0, x0 + length / 3, x0 + 2 * length / 3, x_total]
    for a, b in zip(cuts[:-1], cuts[1:]):
        lines.append(f'[[fluid.wall_boxes]]\nlow = [{r(a)}, 0.0, {r(z0 + h)}]\nhigh = [{r(b)}, {r(y_total)}, {r(z_total)}]\n'
                     f'lid = "no_slip"\nvelocity = {speed}\n')
    lines.append(f'[output]\nvtk_interval = {r(end / 4)}\n[[output.probes]]\nkind = "driven_flow"\nname = "lid"\n'
                 f'interval = {r(end / 50)}\n')
    if periodic:
        lines.append(periodic + "\n")
    info = dict(h=h, U=speed, nu=nu, length=length, x0=x0, z0=z0, width=width, end=end, closed=not periodic,
                middle_lid=f"lid{3 + 1}")  # lids: two free-slip sides, the floor, then the thirds
    return "\n".join(lines), info


def tilt_scene(l0):
    length, width, depth = 0.2, 0.04, 0.1
    text = (f'[run]\nname = "tilt"\nend_time = 2.5\ndt = 2.0e-3\n\n[materials.glass]\ndensity = 2500.0\n\n'
            f'[tank]\nsize = [{length}, {width}, 0.15]\nopen_faces = ["z_max"]\nwall_material = "glass"\n\n'
            f'[fluid]\nspacing = {l0}\nkinematic_viscosity = 5.0e-3\n\n[fluid.body_force]\nkind = "constant"\n'
            f'acceleration = 0.981\n\n[[fluid.boxes]]\nlow = [0.0, 0.0, 0.0]\nhigh = [{length}, {width}, {depth}]\n\n'
            f'[output]\nvtk_interval = 0.05\n')
    return text, dict(length=length, depth=depth, f=0.981)


def channel_scene(case, l0, dt_factor=1.0):
    """Channel of height H = 0.04 m periodic along x and y (8 x 6 l0: the periods exceed twice the neighbour lists'
    reach, 2.7 l0): the floor a no-slip lid at rest, the top a no-slip lid at rest (Poiseuille), at U (Couette) or a
    free-slip lid (Stokes: a layer deep compared with delta), each 3 l0 thick (the lids' wall treatment,
    docs/FLUID.md: the tank's own walls slip). The water fills the channel (tension allowed). dt = dt_factor x the
    viscous limit 0.2 l0^2 / nu (at most 5 ms)."""
    height, wall = 0.04, 3 * l0
    length, width = round(8 * l0, 12), round(6 * l0, 12)
    top = ('lid = "no_slip"\n', 'lid = "no_slip"\nvelocity = 0.01\n', 'lid = "free_slip"\n')[
        ("poiseuille", "couette", "stokes2").index(case)]
    if case == "poiseuille":
        f = 12 * NU * 0.01 / height ** 2  # bulk velocity 1 cm/s
        end = 2.0 * height ** 2 / NU
        force = f'[fluid.body_force]\nkind = "constant"\nacceleration = {f}\ngrains = "none"\n'
        info = dict(f=f, H=height)
    elif case == "couette":
        end = 2.0 * height ** 2 / NU
        force = ""
        info = dict(U=0.01, H=height)
    else:
        period = 1.0
        omega = 2 * math.pi / period
        f = 0.01 * omega  # free-stream amplitude F / omega = 1 cm/s
        end = 6 * period
        force = f'[fluid.body_force]\nkind = "sinusoidal"\namplitude = {f}\nperiod = {period}\ngrains = "none"\n'
        info = dict(F=f, omega=omega, H=height, period=period)
    text = (f'[run]\nname = "{case}"\nend_time = {end}\ndt = {min(5e-3, dt_factor * 0.2 * l0 * l0 / NU)}\n'
            f'gravity = [0.0, 0.0, 0.0]\n\n[materials.glass]\ndensity = 2500.0\n\n'
            f'[tank]\nsize = [{length}, {width}, {round(height + 2 * wall, 12)}]\nwall_material = "glass"\n'
            f'periodic = ["x", "y"]\n\n'
            f'[fluid]\nspacing = {l0}\nkinematic_viscosity = {NU}\nclamp_negative_pressure = false\n\n{force}\n'
            f'[[fluid.boxes]]\nlow = [0.0, 0.0, {wall}]\nhigh = [{length}, {width}, {round(wall + height, 12)}]\n\n'
            f'[[fluid.wall_boxes]]\nlow = [0.0, 0.0, 0.0]\nhigh = [{length}, {width}, {wall}]\nlid = "no_slip"\n\n'
            f'[[fluid.wall_boxes]]\nlow = [0.0, 0.0, {round(wall + height, 12)}]\nhigh = [{length}, {width}, '
            f'{round(2 * wall + height, 12)}]\n'
            f'{top}\n'
            f'[output]\nvtk_interval = {end / 60}\n[[output.probes]]\nkind = "driven_flow"\nname = "drive"\n'
            f'interval = {end / 100}\n')
    info["end"] = end
    info["z0"] = wall
    return text, info


def run(riffle, scene_text, out_dir, name, overrides=()):
    """riffle run of the scene; `overrides` are its --set KEY=VALUE arguments (e.g. a scheme under study)."""
    out_dir.mkdir(parents=True, exist_ok=True)
    scene = out_dir / f"{name}.toml"
    scene.write_text(scene_text)
    run_dir = out_dir / name
    command = [riffle, "run", str(scene), "--out", str(run_dir), "--threads", "1"]
    for override in overrides:
        command += ["--set", override]
    result = subprocess.run(command, capture_output=True, text=True)
    if result.returncode != 0:
        raise RuntimeError(f"riffle failed on {scene} (exit {result.returncode}):\n{result.stderr[-2000:]}")
    return run_dir


def layer_profile(frame, l0, x_window=None, z0=0.0):
    """(z - z0 of each l0 layer, mean u_x of its fluid particles), fluid = kind 0; x_window = (lo, hi) or None."""
    points, velocity, kind = frame["points"] - np.array([0.0, 0.0, z0]), frame["velocity"], frame["kind"]
    use = kind == 0
    if x_window is not None:
        use &= (points[:, 0] > x_window[0]) & (points[:, 0] < x_window[1])
    layers = np.floor(points[use, 2] / l0).astype(int)
    z, u = [], []
    for layer in np.unique(layers):
        inside = layers == layer
        z.append((layer + 0.5) * l0)
        u.append(velocity[use][inside, 0].mean())
    return np.array(z), np.array(u)


def last_frame(run_dir):
    frames = vtp.read_pvd(run_dir / "fluid.pvd")
    return frames[-1][0], vtp.read_vtp(frames[-1][1], ["velocity", "kind", "pressure"])


def probe_rows(run_dir, name):
    with open(run_dir / f"probe_{name}.csv") as file:
        return list(csv.DictReader(file))


def order(spacings, errors):
    if len(spacings) < 2 or min(errors) <= 0:
        return float("nan")
    return float(np.polyfit(np.log(spacings), np.log(errors), 1)[0])


def study_lid(args, periodic=None):
    errors, tractions = [], []
    for l0 in args.spacings:
        text, info = lid_scene(l0, periodic)
        run_dir = run(args.riffle, text, args.out, f"lid_{l0}", args.set)
        _, frame = last_frame(run_dir)
        length, h, speed = info["length"], info["h"], info["U"]
        z, u = layer_profile(frame, l0, (info["x0"] + length / 3, info["x0"] + 2 * length / 3), z0=info["z0"])
        s = z / h
        exact = speed * (3 * s * s - 2 * s) if info["closed"] else speed * s
        error = math.sqrt(np.mean((u - exact) ** 2)) / speed
        rows = probe_rows(run_dir, "lid")
        # The middle lid's force over the water under it (the lid spans the side boxes too).
        shear = float(rows[-1][info["middle_lid"] + "_fx_N"]) / (length / 3 * info["width"])
        expected = (4.0 if info["closed"] else 1.0) * 1000.0 * info["nu"] * speed / h
        errors.append(error)
        tractions.append(abs(shear / expected - 1.0))
        print(f"l0 = {l0} m (h = {h / l0:.0f} l0): profile error {error:.4f} U, lid shear {shear:.5g} Pa against "
              f"{expected:.5g} Pa ({100 * (shear / expected - 1):+.2f} %)", flush=True)
    print(f"order in l0: profile error {order(args.spacings, errors):.2f}, traction error "
          f"{order(args.spacings, tractions):.2f}")


def study_tilt(args):
    for l0 in args.spacings:
        text, info = tilt_scene(l0)
        run_dir = run(args.riffle, text, args.out, f"tilt_{l0}", args.set)
        slopes = []
        for time, path in vtp.read_pvd(run_dir / "fluid.pvd"):
            if time < 1.5 - 1e-9:
                continue
            frame = vtp.read_vtp(path, ["kind", "pressure"])
            p, kind = frame["points"], frame["kind"]
            surface = info["depth"] + info["f"] / 9.81 * (p[:, 0] - info["length"] / 2)
            use = (kind == 0) & (p[:, 2] < surface - 2 * l0) & (p[:, 0] > l0) & (p[:, 0] < info["length"] - l0) \
                & (p[:, 2] > l0)
            matrix = np.column_stack([np.ones(use.sum()), p[use, 0], p[use, 2]])
            slopes.append(np.linalg.lstsq(matrix, frame["pressure"][use], rcond=None)[0][1:])
        dpdx, dpdz = np.mean(slopes, axis=0)
        print(f"l0 = {l0} m: dp/dx = {dpdx:.1f} Pa/m (rho f = {1000 * info['f']:.1f}, "
              f"{100 * (dpdx / (1000 * info['f']) - 1):+.2f} %), dp/dz = {dpdz:.1f} Pa/m (-rho g = -9810)")


def channel_exact(case, info, z):
    if case == "poiseuille":
        return info["f"] * z * (info["H"] - z) / (2 * NU)
    return info["U"] * z / info["H"]


TURBULENT_HEIGHT, TURBULENT_LID, WATER_NU, WATER_RHO = 0.02, 1.0, 1.0e-6, 1000.0


def turbulent_couette_scene(l0, end=3.0):
    """Plane Couette flow of water at U H / nu = 2e4 (docs/cases/sheared-beds.md): a no-slip lid at 1 m/s over 2 cm
    of water, lids 3 l0 thick, periodic over 20 x 15 mm (at least 8 x 6 l0), SPS eddy viscosity."""
    height, wall = TURBULENT_HEIGHT, 3 * l0
    length = round(max(8, round(0.020 / l0)) * l0, 12)
    width = round(max(6, round(0.015 / l0)) * l0, 12)
    top = round(wall + height, 12)
    text = (f'[run]\nname = "turbulent_couette"\nend_time = {end}\ndt = {0.2 * l0 / TURBULENT_LID}\n'
            f'gravity = [0.0, 0.0, 0.0]\n\n[materials.glass]\ndensity = 2500.0\n\n'
            f'[tank]\nsize = [{length}, {width}, {round(height + 2 * wall, 12)}]\nwall_material = "glass"\n'
            f'periodic = ["x", "y"]\n\n'
            f'[fluid]\nspacing = {l0}\nkinematic_viscosity = {WATER_NU}\nclamp_negative_pressure = false\n'
            f'turbulence = "sps"\n\n'
            f'[fluid.initial_velocity]\nkind = "linear"\nbottom = {wall}\ntop = {top}\nvelocity = {TURBULENT_LID}\n\n'
            f'[[fluid.boxes]]\nlow = [0.0, 0.0, {wall}]\nhigh = [{length}, {width}, {top}]\n\n'
            f'[[fluid.wall_boxes]]\nlow = [0.0, 0.0, 0.0]\nhigh = [{length}, {width}, {wall}]\nlid = "no_slip"\n\n'
            f'[[fluid.wall_boxes]]\nlow = [0.0, 0.0, {top}]\nhigh = [{length}, {width}, {round(top + wall, 12)}]\n'
            f'lid = "no_slip"\nvelocity = {TURBULENT_LID}\n\n'
            f'[output]\nvtk_interval = 0.1\n[[output.probes]]\nkind = "driven_flow"\nname = "drive"\n'
            f'interval = 0.01\n')
    return text, dict(H=height, z0=wall, end=end)


def log_law_stress(kappa=0.41, smooth=5.2):
    """tau / rho of the smooth-wall log law carried to the centre line of the turbulent Couette case."""
    u_star = 0.03
    for _ in range(100):  # fixed point of u* = (U/2) / (ln(u* H / (2 nu)) / kappa + B)
        u_star = 0.5 * TURBULENT_LID / (math.log(u_star * TURBULENT_HEIGHT / (2 * WATER_NU)) / kappa + smooth)
    return u_star * u_star


def study_turbulent(args):
    smagorinsky = 0.12
    for override in args.set:
        if override.startswith("fluid.smagorinsky_constant="):
            smagorinsky = float(override.split("=", 1)[1])
    reference = log_law_stress()
    print(f"smooth-wall log law to the centre line: tau/rho = {reference:.3e} m^2/s^2, u* = {math.sqrt(reference):.4f} "
          f"m/s, nu_gap = {reference * TURBULENT_HEIGHT / TURBULENT_LID:.3e} m^2/s")
    print("| l0 [mm] | H/l0 | particles | tau [Pa], last s (second-last s) | lid + floor [Pa] | nu_gap [m^2/s] | "
          "du/dz core [1/s] | nu_core [m^2/s] | nu_SPS core [m^2/s] | u', w' core / u* |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for l0 in args.spacings:
        text, info = turbulent_couette_scene(l0, args.end)
        run_dir = args.out / f"turbulent_couette_{l0}"
        if not (args.reuse and "finished at" in (run_dir / "riffle.log").read_text(errors="replace")
                if (run_dir / "riffle.log").exists() else False):
            run_dir = run(args.riffle, text, args.out, f"turbulent_couette_{l0}", args.set)
        rows = probe_rows(run_dir, "drive")
        times = np.array([float(r["time_s"]) for r in rows])
        # lid0 is the floor (at rest), lid1 the moving lid; in a steady flow their stresses are equal and opposite.
        floor = np.array([float(r["lid0_shear_Pa"]) if r["lid0_shear_Pa"] else math.nan for r in rows])
        lid = np.array([float(r["lid1_shear_Pa"]) if r["lid1_shear_Pa"] else math.nan for r in rows])
        shear = 0.5 * (lid - floor)
        last_second = times > info["end"] - 1.0 + 1e-9
        last = np.nanmean(shear[last_second])
        before = np.nanmean(shear[(times > info["end"] - 2.0 + 1e-9) & ~last_second])
        imbalance = np.nanmean(lid[last_second] + floor[last_second])
        height = info["H"]
        profiles, scatter_u, scatter_w, count = [], [], [], 0
        for time, path in vtp.read_pvd(run_dir / "fluid.pvd"):
            if time < info["end"] - 1.0 - 1e-9:
                continue
            frame = vtp.read_vtp(path, ["velocity", "kind"])
            fluid = frame["kind"] == 0
            zp = frame["points"][fluid, 2] - info["z0"]
            count = int(fluid.sum())
            # Layers l0 thick on a fixed grid over the water's depth (a particle that strays past either end counts in
            # the end layer), so that every frame's profile has the same layers.
            n_layers = int(round(height / l0))
            layers = np.clip(np.floor(zp / l0).astype(int), 0, n_layers - 1)
            z = (np.arange(n_layers) + 0.5) * l0
            velocity = frame["velocity"][fluid]
            means = np.array([velocity[layers == k].mean(axis=0) for k in range(n_layers)])
            profiles.append(means[:, 0])
            core = (zp > 0.25 * height) & (zp < 0.75 * height)
            deviation = velocity[core] - means[layers[core]]
            scatter_u.append(np.sqrt(np.mean(deviation[:, 0] ** 2)))
            scatter_w.append(np.sqrt(np.mean(deviation[:, 2] ** 2)))
        profile = np.mean(profiles, axis=0)
        core = (z > 0.25 * height) & (z < 0.75 * height)
        slope = float(np.polyfit(z[core], profile[core], 1)[0])
        u_star = math.sqrt(abs(last) / WATER_RHO)
        print(f"| {1e3 * l0:g} | {height / l0:.0f} | {count} | {last:.4g} ({before:.4g}) | {imbalance:+.3g} | "
              f"{abs(last) * height / (WATER_RHO * TURBULENT_LID):.3e} | {slope:.1f} | "
              f"{abs(last) / (WATER_RHO * slope):.3e} | {(smagorinsky * l0) ** 2 * slope:.3e} | "
              f"{np.mean(scatter_u) / u_star:.2f}, {np.mean(scatter_w) / u_star:.2f} |", flush=True)


def study_channel(args):
    errors, particle_errors = [], []
    for l0 in args.spacings:
        text, info = channel_scene(args.case, l0, args.dt_factor)
        run_dir = run(args.riffle, text, args.out, f"{args.case}_{l0}_dt{args.dt_factor}", args.set)
        height = info["H"]
        if args.case in ("poiseuille", "couette"):
            _, frame = last_frame(run_dir)
            z, u = layer_profile(frame, l0, z0=info["z0"])
            exact = channel_exact(args.case, info, z)
            reference = np.abs(exact).max()
            error = math.sqrt(np.mean((u - exact) ** 2)) / reference
            fluid = frame["kind"] == 0
            z_particle = frame["points"][fluid, 2] - info["z0"]
            u_particle = frame["velocity"][fluid, 0]
            exact_particle = channel_exact(args.case, info, z_particle)
            particle_errors.append(math.sqrt(np.sum((u_particle - exact_particle) ** 2) / np.sum(exact_particle ** 2)))
            print(f"  L2 relative over the {fluid.sum()} fluid particles: {particle_errors[-1]:.5f}; bulk velocity "
                  f"{u_particle.mean():.6g} m/s (exact {np.mean(exact_particle):.6g})")
        else:  # Stokes: amplitude and phase per layer over the last two periods
            omega, delta = info["omega"], math.sqrt(2 * NU / info["omega"])
            times, profiles = [], []
            for time, path in vtp.read_pvd(run_dir / "fluid.pvd"):
                if time < info["end"] - 2 * info["period"] - 1e-9:
                    continue
                z, u = layer_profile(vtp.read_vtp(path, ["velocity", "kind"]), l0, z0=info["z0"])
                times.append(time)
                profiles.append(u)
            times, profiles = np.array(times), np.array(profiles)
            basis = np.column_stack([np.cos(omega * times), np.sin(omega * times), np.ones_like(times)])
            coefficients = np.linalg.lstsq(basis, profiles, rcond=None)[0]
            measured = coefficients[0] - 1j * coefficients[1]  # u = Re(u^ e^(i omega t))
            forcing = info["F"] * np.exp(-0.5j * math.pi)  # F sin(omega t) = Re(F e^(-i pi/2) e^(i omega t))
            # Finite depth: no slip at z = 0, free slip (du/dz = 0) at z = H under the free-slip lid.
            k = (1 + 1j) / delta
            exact = forcing / (1j * omega) * (1 - np.cosh(k * (height - z)) / np.cosh(k * height))
            reference = abs(forcing / omega)
            error = math.sqrt(np.mean(np.abs(measured - exact) ** 2)) / reference
            far = np.argmax(z)
            print(f"  far field: amplitude {abs(measured[far]):.5g} m/s (exact {abs(exact[far]):.5g}), phase "
                  f"{math.degrees(np.angle(measured[far])):.1f} deg (exact {math.degrees(np.angle(exact[far])):.1f})")
        errors.append(error)
        print(f"l0 = {l0} m (H = {info['H'] / l0:.0f} l0, dt factor {args.dt_factor}): {args.case} profile error "
              f"{error:.5f} of the profile's maximum", flush=True)
    print(f"order in l0: {order(args.spacings, errors):.2f}" +
          (f" (layer norm), {order(args.spacings, particle_errors):.2f} (L2 over the particles)"
           if particle_errors else ""))


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("case", choices=["closed_lid", "closed_tilt", "poiseuille", "couette", "stokes2",
                                         "turbulent_couette"])
    parser.add_argument("--riffle", default="build/riffle")
    parser.add_argument("--out", type=pathlib.Path, default=pathlib.Path("/tmp/driven_flow_study"))
    parser.add_argument("--spacings", type=float, nargs="+", default=[0.01, 0.005])
    parser.add_argument("--dt-factor", type=float, default=1.0,
                        help="channel cases: dt as a multiple of the viscous limit 0.2 l0^2 / nu")
    parser.add_argument("--reuse", action="store_true",
                        help="turbulent_couette: analyse a finished run in --out instead of running it again (one "
                             "taken further by `riffle resume ... --until T`: give --end T)")
    parser.add_argument("--end", type=float, default=3.0,
                        help="turbulent_couette: the runs' end [s]; the measures are over its last second")
    parser.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                        help="a scene override passed to every riffle run (repeatable), e.g. "
                             "fluid.schemes.conservative_gradient=true")
    args = parser.parse_args(argv)
    if args.case == "closed_lid":
        study_lid(args)
    elif args.case == "closed_tilt":
        study_tilt(args)
    elif args.case == "turbulent_couette":
        study_turbulent(args)
    else:
        study_channel(args)


if __name__ == "__main__":
    sys.exit(main())

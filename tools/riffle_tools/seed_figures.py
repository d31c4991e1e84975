"""Figures shaped like seed 000's (Tazaki, Harada & Gotoh), from one riffle run's output directory, as CSV + PNG,
so that riffle's results can be put beside the paper's. Writes into OUT_DIR/figures/ (or --out DIR).

Usage: tools/riffle-tools seed-figures OUT_DIR [--figures NAME ...] [options]

Figures (NAME: files written):
  fig03   fig03_snapshot_tT<k>.png     side view (x-z, tank frame) of the grains by size class at --times
  fig04   fig04_top_views.csv/png      top views (x-y) of the bed by size class at --times, seen area per class
  fig06   fig06_centroids.csv/png      concentration centroid height per size class vs t/T
  fig07_08  fig07_08_occupancy.csv/png  occupancy rate per class in four 15 mm sub-layers of the front view
  fig09   fig09_side_view_velocity.csv/png  mean x-velocity per 15 mm sub-layer of the grains seen at the front wall
  fig10   fig10_fluid_slab.csv/png     fluid v_x and v_z in a mid-depth x-z slab, and its grains, at four phases
  fig11   fig11_concentration.csv/png  volume concentration per class in four 15 mm sub-layers at --conc-times
  fig12   fig12_coordination_overlap.csv/png  coordination number Z and mean overlap delta* (bed_profile.csv)
  fig13   fig13_cross_section.csv/png  mid-depth cross-section of the bed with the fluid velocity on the plane
  fig14   fig14_velocity_phases.csv/png  mean grain x-velocity per class per 5 mm sub-layer at four phases
  fig15   fig15_fluid_velocity.csv/png   mean fluid x-velocity per 5 mm sub-layer at four phases
  fig16   fig16_strain_q.csv/png       fluid |S|^2 and positive Q-criterion per sub-layer at seed phi = pi
  fig17_19  fig17_19_force_balance.csv/png  mean forces per grain of each class, x and z, vs t/T
  fig19   fig19_z_force_profiles.csv/png  z forces per class per 5 mm sub-layer at four phases (periods 10-12)
  fig20   fig20_granular_temperature.csv/png (+ _profiles.csv)  granular temperature vs t/T and profiles
  drift   drift.csv/png                 grains' mean displacement per start cell over --drift-windows (circulation)

Conventions (docs/RESULTS.md has them in full):
  - heights are above the tank floor (z minus the tank's vertical displacement, zero for the seed's motion);
  - the phase is the tank's: phase = 2 pi f t mod 2 pi, with x_tank = -A r(t) sin(2 pi f t). Phase 0: tank
    velocity most negative (the seed's phi = pi/2); pi/2: tank at -A, accelerating (seed phi = pi); pi: velocity
    most positive (seed 3pi/2); 3pi/2: tank at +A, decelerating (seed 2pi). Frames are matched to a phase when
    within --phase-tolerance degrees of it;
  - velocities in fig14/fig15 are relative to the tank (lab velocity minus the analytic tank velocity, with the
    quintic start-up ramp) unless --frame lab; both are in the CSV;
  - a "stage" is a range of periods, the k-th period being t/T in [k-1, k] (seed numbering). --stages 10 85 is
    the seed's developing and fully developed stage; 10-12 averages periods 10 to 12. By default the seed's
    stages the run covers, else every period after the start-up ramp as one stage.

Needs numpy and matplotlib (Debian's python3-numpy and python3-matplotlib, installed by tools/setup.sh): run it
with /usr/bin/python3.
"""
import argparse
import csv
import math
import pathlib
import re
import sys

import matplotlib
import numpy as np

from . import plotting, seed_views, vtp
from .run_outputs import number, read_rows as read_csv_rows
from .tank_motion import SinusoidalMotion

plt = plotting.pyplot("seed_figures")
from matplotlib.collections import EllipseCollection  # noqa: E402  (after the backend is chosen)

try:
    import tomllib
except ImportError:  # Python < 3.11: the scene is then not read, the fall-backs are used
    tomllib = None

G = 9.81
CLASS_NAMES = {0: "small (5 mm)", 1: "medium (10 mm)", 2: "large (15 mm)"}
CLASS_COLOURS = {0: "#c8a24a", 1: "#222222", 2: "#d62728"}
PHASES = [(0.0, "phase 0 (seed φ=π/2): tank velocity max −"),
          (0.5 * math.pi, "phase π/2 (seed φ=π): accelerating"),
          (math.pi, "phase π (seed φ=3π/2): tank velocity max +"),
          (1.5 * math.pi, "phase 3π/2 (seed φ=2π): decelerating")]
SEED_PHI = ["pi/2", "pi", "3pi/2", "2pi"]
ALL_FIGURES = ["fig03", "fig04", "fig06", "fig07_08", "fig09", "fig10", "fig11", "fig12", "fig13", "fig14", "fig15",
               "fig16", "fig17_19", "fig19", "fig20", "drift"]


class Skip(Exception):
    """A figure that cannot be made from this run (the message says why)."""


def class_name(k):
    return CLASS_NAMES.get(int(k), f"class {int(k)}")


def class_colour(k):
    return CLASS_COLOURS.get(int(k), f"C{int(k) % 10}")


def write_csv(path, header, rows):
    with open(path, "w", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow(header)
        for row in rows:
            writer.writerow([f"{v:.9g}" if isinstance(v, float) else v for v in row])


# ----------------------------------------------------------------------------------------------------------------
# The run: scene parameters, tank motion, frames


class Run:
    def __init__(self, out_dir, scene_path=None, layer=0.005, verbose=True):
        self.out_dir = pathlib.Path(out_dir)
        self.layer = layer
        self.notes = []
        self.scene = {}
        self.scene_path = self._find_scene(scene_path)
        if self.scene_path is not None and tomllib is not None:
            with open(self.scene_path, "rb") as handle:
                self.scene = tomllib.load(handle)
        tank = self.scene.get("tank", {})
        motion = tank.get("motion", {})
        self.size = np.array(tank.get("size", [0.24, 0.16, 0.20]), dtype=float)
        self.frequency = float(motion.get("frequency", math.nan))
        self.amplitude = float(motion.get("amplitude", math.nan))
        direction = np.array(motion.get("direction", [1.0, 0.0, 0.0]), dtype=float)
        self.direction = direction / np.linalg.norm(direction)
        self.ramp_time = motion.get("ramp_time")
        if self.scene and motion.get("kind", "none") != "sinusoidal":
            raise SystemExit(f"seed_figures: the scene {self.scene_path} has no sinusoidal tank motion")
        if not math.isfinite(self.frequency):
            self.frequency = self._frequency_from_outputs()
        if not math.isfinite(self.amplitude):
            self.amplitude = self._amplitude_from_diagnostics()
        if self.ramp_time is None:
            self.ramp_time = 0.0 if self.scene else 1.0 / self.frequency
            if not self.scene:
                self.notes.append(f"ramp_time taken as one period ({self.ramp_time:.6g} s): scene not found")
        self.ramp_time = float(self.ramp_time)
        self.period = 1.0 / self.frequency
        self.omega = 2.0 * math.pi * self.frequency
        self.a_max = self.amplitude * self.omega ** 2
        # phase and start_time are left at 0: the seed's motion (the figures' phases assume them).
        self.motion = SinusoidalMotion(self.amplitude, self.frequency, self.ramp_time)
        self._solid_frames = self._frames("solids.pvd")
        self._fluid_frames = self._frames("fluid.pvd")
        self._cache = {}
        self._check_against_diagnostics()
        if verbose:
            where = self.scene_path if self.scene_path else "fall-backs (no scene file found)"
            print(f"seed_figures: {self.out_dir}: f = {self.frequency:g} Hz, A = {self.amplitude:g} m, "
                  f"ramp {self.ramp_time:g} s, tank {self.size.tolist()} m (from {where}); "
                  f"{len(self._solid_frames)} grain frames, {len(self._fluid_frames)} fluid frames")
            for note in self.notes:
                print("  note:", note)

    # -- scene and motion --
    def _find_scene(self, explicit):
        if explicit:
            path = pathlib.Path(explicit)
            if not path.exists():
                raise SystemExit(f"seed_figures: --scene {path} does not exist")
            return path
        path, named = vtp.run_scene(self.out_dir)
        if path is None and named is not None:
            self.notes.append(f"the log names the scene {named}, which was not found; pass --scene")
        return path

    def _frequency_from_outputs(self):
        path = self.out_dir / "class_centroids.csv"
        if path.exists():
            for row in read_csv_rows(path):
                t, tt = number(row["time_s"]), number(row["t_over_T"])
                if t > 0 and math.isfinite(tt):
                    self.notes.append("frequency from class_centroids.csv (t/T over t)")
                    return tt / t
        self.notes.append("frequency not found: the seed's 1.7 Hz assumed")
        return 1.7

    def _amplitude_from_diagnostics(self):
        path = self.out_dir / "diagnostics.csv"
        if path.exists():
            values = [abs(number(r["tank_displacement_m"])) for r in read_csv_rows(path)]
            if values and max(values) > 0:
                self.notes.append("amplitude = largest |tank_displacement_m| in diagnostics.csv")
                return max(values)
        self.notes.append("amplitude not found: the seed's 0.01 m assumed")
        return 0.01

    def tank_displacement(self, t):
        """Scalar displacement along the motion direction [m] (tank_motion: the engine's formula with its ramp)."""
        return self.motion.displacement(t)

    def tank_velocity(self, t):
        """Scalar velocity along the motion direction [m/s]."""
        return self.motion.velocity(t)

    def tank_acceleration(self, t):
        """Scalar acceleration along the motion direction [m/s^2]."""
        return self.motion.acceleration(t)

    def phase(self, t):
        return np.mod(self.omega * np.asarray(t, dtype=float), 2.0 * math.pi)

    def _check_against_diagnostics(self):
        path = self.out_dir / "diagnostics.csv"
        if not path.exists():
            return
        rows = read_csv_rows(path)
        if not rows or "tank_velocity_m_s" not in rows[0]:
            return
        t = np.array([number(r["time_s"]) for r in rows])
        v = np.array([number(r["tank_velocity_m_s"]) for r in rows])
        model = self.tank_velocity(t) * self.direction[0] if abs(self.direction[0]) > 0 else self.tank_velocity(t)
        error = np.nanmax(np.abs(model - v)) if len(t) else 0.0
        if error > 1e-3 * max(self.amplitude * self.omega, 1e-12):
            self.notes.append(f"the analytic tank velocity differs from diagnostics.csv by up to {error:.3g} m/s: "
                              "check --scene (frequency, amplitude, ramp_time)")

    # -- frames --
    def _frames(self, name):
        path = self.out_dir / name
        return vtp.read_pvd(path) if path.exists() else []

    def solid_times(self):
        return np.array([t for t, _ in self._solid_frames])

    def fluid_times(self):
        return np.array([t for t, _ in self._fluid_frames])

    def solids(self, index, fields=("velocity", "radius", "mass", "size_class")):
        return self._load("solids", self._solid_frames, index, fields)

    def fluid(self, index, fields=("kind", "velocity")):
        return self._load("fluid", self._fluid_frames, index, fields)

    def _load(self, tag, frames, index, fields):
        key = (tag, index)
        cached = self._cache.get(key)
        if cached is not None and all(f in cached for f in fields):
            return cached
        time, path = frames[index]
        data = vtp.read_vtp(path, fields)
        data["time"] = time
        displacement = self.tank_displacement(time) * self.direction
        data["tank_frame_points"] = data["points"] - displacement  # positions in the tank's frame
        data["height"] = data["tank_frame_points"][:, 2]             # above the tank floor
        if len(self._cache) > 64:
            self._cache.clear()
        self._cache[key] = data
        return data

    def nearest_frame(self, times, t_over_T):
        """The index of the frame nearest to t/T, or None when t/T is beyond the run (by more than half a gap)."""
        if len(times) == 0:
            return None
        target = t_over_T * self.period
        index = int(np.argmin(np.abs(times - target)))
        gap = np.median(np.diff(times)) if len(times) > 1 else 0.0
        if target > times[-1] + 0.5 * gap + 1e-9 or target < times[0] - 0.5 * gap - 1e-9:
            return None
        return index

    # -- stages and phases --
    def stages(self, requested, times):
        """[(label, k_first, k_last)] for the stage specs; a period k is t/T in [k-1, k]."""
        last = times[-1] * self.frequency if len(times) else 0.0
        first_after_ramp = int(math.floor(self.ramp_time * self.frequency + 1e-3)) + 1
        stages = []
        if requested:
            for spec in requested:
                parts = spec.split("-")
                k1, k2 = int(parts[0]), int(parts[-1])
                if k1 - 1 >= last - 1e-9:
                    print(f"  stage {spec}: skipped, the run ends at t/T = {last:.3g}")
                    continue
                stages.append((f"period {k1}" if k1 == k2 else f"periods {k1}-{k2}", k1, k2))
        else:
            for k in (10, 85):
                if k <= last + 1e-9:
                    stages.append((f"period {k}", k, k))
            if not stages:
                k2 = max(first_after_ramp, int(math.ceil(last - 1e-9)))
                span = f"period {k2}" if k2 == first_after_ramp else f"periods {first_after_ramp}-{k2}"
                stages.append((f"{span} (all after the ramp)", first_after_ramp, k2))
        return stages

    def phase_frames(self, times, k1, k2, tolerance_deg):
        """For each of the four PHASES, the frame indices in periods k1..k2 within the tolerance, after the ramp."""
        t_over_T = times * self.frequency
        inside = (t_over_T >= k1 - 1 - 1e-9) & (t_over_T <= k2 + 1e-9) & (times >= self.ramp_time - 1e-9)
        phases = self.phase(times)
        result = []
        for target, _ in PHASES:
            difference = np.angle(np.exp(1j * (phases - target)))
            chosen = np.where(inside & (np.abs(difference) <= math.radians(tolerance_deg)))[0]
            result.append((chosen, np.degrees(difference[chosen])))
        return result


# ----------------------------------------------------------------------------------------------------------------
# Helpers


def layer_index(height, thickness, count):
    k = np.floor(height / thickness).astype(int)
    return np.where((k >= 0) & (k < count), k, -1)


def binned_mean(keys, values, count):
    """Sum and count of values per key 0..count-1 (keys < 0 dropped)."""
    valid = keys >= 0
    sums = np.bincount(keys[valid], weights=values[valid], minlength=count)[:count]
    counts = np.bincount(keys[valid], minlength=count)[:count]
    return sums, counts


def save(figure, path):
    figure.savefig(path, dpi=130)
    plt.close(figure)
    return path


# ----------------------------------------------------------------------------------------------------------------
# Figures


def fig03(run, out, args):
    times = run.solid_times()
    if len(times) == 0:
        raise Skip("no solids.pvd")
    targets = args.times if args.times else [t for t in (0, 5, 10, 30, 85, 100)]
    written = []
    fluid_times = run.fluid_times()
    for target in targets:
        index = run.nearest_frame(times, target)
        if index is None:
            print(f"  fig03: t/T = {target:g} is beyond the run (last frame t/T = {times[-1] * run.frequency:.3g})")
            continue
        grains = run.solids(index, ("radius", "size_class"))
        p = grains["tank_frame_points"]
        order = np.argsort(-p[:, 1])  # the viewer looks along +y from y < 0: far grains first
        figure, ax = plt.subplots(figsize=(9, 4.2), constrained_layout=True)
        fi = run.nearest_frame(fluid_times, target) if len(fluid_times) else None
        if fi is not None:
            water = run.fluid(fi, ("kind",))
            q = water["tank_frame_points"][water["kind"] == 0]
            ax.scatter(q[:, 0], q[:, 2], s=4, color="#6baed6", alpha=0.35, linewidths=0, zorder=0)
        diameters = 2 * grains["radius"][order]
        colours = [class_colour(k) for k in grains["size_class"][order]]
        ax.add_collection(EllipseCollection(diameters, diameters, np.zeros_like(diameters), units="xy",
                                            offsets=np.column_stack([p[order, 0], p[order, 2]]),
                                            offset_transform=ax.transData, facecolors=colours,
                                            edgecolors="#00000040", linewidths=0.2, zorder=1))
        for k in sorted(set(grains["size_class"].tolist())):
            ax.scatter([], [], color=class_colour(k), label=class_name(k))
        ax.plot([0, 0, run.size[0], run.size[0]], [0.1, 0, 0, 0.1], color="k", lw=1)
        ax.set_xlim(-0.005, run.size[0] + 0.005)
        ax.set_ylim(-0.003, 0.10)
        ax.set_aspect("equal")
        ax.set_xlabel("x in the tank frame [m]")
        ax.set_ylabel("height above the floor [m]")
        actual = grains["time"] * run.frequency
        ax.set_title(f"side view (from y < 0, near grains in front), t/T = {actual:.2f}"
                     + (" + water (kind 0) in blue" if fi is not None else ""))
        ax.legend(loc="upper right", fontsize=8, ncol=3)
        label = f"{target:g}".replace(".", "p")
        written.append(save(figure, out / f"fig03_snapshot_tT{label}.png"))
    if not written:
        raise Skip("no requested time lies within the run")
    return written


def segregation_index(volumes, start_centroids, centroids):
    """How far the gap between the largest and the smallest class's centroid heights has gone from its start
    towards that of a bed of the same height fully sorted in layers (smallest class at the bottom, largest on top):
    0 at the start, 1 fully sorted. Classes in size order; `volumes` their total grain volumes (any common unit).
    The bed height is taken as twice the volume-weighted mean centroid (uniform packing)."""
    total = sum(volumes)
    mean_height = sum(v * z for v, z in zip(volumes, centroids)) / total
    full_gap = 2.0 * mean_height * (0.5 * volumes[0] + sum(volumes[1:-1]) + 0.5 * volumes[-1]) / total
    start_gap = start_centroids[-1] - start_centroids[0]
    gap = centroids[-1] - centroids[0]
    return (gap - start_gap) / (full_gap - start_gap) if full_gap != start_gap else float("nan")


def fig06(run, out, args):
    path = run.out_dir / "class_centroids.csv"
    rows = []
    if path.exists():
        data = read_csv_rows(path)
        classes = sorted(int(m.group(1)) for key in data[0] for m in [re.match(r"class_(\d+)_centroid_m", key)] if m)
        for row in data:
            rows.append([number(row["t_over_T"]) if row["t_over_T"] else number(row["time_s"]) * run.frequency]
                        + [number(row[f"class_{k}_centroid_m"]) for k in classes])
        source = "class_centroids.csv"
    else:
        times = run.solid_times()
        if len(times) == 0:
            raise Skip("neither class_centroids.csv nor solids.pvd")
        classes = None
        for index in range(len(times)):
            grains = run.solids(index, ("radius", "size_class"))
            volume = grains["radius"] ** 3
            if classes is None:
                classes = sorted(set(grains["size_class"].tolist()))
            rows.append([times[index] * run.frequency] + [
                float(np.sum(volume[grains["size_class"] == k] * grains["height"][grains["size_class"] == k])
                      / np.sum(volume[grains["size_class"] == k])) for k in classes])
        source = "the grain frames (volume-weighted mean centre height)"
    header = ["t_over_T"] + [f"class_{k}_centroid_m" for k in classes]
    # S is measured from the bed at t = 0, which a series starting later (a folder resumed into by an older riffle)
    # does not hold: then no index rather than one against the bed at the resume.
    starts_at_zero = bool(rows) and rows[0][0] <= 0.01
    if rows and not starts_at_zero:
        print(f"fig06: the centroids start at t/T = {rows[0][0]:g}, not 0: no segregation index drawn")
    if len(run.solid_times()) > 0 and len(classes) >= 2 and starts_at_zero:
        grains = run.solids(0, ("radius", "size_class"))
        volumes = [float(np.sum(grains["radius"][grains["size_class"] == k] ** 3)) for k in classes]
        for row in rows:
            row.append(segregation_index(volumes, rows[0][1:1 + len(classes)], row[1:1 + len(classes)]))
        header.append("segregation_index")
    write_csv(out / "fig06_centroids.csv", header, rows)
    table = np.array(rows)
    figure, ax = plt.subplots(figsize=(7, 4.2), constrained_layout=True)
    for j, k in enumerate(classes):
        ax.plot(table[:, 0], 1e3 * table[:, j + 1], color=class_colour(k), label=class_name(k))
    ax.set_xlabel("t/T")
    ax.set_ylabel("concentration centroid above the floor [mm]")
    ax.set_title(f"Fig. 6 shape: centroid per size class (from {source})", fontsize=9)
    ax.legend()
    ax.grid(alpha=0.3)
    return [out / "fig06_centroids.csv", save(figure, out / "fig06_centroids.png")]


def class_profiles_figure(profiles, chosen, count, thickness, xlabel, title, xlim=None):
    """One panel per size class: a profile per chosen stage against the height of the `count` sub-layers of
    `thickness` [m]; profiles[(target, k)] = (actual t/T, values per sub-layer). Figs. 7-8 and 11."""
    classes = sorted({k for _, k in profiles})
    figure, axes = plt.subplots(1, len(classes), figsize=(4 * len(classes), 4.2), sharey=True,
                                constrained_layout=True, squeeze=False)
    mids = 1e3 * (np.arange(count) + 0.5) * thickness
    for ax, k in zip(axes[0], classes):
        for j, (target, _) in enumerate(chosen):
            actual, values = profiles[(target, k)]
            ax.plot(values, mids, marker="o", color=f"C{j}", label=f"t/T = {actual:.3g}")
        ax.set_title(class_name(k))
        ax.set_xlabel(xlabel)
        if xlim is not None:
            ax.set_xlim(*xlim)
        ax.set_yticks(1e3 * np.arange(count + 1) * thickness)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    axes[0][0].set_ylabel("height above the floor [mm] (15 mm sub-layers)")
    figure.suptitle(title, fontsize=9)
    return figure


def fig11(run, out, args):
    times = run.solid_times()
    if len(times) == 0:
        raise Skip("no solids.pvd")
    thickness, count = 0.015, 4
    volume_layer = run.size[0] * run.size[1] * thickness
    chosen = []
    for target in args.conc_times:
        index = run.nearest_frame(times, target)
        if index is None:
            print(f"  fig11: t/T = {target:g} skipped: beyond the run (last frame t/T = "
                  f"{times[-1] * run.frequency:.3g})")
        else:
            chosen.append((target, index))
    if all(target == 0 for target, _ in chosen) and len(times) > 1:
        print(f"  fig11: none of the seed's times lies within the run; the last frame is used instead")
        chosen.append((times[-1] * run.frequency, len(times) - 1))
    rows = []
    profiles = {}
    for target, index in chosen:
        grains = run.solids(index, ("radius", "size_class"))
        keys = layer_index(grains["height"], thickness, count)
        volume = 4.0 / 3.0 * math.pi * grains["radius"] ** 3
        actual = grains["time"] * run.frequency
        for k in sorted(set(grains["size_class"].tolist())):
            mask = grains["size_class"] == k
            sums, numbers = binned_mean(keys[mask], volume[mask], count)
            profiles[(target, k)] = (actual, sums / volume_layer)
            for layer in range(count):
                rows.append([target, actual, k, layer, layer * thickness, (layer + 1) * thickness,
                             int(numbers[layer]), float(sums[layer]), float(sums[layer] / volume_layer)])
    write_csv(out / "fig11_concentration.csv",
              ["target_t_over_T", "frame_t_over_T", "size_class", "sublayer", "z_low_m", "z_high_m", "grains",
               "grain_volume_m3", "volume_concentration"], rows)
    figure = class_profiles_figure(profiles, chosen, count, thickness, "volume concentration [-]",
                                   "Fig. 11 shape: volume concentration (grain assigned to the sub-layer of its "
                                   "centre; sub-layer volume = tank area x 15 mm)")
    return [out / "fig11_concentration.csv", save(figure, out / "fig11_concentration.png")]


def fig12(run, out, args):
    path = run.out_dir / "bed_profile.csv"
    if not path.exists():
        raise Skip("no bed_profile.csv (set output.bed_profile_interval)")
    rows = read_csv_rows(path)
    times = sorted({number(r["time_s"]) for r in rows})
    with_contacts = sorted({number(r["time_s"]) for r in rows if r["mean_dimensionless_overlap"] != ""})
    series = np.array(times)
    chosen = []
    for target in args.profile_times:
        index = run.nearest_frame(series, target)
        if index is None:
            print(f"  fig12: t/T = {target:g} skipped: beyond the run (last profile t/T = "
                  f"{series[-1] * run.frequency:.3g})")
        else:
            chosen.append(series[index])
    if not chosen:
        if with_contacts:
            chosen = sorted({with_contacts[0], with_contacts[-1]})
            print("  fig12: none of the seed's times lies within the run; the first and last profiles with "
                  "contacts are used")
        else:
            raise Skip("bed_profile.csv has no contacts yet")
    figure, axes = plt.subplots(1, 2, figsize=(9, 4.8), sharey=True, constrained_layout=True)
    out_rows = []
    for j, t in enumerate(chosen):
        selected = [r for r in rows if number(r["time_s"]) == t and int(r["grains"]) > 0]
        z = np.array([0.5 * (number(r["z_low_m"]) + number(r["z_high_m"])) for r in selected]) / 0.005
        Z = np.array([number(r["coordination_number"]) for r in selected])
        delta = np.array([number(r["mean_dimensionless_overlap"]) for r in selected])
        label = f"t/T = {t * run.frequency:.3g}"
        axes[0].plot(Z, z, marker="o", color=f"C{j}", label=label)
        axes[1].plot(delta, z, marker="o", color=f"C{j}", label=label)
        out_rows += [[t, t * run.frequency, r["layer"], number(r["z_low_m"]), number(r["z_high_m"]), r["grains"],
                      r["contacts"], number(r["coordination_number"]), number(r["mean_dimensionless_overlap"])]
                     for r in selected]
    write_csv(out / "fig12_coordination_overlap.csv",
              ["time_s", "t_over_T", "layer", "z_low_m", "z_high_m", "grains", "contacts", "coordination_number",
               "mean_dimensionless_overlap"], out_rows)
    axes[0].set_xlabel("coordination number Z = 2 Nc / Np")
    axes[1].set_xlabel("mean dimensionless overlap δ*")
    axes[1].ticklabel_format(axis="x", style="sci", scilimits=(-2, 2))
    axes[0].set_ylabel("z / d_s1 (layer mid-height, d_s1 = 5 mm)")
    for ax in axes:
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    figure.suptitle("Fig. 12 shape (from bed_profile.csv)", fontsize=9)
    return [out / "fig12_coordination_overlap.csv", save(figure, out / "fig12_coordination_overlap.png")]


def phase_profiles(run, times, stages, load, select, values, tolerance, count):
    """Per stage and phase, per group: per-layer sums of each named per-particle value, and counts.

    load(index) -> frame dict; select(frame) -> [(group, mask)]; values(frame) -> {name: per-particle array}.
    Returns {(stage label, phase index): (frame indices, phase errors, {group: ({name: sums}, counts)})}."""
    results = {}
    for label, k1, k2 in stages:
        for p, (indices, errors) in enumerate(run.phase_frames(times, k1, k2, tolerance)):
            accumulated = {}
            for index in indices:
                frame = load(index)
                per_particle = values(frame)
                keys_all = layer_index(frame["height"], run.layer, count)
                for group, mask in select(frame):
                    sums, numbers = accumulated.get(group, ({name: 0 for name in per_particle}, 0))
                    for name, value in per_particle.items():
                        part, counted = binned_mean(keys_all[mask], value[mask], count)
                        sums[name] = sums[name] + part
                    accumulated[group] = (sums, numbers + counted)
            results[(label, p)] = (indices, errors, accumulated)
    return results


def x_velocities(run):
    """values() for phase_profiles: lab x-velocity and x-velocity relative to the tank at the frame's time."""
    def values(frame):
        vx = frame["velocity"][:, 0]
        return {"lab": vx, "relative": vx - float(run.tank_velocity(frame["time"])) * run.direction[0]}
    return values


def velocity_figure(run, out, args, name, title, times, load, select, count, group_label, group_colour):
    stages = run.stages(args.stages, times)
    if not stages:
        raise Skip("no stage lies within the run")
    results = phase_profiles(run, times, stages, load, select, x_velocities(run), args.phase_tolerance, count)
    rows = []
    figure, axes = plt.subplots(len(stages), 4, figsize=(15, 3.8 * len(stages)), sharey=True, squeeze=False,
                                constrained_layout=True)
    key = 0 if args.frame == "lab" else 1
    for s, (label, k1, k2) in enumerate(stages):
        for p, (target, phase_label) in enumerate(PHASES):
            indices, errors, accumulated = results[(label, p)]
            ax = axes[s][p]
            for group in sorted(accumulated):
                sums, numbers = accumulated[group]
                with np.errstate(invalid="ignore", divide="ignore"):
                    lab = np.where(numbers > 0, sums["lab"] / np.maximum(numbers, 1), np.nan)
                    rel = np.where(numbers > 0, sums["relative"] / np.maximum(numbers, 1), np.nan)
                for layer in range(count):
                    if numbers[layer]:
                        rows.append([label, k1, k2, p, target, SEED_PHI[p], len(indices),
                                     float(np.mean(np.abs(errors))) if len(errors) else math.nan, group, layer,
                                     layer * run.layer, (layer + 1) * run.layer, int(numbers[layer]),
                                     float(lab[layer]), float(rel[layer])])
                z = (np.arange(count) + 0.5) * run.layer / 0.005
                ax.plot((lab, rel)[key], z, marker=".", color=group_colour(group), label=group_label(group))
            ax.axvline(0, color="grey", lw=0.6)
            err = f", |Δphase| ≤ {np.max(np.abs(errors)):.0f}°" if len(errors) else ""
            ax.set_title(f"{phase_label}\n{label}, {len(indices)} frames{err}", fontsize=8)
            ax.grid(alpha=0.3)
            if s == len(stages) - 1:
                ax.set_xlabel("mean x-velocity " + ("(lab) [m/s]" if key == 0 else "relative to the tank [m/s]"))
            if p == 0:
                ax.set_ylabel(f"z / d_s1 ({1e3 * run.layer:g} mm sub-layers, d_s1 = 5 mm)")
            if accumulated:
                ax.legend(fontsize=7)
            else:
                ax.text(0.5, 0.5, "no frame at this phase", transform=ax.transAxes, ha="center")
    figure.suptitle(title.replace("; ", ";\n", 1), fontsize=9)
    write_csv(out / f"{name}.csv",
              ["stage", "period_first", "period_last", "phase_index", "tank_phase_rad", "seed_phi", "frames",
               "mean_abs_phase_error_deg", "group", "sublayer", "z_low_m", "z_high_m", "samples", "mean_vx_lab_m_s",
               "mean_vx_relative_to_tank_m_s"], rows)
    missing = sum(1 for v in results.values() if len(v[0]) == 0)
    if missing:
        print(f"  {name}: {missing} stage-phase panels have no frame within {args.phase_tolerance:g}° "
              "(write frames more often: output.vtk_interval = T/8 hits the four phases exactly)")
    return [out / f"{name}.csv", save(figure, out / f"{name}.png")]


def fig14(run, out, args):
    times = run.solid_times()
    if len(times) == 0:
        raise Skip("no solids.pvd")
    count = int(math.ceil(0.08 / run.layer))  # 16 sub-layers of 5 mm: the bed stays below 8 cm

    def select(frame):
        return [(int(k), frame["size_class"] == k) for k in sorted(set(frame["size_class"].tolist()))]

    return velocity_figure(run, out, args, "fig14_velocity_phases",
                           "Fig. 14 shape: mean grain x-velocity per size class per 5 mm sub-layer (grain in the "
                           "sub-layer of its centre), averaged over the frames at each phase of the stage; "
                           + ("lab frame" if args.frame == "lab" else "relative to the tank (v - v_tank(t), "
                              "analytic with the ramp)"),
                           times, lambda i: run.solids(i, ("velocity", "size_class")), select, count, class_name,
                           class_colour)


def fig15(run, out, args):
    times = run.fluid_times()
    if len(times) == 0:
        raise Skip("no fluid.pvd")
    # The seed's 5 mm sub-layers, or l0 when coarser: thinner layers alias the particle lattice (at l0 = 10 mm
    # every other 5 mm layer would hold the particles of a lattice plane and its neighbour almost none).
    spacing = float(run.scene.get("fluid", {}).get("spacing", 0.005))
    thickness = args.fluid_layer if args.fluid_layer else max(0.005, spacing)
    saved, run.layer = run.layer, thickness
    count = int(math.ceil(0.12 / run.layer))

    def select(frame):
        return [("fluid", frame["kind"] == 0)]

    try:
        return _fig15(run, out, args, times, count, select)
    finally:
        run.layer = saved


def _fig15(run, out, args, times, count, select):
    return velocity_figure(run, out, args, "fig15_fluid_velocity",
                           "Fig. 15 shape: horizontally averaged x-velocity of the MPS fluid particles (kind 0) "
                           f"per {1e3 * run.layer:g} mm sub-layer, averaged over the frames at each phase; "
                           + ("lab frame" if args.frame == "lab" else "relative to the tank"),
                           times, lambda i: run.fluid(i, ("kind", "velocity")), select, count, lambda g: "fluid",
                           lambda g: "C0")


def granular_temperature(run, frame, count):
    """Per grain (1/3)|u - u_ave(layer)|^2, u_ave the mean velocity of all grains in its 5 mm sub-layer
    (seed Eq. 31), and the layer index of each grain."""
    keys = layer_index(frame["height"], run.layer, count)
    keys = np.where(keys < 0, count, keys)  # grains outside: one extra bin
    numbers = np.bincount(keys, minlength=count + 1)
    mean = np.stack([np.bincount(keys, weights=frame["velocity"][:, c], minlength=count + 1) for c in range(3)], 1)
    mean /= np.maximum(numbers, 1)[:, None]
    fluctuation = frame["velocity"] - mean[keys]
    return np.sum(fluctuation ** 2, axis=1) / 3.0, keys


def fig20(run, out, args):
    times = run.solid_times()
    if len(times) == 0:
        raise Skip("no solids.pvd")
    count = int(math.ceil(0.08 / run.layer))
    rows = []
    classes = None
    series = {}
    for index in range(len(times)):
        frame = run.solids(index, ("velocity", "size_class"))
        tg, _ = granular_temperature(run, frame, count)
        if classes is None:
            classes = sorted(set(frame["size_class"].tolist()))
        t = frame["time"]
        values = [float(np.mean(tg))] + [float(np.mean(tg[frame["size_class"] == k])) for k in classes]
        rows.append([t, t * run.frequency, float(run.phase(t))] + values)
    header = ["time_s", "t_over_T", "tank_phase_rad", "Tg_all_m2_s2"] + [f"Tg_class_{k}_m2_s2" for k in classes]
    write_csv(out / "fig20_granular_temperature.csv", header, rows)
    table = np.array(rows)

    # (b) profiles (all classes, as the seed) at the acceleration (tank phase pi/2) and maximum-velocity
    # (tank phase pi) phases, averaged over the frames of each stage at that phase
    stages = run.stages(args.stages, times)
    profile_rows = []
    profiles = {}
    for label, k1, k2 in stages:
        matched = run.phase_frames(times, k1, k2, args.phase_tolerance)
        for p in (1, 2):
            indices, _ = matched[p]
            sums = np.zeros(count)
            numbers = np.zeros(count)
            for index in indices:
                frame = run.solids(index, ("velocity", "size_class"))
                tg, keys = granular_temperature(run, frame, count)
                s, n = binned_mean(np.where(keys < count, keys, -1), tg, count)
                sums += s
                numbers += n
            with np.errstate(invalid="ignore", divide="ignore"):
                profile = np.where(numbers > 0, sums / np.maximum(numbers, 1), np.nan)
            profiles[(label, p)] = (profile, len(indices))
            for layer in range(count):
                if numbers[layer]:
                    profile_rows.append([label, k1, k2, p, PHASES[p][0], SEED_PHI[p], len(indices), layer,
                                         layer * run.layer, (layer + 1) * run.layer, int(numbers[layer]),
                                         float(profile[layer])])
    write_csv(out / "fig20_granular_temperature_profiles.csv",
              ["stage", "period_first", "period_last", "phase_index", "tank_phase_rad", "seed_phi", "frames",
               "sublayer", "z_low_m", "z_high_m", "samples", "Tg_m2_s2"], profile_rows)

    figure, axes = plt.subplots(1, 3, figsize=(15, 4.2), constrained_layout=True,
                                gridspec_kw={"width_ratios": [2, 1, 1]})
    ax = axes[0]
    ax.plot(table[:, 1], table[:, 3], color="C0", lw=1.6, label="all grains")
    for j, k in enumerate(classes):
        ax.plot(table[:, 1], table[:, 4 + j], color=class_colour(k), lw=0.9, label=class_name(k))
    ax.set_yscale("log")
    ax.set_xlabel("t/T")
    ax.set_ylabel("granular temperature [m²/s²]")
    ax.set_title("(a) bed-averaged, fluctuation about the sub-layer mean velocity (seed Eq. 31)", fontsize=8)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    z = (np.arange(count) + 0.5) * run.layer / 0.005
    for ax, p in zip(axes[1:], (1, 2)):
        for j, (label, _, _) in enumerate(stages):
            profile, used = profiles[(label, p)]
            ax.plot(profile, z, marker=".", color=f"C{j}", label=f"{label} ({used} frames)")
        ax.set_title("(b) " + PHASES[p][1], fontsize=8)
        ax.set_xlabel("granular temperature [m²/s²]")
        ax.ticklabel_format(axis="x", style="sci", scilimits=(-2, 2))
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    axes[1].set_ylabel("z / d_s1")
    figure.suptitle("Fig. 20 shape: granular temperature (sampled at the VTK frames only)", fontsize=9)
    return [out / "fig20_granular_temperature.csv", out / "fig20_granular_temperature_profiles.csv",
            save(figure, out / "fig20_granular_temperature.png")]


FORCES = ["pressure_force", "drag_force", "contact_force", "added_mass_force", "history_force", "gravity", "total"]
# Applied by the grains' kicks, not part of `force` (solid_force_sum): docs/COUPLING.md, "Added mass and history
# force". Frames written before these forces existed lack them (zero then), as do runs with both switched off (zero
# fields).
KICK_FORCES = ("added_mass_force", "history_force")


def field_or_zero(frame, name):
    """frame[name], or zeros shaped like the frame's points when the frames do not have the field."""
    return frame[name] if name in frame else np.zeros_like(frame["points"])


def solids_with_kick_forces(run, index, fields):
    """The frame's `fields` and, where the frame has them, KICK_FORCES."""
    try:
        return run.solids(index, tuple(fields) + KICK_FORCES)
    except vtp.VtpError:
        return run.solids(index, fields)


def fig17_19(run, out, args):
    times = run.solid_times()
    if len(times) == 0:
        raise Skip("no solids.pvd")
    fields = ("velocity", "mass", "radius", "size_class", "force", "contact_force", "drag_force", "pressure_force")
    water = float(run.scene.get("fluid", {}).get("density", 1000.0))
    buoyancy = {}
    rows = []
    series = {}
    for index in range(len(times)):
        frame = solids_with_kick_forces(run, index, fields)
        t = frame["time"]
        for k in sorted(set(frame["size_class"].tolist())):
            mask = frame["size_class"] == k
            m = frame["mass"][mask]
            buoyancy[k] = water / float(np.mean(m / (4.0 / 3.0 * math.pi * frame["radius"][mask] ** 3)))
            per_mass = {name: field_or_zero(frame, name)[mask] / m[:, None]
                        for name in ("pressure_force", "drag_force", "contact_force") + KICK_FORCES}
            per_mass["gravity"] = np.tile([0.0, 0.0, -G], (int(mask.sum()), 1))
            per_mass["total"] = (frame["force"][mask] / m[:, None] + per_mass["gravity"]
                                 + sum(per_mass[name] for name in KICK_FORCES))
            row = [t, t * run.frequency, float(run.phase(t)), k, int(mask.sum()), float(np.mean(m)),
                   float(np.mean(frame["velocity"][mask, 0])), float(np.mean(frame["velocity"][mask, 2])),
                   float(run.tank_velocity(t)), float(run.tank_acceleration(t))]
            for name in FORCES:
                mean = np.mean(per_mass[name], axis=0)  # mean acceleration from this force [m/s^2]
                row += [float(mean[0] * np.mean(m)), float(mean[2] * np.mean(m)),
                        float(mean[0] / run.a_max), float(mean[2] / G)]
                series.setdefault((k, name), []).append((t * run.frequency, mean[0] / run.a_max, mean[2] / G))
            rows.append(row)
    header = ["time_s", "t_over_T", "tank_phase_rad", "size_class", "grains", "mean_mass_kg", "mean_vx_m_s",
              "mean_vz_m_s", "tank_velocity_m_s", "tank_acceleration_m_s2"]
    for name in FORCES:
        header += [f"{name}_x_N", f"{name}_z_N", f"{name}_x_over_m_amax", f"{name}_z_over_m_g"]
    write_csv(out / "fig17_19_force_balance.csv", header, rows)

    classes = sorted({k for k, _ in series})
    window = args.window if args.window else (None, None)
    figure, axes = plt.subplots(2, len(classes), figsize=(5 * len(classes), 7), sharex=True, squeeze=False,
                                constrained_layout=True)
    styles = {"pressure_force": ("C0", "pressure gradient"), "drag_force": ("C2", "drag"),
              "contact_force": ("C3", "contact"), "added_mass_force": ("C4", "added mass"),
              "history_force": ("C5", "history"), "gravity": ("C7", "gravity"), "total": ("k", "total (m a)")}
    for j, k in enumerate(classes):
        for name in FORCES:
            data = np.array(series[(k, name)])
            keep = np.ones(len(data), bool)
            if window[0] is not None:
                keep = (data[:, 0] >= window[0]) & (data[:, 0] <= window[1])
            colour, label = styles[name]
            if name != "gravity":
                axes[0][j].plot(data[keep, 0], data[keep, 1], color=colour, lw=1, label=label)
            axes[1][j].plot(data[keep, 0], data[keep, 2], color=colour, lw=1, label=label)
        tt = np.linspace(data[keep, 0].min(), data[keep, 0].max(), 400)
        axes[0][j].plot(tt, run.tank_acceleration(tt / run.frequency) / run.a_max, color="C1", ls="--", lw=0.8,
                        label="tank acceleration / a_max")
        axes[1][j].axhline(buoyancy[k], color="C0", ls="--", lw=0.8, label=f"ρ_w/ρ_s = {buoyancy[k]:.3f}")
        axes[0][j].set_title(f"{class_name(k)}: x, force / (m a_max)", fontsize=9)
        axes[1][j].set_title(f"{class_name(k)}: z, force / (m g)", fontsize=9)
        axes[1][j].set_xlabel("t/T")
        for ax in axes[:, j]:
            ax.grid(alpha=0.3)
            ax.axhline(0, color="grey", lw=0.5)
        axes[0][j].legend(fontsize=7)
        axes[1][j].legend(fontsize=7)
    figure.suptitle("Figs. 17-19 shape: mean force per grain of each class (class-averaged, per unit of the "
                    "grain's own m a_max or m g), at the VTK frames", fontsize=9)
    return [out / "fig17_19_force_balance.csv", save(figure, out / "fig17_19_force_balance.png")]


Z_FORCES = ["pressure_force", "drag_force", "contact_force", "total"]


def fig19(run, out, args):
    """Vertical profiles of the z forces per class per 5 mm sub-layer at the four phases (seed Fig. 19: periods
    10-12, forces over m g, stacked: pressure gradient, + drag, + contact = total fluid + contact; the total
    including gravity is m a / m g + 1 - 1)."""
    times = run.solid_times()
    if len(times) == 0:
        raise Skip("no solids.pvd")
    stages = run.stages(args.stages if args.stages else ["10-12"], times)
    if not stages:
        stages = run.stages(None, times)
    count = int(math.ceil(0.08 / run.layer))
    fields = ("mass", "size_class", "force", "contact_force", "drag_force", "pressure_force")

    def select(frame):
        return [(int(k), frame["size_class"] == k) for k in sorted(set(frame["size_class"].tolist()))]

    def values(frame):
        weight = frame["mass"] * G
        per_weight = {name: frame[name][:, 2] / weight for name in ("pressure_force", "drag_force", "contact_force")}
        # force is contact + drag + pressure (solid_force_sum); gravity, added mass and history are added by the
        # integrator's kicks
        per_weight["total"] = (frame["force"][:, 2] + sum(field_or_zero(frame, name)[:, 2] for name in KICK_FORCES)) \
            / weight
        return per_weight

    results = phase_profiles(run, times, stages, lambda i: solids_with_kick_forces(run, i, fields), select, values,
                             args.phase_tolerance, count)
    rows = []
    classes = sorted({k for _, _, accumulated in results.values() for k in accumulated})
    profiles = {}  # (stage, phase, class) -> ({force: sums per layer}, counts per layer)
    for label, k1, k2 in stages:
        for p in range(len(PHASES)):
            indices, errors, accumulated = results[(label, p)]
            for k in sorted(accumulated):
                sums, numbers = profiles[(label, p, k)] = accumulated[k]
                for layer in range(count):
                    if numbers[layer]:
                        rows.append([label, k1, k2, p, PHASES[p][0], SEED_PHI[p], len(indices),
                                     float(np.mean(np.abs(errors))) if len(errors) else math.nan, k, layer,
                                     layer * run.layer, (layer + 1) * run.layer, int(numbers[layer])]
                                    + [float(sums[name][layer] / numbers[layer]) for name in Z_FORCES])
    if not rows:
        raise Skip("no frame at any phase of the stages (write frames more often: vtk_interval = T/8)")
    write_csv(out / "fig19_z_force_profiles.csv",
              ["stage", "period_first", "period_last", "phase_index", "tank_phase_rad", "seed_phi", "frames",
               "mean_abs_phase_error_deg", "size_class", "sublayer", "z_low_m", "z_high_m", "samples"]
              + [f"{name}_z_over_m_g" for name in Z_FORCES], rows)
    water = float(run.scene.get("fluid", {}).get("density", 1000.0))
    density = float(run.scene.get("materials", {}).get("grain", {}).get("density", 1318.0))
    label = stages[0][0]
    figure, axes = plt.subplots(len(classes), 4, figsize=(15, 3.6 * len(classes)), sharey=True, squeeze=False,
                                constrained_layout=True)
    z = (np.arange(count) + 0.5) * run.layer / 0.005
    for j, k in enumerate(classes):
        for p, (_, phase_label) in enumerate(PHASES):
            ax = axes[j][p]
            if (label, p, k) in profiles:
                sums, numbers = profiles[(label, p, k)]
                with np.errstate(invalid="ignore", divide="ignore"):
                    mean = {n: np.where(numbers > 0, sums[n] / np.maximum(numbers, 1), np.nan) for n in Z_FORCES}
                stacked = mean["pressure_force"]
                ax.plot(stacked, z, color="C0", marker=".", label="pressure gradient")
                stacked = stacked + mean["drag_force"]
                ax.plot(stacked, z, color="C2", marker=".", label="+ drag")
                stacked = stacked + mean["contact_force"]
                ax.plot(stacked, z, color="C3", marker=".", label="+ contact")
                ax.plot(mean["total"], z, color="k", lw=0.8, ls=":", label="force / m g (the sum, as written)")
            ax.axvline(water / density, color="C0", ls="--", lw=0.8, label=f"ρ_w/ρ_s = {water / density:.3f}")
            ax.axvline(1.0, color="grey", lw=0.6, label="balances gravity")
            ax.set_title(f"{class_name(k)}, {phase_label}", fontsize=8)
            ax.grid(alpha=0.3)
            if j == len(classes) - 1:
                ax.set_xlabel("z force / (m g), cumulative")
            if p == 0:
                ax.set_ylabel("z / d_s1 (5 mm sub-layers)")
            if j == 0 and p == 0:
                ax.legend(fontsize=6)
    figure.suptitle(f"Fig. 19 shape: z forces per class per sub-layer at the four phases, {label} (grain in the "
                    "sub-layer of its centre; stacked: pressure gradient, + drag, + contact)", fontsize=9)
    return [out / "fig19_z_force_profiles.csv", save(figure, out / "fig19_z_force_profiles.png")]


DRIFT_COLUMNS = 10   # x bins across the tank
DRIFT_LAYER = 0.015  # [m] z bins, the seed's Fig. 11 sub-layers


def drift(run, out, args):
    """Lagrangian mean drift of the grains over windows of periods: each grain followed by id from the frame
    nearest t/T = k1 to the one nearest k2, its displacement in the tank frame binned by where it started (ten
    columns across the tank, 15 mm layers). Not a seed figure: it shows the bed's circulation (convection rolls)
    that carries grains up and down besides the sorting."""
    times = run.solid_times()
    if len(times) == 0:
        raise Skip("no solids.pvd")
    windows = []
    for spec in args.drift_windows:
        first, last = (float(v) for v in spec.split("-"))
        a, b = run.nearest_frame(times, first), run.nearest_frame(times, last)
        if a is None or b is None or a == b:
            print(f"  drift: window {spec} is not within the run's frames; skipped")
            continue
        windows.append((spec, a, b))
    if not windows:
        raise Skip("no drift window lies within the run")
    length = float(run.size[0])
    count_z = 4
    rows = []
    figure, axes = plt.subplots(len(windows), 1, figsize=(9, 2.6 * len(windows)), squeeze=False,
                                constrained_layout=True)
    for w, (spec, a, b) in enumerate(windows):
        start, end = run.solids(a, ("id", "size_class")), run.solids(b, ("id",))
        order_a, order_b = np.argsort(start["id"]), np.argsort(end["id"])
        if not np.array_equal(start["id"][order_a], end["id"][order_b]):
            raise Skip(f"the grains of t/T = {times[a] * run.frequency:.3g} and {times[b] * run.frequency:.3g} "
                       "differ (ids)")
        p0 = start["tank_frame_points"][order_a]
        displacement = end["tank_frame_points"][order_b] - p0
        classes = start["size_class"][order_a]
        column = np.clip((p0[:, 0] / length * DRIFT_COLUMNS).astype(int), 0, DRIFT_COLUMNS - 1)
        layer = np.clip((p0[:, 2] / DRIFT_LAYER).astype(int), 0, count_z - 1)
        periods = (times[b] - times[a]) * run.frequency
        ax = axes[w][0]
        centres_x, centres_z, mean_dx, mean_dz = [], [], [], []
        for group, mask_group in [("all", np.ones(len(classes), bool))] + \
                [(str(k), classes == k) for k in sorted(set(classes.tolist()))]:
            for i in range(DRIFT_COLUMNS):
                for j in range(count_z):
                    mask = mask_group & (column == i) & (layer == j)
                    if not mask.any():
                        continue
                    dx, dz = displacement[mask, 0].mean(), displacement[mask, 2].mean()
                    rows.append([spec, times[a] * run.frequency, times[b] * run.frequency, group, i,
                                 i * length / DRIFT_COLUMNS, (i + 1) * length / DRIFT_COLUMNS, j, j * DRIFT_LAYER,
                                 (j + 1) * DRIFT_LAYER, int(mask.sum()), float(dx), float(dz)])
                    if group == "all" and mask.sum() >= 5:
                        centres_x.append(p0[mask, 0].mean())
                        centres_z.append(p0[mask, 2].mean())
                        mean_dx.append(dx)
                        mean_dz.append(dz)
        ax.quiver(centres_x, centres_z, mean_dx, mean_dz, angles="xy", scale_units="xy", scale=1, width=0.003)
        ax.plot([0, 0, length, length], [0.07, 0, 0, 0.07], color="k", lw=1)
        ax.set_xlim(-0.005, length + 0.005)
        ax.set_ylim(-0.005, 0.07)
        ax.set_aspect("equal")
        ax.set_title(f"mean displacement of the grains starting in each cell, t/T = {times[a] * run.frequency:.3g}"
                     f" to {times[b] * run.frequency:.3g} ({periods:.3g} periods; arrows to scale)", fontsize=8)
        ax.set_ylabel("z [m]")
    axes[-1][0].set_xlabel("x in the tank frame [m]")
    write_csv(out / "drift.csv", ["window", "t_over_T_start", "t_over_T_end", "group", "column", "x_low_m",
                                  "x_high_m", "layer", "z_low_m", "z_high_m", "grains", "mean_dx_m", "mean_dz_m"],
              rows)
    return [out / "drift.csv", save(figure, out / "drift.png")]


# ----------------------------------------------------------------------------------------------------------------
# Figures 4, 7-8, 9, 10, 13, 16: views of the bed (seed_views.py makes the images) and the fluid's strain

PIXEL = 0.0005          # [m] image pixel of the views: a small grain is 10 pixels across
SUBLAYER = 0.015        # [m] the seed's sub-layers of Figs. 7-9 and 11: one large diameter
SUBLAYERS = 4           # 0-15, 15-30, 30-45, 45-60 mm above the floor
HIGHLIGHT_SPEED = 0.2   # [m/s] Fig. 13's green vectors
ARROW_SCALE = 15.0      # [(m/s)/m] Fig. 13's arrows: 0.2 m/s is 13 mm long, about one cell at l0 = 10 mm
NO_GRAIN = (0.78, 0.87, 0.95)  # the image's colour where no grain is seen (water)


def frames_at(run, times, targets, name):
    """[(target t/T, frame index)] of the frames nearest the targets; targets beyond the run are named and
    dropped; Skip when none is left."""
    chosen = []
    for target in targets:
        index = run.nearest_frame(times, target)
        if index is None:
            print(f"  {name}: t/T = {target:g} skipped: beyond the run (last frame t/T = "
                  f"{times[-1] * run.frequency:.3g})")
        else:
            chosen.append((target, index))
    if not chosen:
        raise Skip("none of the requested times lies within the run")
    return chosen


def best_phase_frames(run, times, k, tolerance):
    """For period k (t/T in [k-1, k]), per phase of PHASES the index of the frame nearest that phase within the
    tolerance, or None: the seed's Figs. 10 and 13 show single frames of one period."""
    best = []
    for indices, errors in run.phase_frames(times, k, k, tolerance):
        if not len(indices):
            best.append(None)
            continue
        # Phase 0 is met at both ends of the period and T/10 frames straddle pi/2 and 3pi/2 symmetrically: among
        # frames equally near (to 1 degree) the earliest, so that the panels run in time order.
        order = np.lexsort((indices, np.round(np.abs(errors))))
        best.append(int(indices[order[0]]))
    return best


def single_period_stages(run, args, times, name):
    """The stages of args.stages (default the seed's 10 and 85) as the one period each shows: a range k1-k2 is
    shown by its last period."""
    stages = run.stages(args.stages, times)
    if not stages:
        raise Skip("no stage lies within the run")
    shown = []
    for label, _, k2 in stages:
        frames = best_phase_frames(run, times, k2, args.phase_tolerance)
        if all(f is None for f in frames):
            print(f"  {name}: period {k2}: no frame within {args.phase_tolerance:g}° of any phase")
            continue
        shown.append((f"period {k2}", k2, frames))
    if not shown:
        raise Skip("no frame at any phase of the stages")
    return shown


def class_image(index, labels, depth=None, shade_from=None, shade_over=0.03):
    """RGB image of a raster: each pixel the colour of its grain's class, NO_GRAIN where none. With depth and
    shade_from, pixels darken with depth beyond shade_from (to half over shade_over metres), so that the cut discs
    of a cross-section stand out from the grains behind them."""
    palette = {int(k): matplotlib.colors.to_rgb(class_colour(k)) for k in set(np.asarray(labels).tolist())}
    image = np.empty(index.shape + (3,))
    image[:] = NO_GRAIN
    seen = index >= 0
    shown = np.asarray(labels)[index[seen]]
    image[seen] = np.array([palette[int(k)] for k in shown]) if len(shown) else image[seen]
    if depth is not None and shade_from is not None:
        shade = 1.0 - 0.5 * np.clip((depth - shade_from) / shade_over, 0.0, 1.0)
        image[seen] *= shade[seen][:, None]
    # outlines: a pixel whose grain differs from its left or lower neighbour's, darkened, so that touching grains
    # of one class stay distinguishable
    edge = np.zeros(index.shape, dtype=bool)
    edge[:, 1:] |= index[:, 1:] != index[:, :-1]
    edge[1:, :] |= index[1:, :] != index[:-1, :]
    image[edge & seen] *= 0.6
    return image


def class_legend(ax, classes):
    for k in classes:
        ax.scatter([], [], color=class_colour(k), label=class_name(k))


def vx_in_frame(run, frame, args):
    """The x-velocity of the frame's particles in the frame of reference of --frame."""
    vx = frame["velocity"][:, 0]
    if args.frame == "lab":
        return vx
    return vx - float(run.tank_velocity(frame["time"])) * run.direction[0]


def fluid_spacing(run):
    """l0: the scene's fluid.spacing, else the median nearest-neighbour distance of the first fluid frame (the
    initial lattice)."""
    spacing = run.scene.get("fluid", {}).get("spacing")
    if spacing:
        return float(spacing)
    first = run.fluid(0, ("kind",))
    spacing = seed_views.infer_spacing(first["points"][first["kind"] == 0])
    print(f"  l0 = {spacing:.4g} m inferred from the first fluid frame (no fluid.spacing in the scene)")
    return spacing


def fig04(run, out, args):
    """Top views of the bed at --times (seed Fig. 4): the grains seen from above (orthographic, a depth buffer of
    PIXEL pixels: each pixel shows the highest grain surface over it), coloured by class. The CSV gives each class's
    share of the tank's plan area as seen, over the whole tank and within one large diameter (15 mm) of the front
    and back walls, where the seed notes riffle's large grains missing."""
    times = run.solid_times()
    if len(times) == 0:
        raise Skip("no solids.pvd")
    chosen = frames_at(run, times, args.times if args.times else [0, 5, 10, 30, 85, 100], "fig04")
    length, width = float(run.size[0]), float(run.size[1])
    rows, images = [], []
    near = None
    for target, index in chosen:
        grains = run.solids(index, ("radius", "size_class"))
        seen, _ = seed_views.raster(grains["tank_frame_points"], grains["radius"], "top", PIXEL,
                                    ((0.0, length), (0.0, width)))
        if near is None:  # image rows are y: those within 15 mm of y = 0 or y = width
            y = (np.arange(seen.shape[0]) + 0.5) * PIXEL
            near = (y < SUBLAYER) | (y > width - SUBLAYER)
        labels = grains["size_class"]
        classes = sorted(set(labels.tolist()))
        whole = seed_views.band_fractions(labels, seen, seen.shape[0], 1, classes)[0]
        walls = seed_views.band_fractions(labels, seen[near], int(near.sum()), 1, classes)[0]
        inner = seed_views.band_fractions(labels, seen[~near], int((~near).sum()), 1, classes)[0]
        actual = grains["time"] * run.frequency
        visible = np.unique(seen[seen >= 0])  # the grains with at least one pixel in view
        for j, k in enumerate(classes):
            rows.append([target, actual, k, int(np.count_nonzero(labels[visible] == k)), float(whole[j]),
                         float(walls[j]), float(inner[j])])
        images.append((actual, class_image(seen, labels), classes, whole))
    write_csv(out / "fig04_top_views.csv",
              ["target_t_over_T", "frame_t_over_T", "size_class", "grains_seen", "area_fraction",
               "area_fraction_near_front_back_walls", "area_fraction_interior"], rows)
    columns = min(3, len(images))
    lines = int(math.ceil(len(images) / columns))
    figure, axes = plt.subplots(lines, columns, figsize=(5.2 * columns, 3.9 * lines), squeeze=False,
                                constrained_layout=True)
    for ax in axes.ravel()[len(images):]:
        ax.axis("off")
    for ax, (actual, image, classes, whole) in zip(axes.ravel(), images):
        ax.imshow(image, origin="lower", extent=(0, 1e3 * length, 0, 1e3 * width), interpolation="nearest")
        shares = ", ".join(f"{100 * f:.0f}%" for f in whole)
        ax.set_title(f"t/T = {actual:.2f}: seen area {shares} (classes {classes})", fontsize=8)
        ax.set_xlabel("x in the tank frame [mm]")
        ax.set_ylabel("y [mm] (front wall at 0)")
    class_legend(axes[0][0], classes)
    axes[0][0].legend(fontsize=7, loc="upper right")
    figure.suptitle("Fig. 4 shape: top views (from above, orthographic: each point shows the highest grain)",
                    fontsize=9)
    return [out / "fig04_top_views.csv", save(figure, out / "fig04_top_views.png")]


def front_view(run, grains, height=SUBLAYERS * SUBLAYER, clip=None):
    """raster() of the grains seen through the front wall (from y < 0), image x in [0, L] and z in [0, height]."""
    return seed_views.raster(grains["tank_frame_points"], grains["radius"], "front", PIXEL,
                             ((0.0, float(run.size[0])), (0.0, height)), clip=clip)


def fig07_08(run, out, args):
    """Occupancy rate per class in the seed's four 15 mm sub-layers above the floor at --conc-times (seed Figs. 7-8).
    The seed measures it from side-view images, by colour: here the occupancy rate of class c in sub-layer k is the
    fraction of the sub-layer's strip of the front view (through the wall at y = 0, orthographic, the nearest grain
    surface in each PIXEL pixel, seen through the water at any depth) that shows a grain of class c. The classes'
    rates add up to the strip's covered fraction (below 1 where the bed surface lies inside it); the CSV also gives
    each class's share of the covered pixels."""
    times = run.solid_times()
    if len(times) == 0:
        raise Skip("no solids.pvd")
    chosen = frames_at(run, times, args.conc_times, "fig07_08")
    rows_per_band = int(round(SUBLAYER / PIXEL))
    rows, profiles = [], {}
    for target, index in chosen:
        grains = run.solids(index, ("radius", "size_class"))
        seen, _ = front_view(run, grains)
        labels = grains["size_class"]
        classes = sorted(set(labels.tolist()))
        rates = seed_views.band_fractions(labels, seen, rows_per_band, SUBLAYERS, classes)
        covered = rates.sum(axis=1)
        actual = grains["time"] * run.frequency
        for j, k in enumerate(classes):
            profiles[(target, k)] = (actual, rates[:, j])
            for layer in range(SUBLAYERS):
                share = rates[layer, j] / covered[layer] if covered[layer] > 0 else math.nan
                rows.append([target, actual, k, layer, layer * SUBLAYER, (layer + 1) * SUBLAYER,
                             float(rates[layer, j]), float(share)])
    write_csv(out / "fig07_08_occupancy.csv",
              ["target_t_over_T", "frame_t_over_T", "size_class", "sublayer", "z_low_m", "z_high_m",
               "occupancy_rate", "share_of_covered_area"], rows)
    figure = class_profiles_figure(profiles, chosen, SUBLAYERS, SUBLAYER, "occupancy rate (side view) [-]",
                                   "Figs. 7-8 shape: occupancy rate = fraction of each 15 mm strip of the front view "
                                   "(through the wall at y = 0) showing a grain of the class", xlim=(0, 1))
    return [out / "fig07_08_occupancy.csv", save(figure, out / "fig07_08_occupancy.png")]


def fig09(run, out, args):
    """Mean horizontal grain velocity per 15 mm sub-layer at the four phases of the 5th, 10th, 30th and 85th
    periods (--stages overrides), as the seed reads it by PIV from side-view frames (seed Fig. 9): the x-velocity
    of the grain seen in each pixel of the front view, averaged over the pixels of the sub-layer's strip that show
    a grain whose visible surface lies within --view-depth (one large diameter) of the front wall, all classes
    together (PIV's area weighting). Beside it the mean over all grains whose centre lies in the sub-layer."""
    times = run.solid_times()
    if len(times) == 0:
        raise Skip("no solids.pvd")
    stages = run.stages(args.stages if args.stages else ["5", "10", "30", "85"], times)
    if not stages:
        raise Skip("no stage lies within the run")
    rows_per_band = int(round(SUBLAYER / PIXEL))
    rows, profiles = [], {}
    for label, k1, k2 in stages:
        for p, (indices, errors) in enumerate(run.phase_frames(times, k1, k2, args.phase_tolerance)):
            seen_sum, seen_count = np.zeros(SUBLAYERS), np.zeros(SUBLAYERS)
            all_sum, all_count = np.zeros(SUBLAYERS), np.zeros(SUBLAYERS)
            for index in indices:
                grains = run.solids(index, ("velocity", "radius", "size_class"))
                vx = vx_in_frame(run, grains, args)
                seen, depth = front_view(run, grains)
                seen = np.where(depth <= args.view_depth, seen, -1)  # deeper: too dim to track (the seed's PIV)
                pixel_vx = np.where(seen >= 0, vx[np.maximum(seen, 0)], 0.0)
                for layer in range(SUBLAYERS):
                    band = slice(layer * rows_per_band, (layer + 1) * rows_per_band)
                    seen_sum[layer] += pixel_vx[band].sum()
                    seen_count[layer] += np.count_nonzero(seen[band] >= 0)
                sums, counts = binned_mean(layer_index(grains["height"], SUBLAYER, SUBLAYERS), vx, SUBLAYERS)
                all_sum += sums
                all_count += counts
            with np.errstate(invalid="ignore", divide="ignore"):
                seen_mean = np.where(seen_count > 0, seen_sum / np.maximum(seen_count, 1), np.nan)
                all_mean = np.where(all_count > 0, all_sum / np.maximum(all_count, 1), np.nan)
            profiles[(label, p)] = (len(indices), seen_mean, all_mean)
            for layer in range(SUBLAYERS):
                rows.append([label, k1, k2, p, PHASES[p][0], SEED_PHI[p], len(indices),
                             float(np.mean(np.abs(errors))) if len(errors) else math.nan, layer, layer * SUBLAYER,
                             (layer + 1) * SUBLAYER, int(seen_count[layer]), float(seen_mean[layer]),
                             int(all_count[layer]), float(all_mean[layer])])
    if all(used == 0 for used, _, _ in profiles.values()):
        raise Skip("no frame at any phase of the stages")
    write_csv(out / "fig09_side_view_velocity.csv",
              ["stage", "period_first", "period_last", "phase_index", "tank_phase_rad", "seed_phi", "frames",
               "mean_abs_phase_error_deg", "sublayer", "z_low_m", "z_high_m", "seen_pixels",
               f"mean_vx_seen_{args.frame}_m_s", "grains", f"mean_vx_all_grains_{args.frame}_m_s"], rows)
    figure, axes = plt.subplots(1, len(stages), figsize=(4.2 * len(stages), 4.4), sharey=True, squeeze=False,
                                constrained_layout=True)
    mids = 1e3 * (np.arange(SUBLAYERS) + 0.5) * SUBLAYER
    for ax, (label, _, _) in zip(axes[0], stages):
        for p in range(len(PHASES)):
            used, seen_mean, all_mean = profiles[(label, p)]
            if used:
                ax.plot(seen_mean, mids, marker="o", color=f"C{p}", label=f"φ = {SEED_PHI[p]} (front view)")
                ax.plot(all_mean, mids, ls="--", lw=0.9, color=f"C{p}", label=f"φ = {SEED_PHI[p]} (all grains)")
        ax.axvline(0, color="grey", lw=0.6)
        ax.set_title(label, fontsize=9)
        ax.set_xlabel(f"mean x-velocity ({'lab' if args.frame == 'lab' else 'relative to the tank'}) [m/s]")
        ax.set_yticks(1e3 * np.arange(SUBLAYERS + 1) * SUBLAYER)
        ax.grid(alpha=0.3)
    axes[0][0].set_ylabel("height above the floor [mm] (15 mm sub-layers)")
    axes[0][0].legend(fontsize=6)
    figure.suptitle(f"Fig. 9 shape: mean x-velocity of the grains seen through the front wall (within "
                    f"{1e3 * args.view_depth:g} mm of it, area-weighted as PIV; solid) and of all grains (dashed); "
                    "seed phases φ", fontsize=9)
    return [out / "fig09_side_view_velocity.csv", save(figure, out / "fig09_side_view_velocity.png")]


def slab(points, centre, half):
    return np.abs(points[:, 1] - centre) < half


def draw_discs(ax, x, z, diameters, colours, **style):
    ax.add_collection(EllipseCollection(diameters, diameters, np.zeros_like(diameters), units="xy",
                                        offsets=np.column_stack([x, z]), offset_transform=ax.transData,
                                        facecolors=colours, **style))


def tank_axes(ax, run, top):
    ax.set_xlim(0, float(run.size[0]))
    ax.set_ylim(0, top)
    ax.set_aspect("equal")
    ax.tick_params(labelsize=6)


def fig10(run, out, args):
    """The fluid's velocity in the x-z slab of --slab thickness at mid-depth (y = W/2), in single frames at the four
    phases of one period per stage (seed Fig. 10: developing and fully developed stage), beside the grains whose
    centre lies in the same slab. The seed's captions say x-component, its text (Sec. 5.1) the vertical component:
    both are drawn (rows), each fluid particle (kind 0) a disc of diameter l0 coloured by its velocity (--frame)."""
    times = run.fluid_times()
    if len(times) == 0 or len(run.solid_times()) == 0:
        raise Skip("no fluid.pvd or no solids.pvd")
    shown = single_period_stages(run, args, times, "fig10")
    spacing = fluid_spacing(run)
    centre, half, top = 0.5 * float(run.size[1]), 0.5 * args.slab, 0.12
    solid_times = run.solid_times()
    rows, panels = [], []
    for label, k, frames in shown:
        for p, index in enumerate(frames):
            if index is None:
                panels.append((label, p, None, None, None))
                continue
            water = run.fluid(index, ("kind", "velocity"))
            keep = (water["kind"] == 0) & slab(water["tank_frame_points"], centre, half)
            q = water["tank_frame_points"][keep]
            vx, vz = vx_in_frame(run, water, args)[keep], water["velocity"][keep, 2]
            grains = run.solids(int(np.argmin(np.abs(solid_times - water["time"]))), ("radius", "size_class"))
            inside = slab(grains["tank_frame_points"], centre, half)
            g = grains["tank_frame_points"][inside]
            actual = water["time"] * run.frequency
            rows += [[label, k, p, SEED_PHI[p], actual, "fluid", -1, x, z, spacing / 2, u, w]
                     for x, z, u, w in zip(q[:, 0], q[:, 2], vx, vz)]
            rows += [[label, k, p, SEED_PHI[p], actual, "grain", int(c), x, z, r, math.nan, math.nan]
                     for x, z, c, r in zip(g[:, 0], g[:, 2], grains["size_class"][inside], grains["radius"][inside])]
            panels.append((label, p, actual, (q, vx, vz), (g, grains["radius"][inside], grains["size_class"][inside])))
    write_csv(out / "fig10_fluid_slab.csv",
              ["stage", "period", "phase_index", "seed_phi", "frame_t_over_T", "particle", "size_class", "x_m", "z_m",
               "radius_m", f"vx_{args.frame}_m_s", "vz_m_s"], rows)
    speeds = [np.abs(np.concatenate([f[1], f[2]])) for _, _, _, f, _ in panels if f is not None and len(f[1])]
    scale = float(np.percentile(np.concatenate(speeds), 99)) if speeds else 1.0
    figure, axes = plt.subplots(3 * len(shown), 4, figsize=(16, 2.5 * 3 * len(shown)), squeeze=False,
                                constrained_layout=True)
    cmap = plt.get_cmap("RdBu_r")
    norm = matplotlib.colors.Normalize(-scale, scale)
    for n, (label, p, actual, fluid, grains) in enumerate(panels):
        s = n // 4
        for r in range(3):
            ax = axes[3 * s + r][p]
            tank_axes(ax, run, top)
            if actual is None:
                ax.text(0.5, 0.5, "no frame at this phase", transform=ax.transAxes, ha="center")
                continue
            if r < 2:
                q, values = fluid[0], fluid[1 + r]
                draw_discs(ax, q[:, 0], q[:, 2], np.full(len(q), spacing), cmap(norm(values)), linewidths=0)
                ax.set_title(f"{label}, φ = {SEED_PHI[p]} (t/T = {actual:.2f}): fluid "
                             + ("v_x" if r == 0 else "v_z"), fontsize=7)
            else:
                g, radius, classes = grains
                draw_discs(ax, g[:, 0], g[:, 2], 2 * radius, [class_colour(c) for c in classes],
                           edgecolors="#00000040", linewidths=0.2)
                ax.set_title(f"grains with centre in the slab (t/T = {actual:.2f})", fontsize=7)
    for s in range(len(shown)):
        for r in range(2):
            figure.colorbar(matplotlib.cm.ScalarMappable(norm, cmap), ax=list(axes[3 * s + r]), shrink=0.8,
                            label=("v_x " + ("(lab)" if args.frame == "lab" else "rel. tank") if r == 0 else "v_z")
                            + " [m/s]")
    figure.suptitle(f"Fig. 10 shape: fluid velocity in the slab |y - {1e3 * centre:g} mm| < {1e3 * half:g} mm "
                    f"(x, z in the tank frame, discs of l0 = {1e3 * spacing:g} mm) and the grains of the slab",
                    fontsize=9)
    return [out / "fig10_fluid_slab.csv", save(figure, out / "fig10_fluid_slab.png")]


def grid_average(x, z, u, w, cell, length, top):
    """Mean (u, w) of the samples in each cell x cell box of [0, length] x [0, top]: (centres x, z, u, w, count)
    of the cells holding samples."""
    nx, nz = int(math.ceil(length / cell)), int(math.ceil(top / cell))
    i, k = np.floor(x / cell).astype(int), np.floor(z / cell).astype(int)
    keep = (i >= 0) & (i < nx) & (k >= 0) & (k < nz)
    key = i[keep] * nz + k[keep]
    count = np.bincount(key, minlength=nx * nz)
    mean_u = np.bincount(key, weights=u[keep], minlength=nx * nz) / np.maximum(count, 1)
    mean_w = np.bincount(key, weights=w[keep], minlength=nx * nz) / np.maximum(count, 1)
    filled = np.where(count > 0)[0]
    return ((filled // nz + 0.5) * cell, (filled % nz + 0.5) * cell, mean_u[filled], mean_w[filled], count[filled])


def fig13(run, out, args):
    """Cross-sections of the bed at mid-depth y0 = W/2 in single frames at the four phases of one period per stage
    (seed Fig. 13). Upper row: the bed beyond the plane seen from the front (grains with y < y0 removed, those cut
    by the plane show their cut disc in full colour, grains behind darkened with depth). Lower row: the discs
    where the plane cuts the grains (smaller than their diameter, as the seed's) and the fluid velocity (kind 0
    particles within l0 of the plane, averaged on a fixed l0 grid, --frame), vectors of in-plane speed
    >= 0.2 m/s in green. The seed draws the fluid's (MPS) velocity there, not the grains'."""
    times = run.solid_times()
    fluid_times = run.fluid_times()
    if len(times) == 0:
        raise Skip("no solids.pvd")
    shown = single_period_stages(run, args, times, "fig13")
    spacing = fluid_spacing(run) if len(fluid_times) else math.nan
    length, centre, top = float(run.size[0]), 0.5 * float(run.size[1]), 0.09
    rows, panels = [], []
    for label, k, frames in shown:
        for p, index in enumerate(frames):
            if index is None:
                panels.append((label, p, None))
                continue
            grains = run.solids(index, ("radius", "size_class"))
            labels = grains["size_class"]
            seen, depth = front_view(run, grains, height=top, clip=centre)
            image = class_image(seen, labels, depth, shade_from=centre + 1e-9)
            offset = grains["tank_frame_points"][:, 1] - centre
            cut = np.abs(offset) < grains["radius"]
            cut_radius = np.sqrt(grains["radius"][cut] ** 2 - offset[cut] ** 2)
            vectors = None
            actual = grains["time"] * run.frequency
            if len(fluid_times):
                water = run.fluid(int(np.argmin(np.abs(fluid_times - grains["time"]))), ("kind", "velocity"))
                near = (water["kind"] == 0) & slab(water["tank_frame_points"], centre, spacing)
                q = water["tank_frame_points"][near]
                vectors = grid_average(q[:, 0], q[:, 2], vx_in_frame(run, water, args)[near],
                                       water["velocity"][near, 2], spacing, length, top)
                speed = np.hypot(vectors[2], vectors[3])
                rows += [[label, k, p, SEED_PHI[p], actual, x, z, int(n), u, w, s, int(s >= HIGHLIGHT_SPEED)]
                         for x, z, u, w, n, s in zip(*vectors, speed)]
            panels.append((label, p, (actual, image, grains["tank_frame_points"][cut], cut_radius, labels[cut],
                                      vectors)))
    write_csv(out / "fig13_cross_section.csv",
              ["stage", "period", "phase_index", "seed_phi", "frame_t_over_T", "cell_x_m", "cell_z_m", "samples",
               f"mean_vx_{args.frame}_m_s", "mean_vz_m_s", "in_plane_speed_m_s", "highlighted"], rows)
    figure, axes = plt.subplots(2 * len(shown), 4, figsize=(16, 2.1 * 2 * len(shown)), squeeze=False,
                                constrained_layout=True)
    for n, (label, p, panel) in enumerate(panels):
        upper, lower = axes[2 * (n // 4)][p], axes[2 * (n // 4) + 1][p]
        for ax in (upper, lower):
            tank_axes(ax, run, top)
        if panel is None:
            upper.text(0.5, 0.5, "no frame at this phase", transform=upper.transAxes, ha="center")
            continue
        actual, image, centres, cut_radius, classes, vectors = panel
        upper.imshow(image, origin="lower", extent=(0, length, 0, top), interpolation="nearest")
        upper.set_title(f"{label}, φ = {SEED_PHI[p]} (t/T = {actual:.2f}): bed beyond y = {1e3 * centre:g} mm",
                        fontsize=7)
        draw_discs(lower, centres[:, 0], centres[:, 2], 2 * cut_radius, [class_colour(c) for c in classes],
                   alpha=0.6, linewidths=0)
        title = "cut discs"
        if vectors is not None and len(vectors[0]):
            fast = np.hypot(vectors[2], vectors[3]) >= HIGHLIGHT_SPEED
            for mask, colour in ((~fast, "k"), (fast, "#1a9641")):
                lower.quiver(vectors[0][mask], vectors[1][mask], vectors[2][mask], vectors[3][mask], color=colour,
                             angles="xy", scale_units="xy", scale=ARROW_SCALE, width=0.002)
            title += f" + fluid velocity ({int(fast.sum())} of {len(fast)} cells ≥ {HIGHLIGHT_SPEED:g} m/s)"
        lower.set_title(title, fontsize=7)
    figure.suptitle("Fig. 13 shape: cross-section at mid-depth (upper) and the plane with the fluid velocity "
                    f"({'lab' if args.frame == 'lab' else 'relative to the tank'}; arrows: 0.2 m/s = "
                 f"{1e3 * HIGHLIGHT_SPEED / ARROW_SCALE:.0f} mm) (lower)",
                    fontsize=9)
    return [out / "fig13_cross_section.csv", save(figure, out / "fig13_cross_section.png")]


def strain_profiles(run, index, spacing, thickness, count):
    """Per horizontal layer of one fluid frame: sums of |S|^2 over the particles with a valid gradient, their
    number, the sum of the positive Q and its number, and the sum of all Q (seed Fig. 16)."""
    try:
        water = run.fluid(index, ("kind", "velocity", "free_surface"))
    except vtp.VtpError:  # frames without the flag: every particle counts as interior
        water = run.fluid(index, ("kind", "velocity"))
    fluid = water["kind"] == 0
    G, valid = seed_views.velocity_gradient(water["points"][fluid], water["velocity"][fluid], 2.1 * spacing)
    s2, q = seed_views.strain_and_q(G)
    keys = np.where(valid, layer_index(water["height"][fluid], thickness, count), -1)
    surface = water["free_surface"][fluid] != 0 if "free_surface" in water else np.zeros(len(keys), dtype=bool)
    sums = []
    for chosen in (keys, np.where(surface, -1, keys)):  # all fluid particles; those not flagged free-surface
        s2_sum, n = binned_mean(chosen, s2, count)
        q_pos_sum, n_pos = binned_mean(np.where(q > 0, chosen, -1), q, count)
        q_sum, _ = binned_mean(chosen, q, count)
        sums += [s2_sum, n, q_pos_sum, n_pos, q_sum]
    return np.stack(sums)


def layer_means(sums):
    """(mean |S|^2, mean positive Q, mean Q) per layer from strain_profiles()'s five sums."""
    s2_sum, n, q_pos_sum, n_pos, q_sum = sums
    with np.errstate(invalid="ignore", divide="ignore"):
        return (np.where(n > 0, s2_sum / np.maximum(n, 1), np.nan),
                np.where(n_pos > 0, q_pos_sum / np.maximum(n_pos, 1), np.nan),
                np.where(n > 0, q_sum / np.maximum(n, 1), np.nan))


def fig16(run, out, args):
    """Vertical profiles of the mean squared rate of strain |S|^2 = S:S and of the Q-criterion
    Q = (|Omega|^2 - |S|^2) / 2 of the fluid at the seed's phase φ = π (tank phase π/2, accelerating), per stage
    (seed Fig. 16). The velocity gradient at each fluid particle (kind 0) is the kernel-weighted least-squares
    gradient over the fluid neighbours within r_e = 2.1 l0 (seed_views.velocity_gradient); the profiles average
    over the particles of each sub-layer (5 mm, or l0 when coarser, as Fig. 15) and over the stage's frames at
    that phase; Q over its positive values only, as the seed (the CSV has the mean of all values too). Dashed and
    the CSV's interior_ columns: without the particles flagged free-surface, whose one-sided neighbourhoods make
    the gradient noisier."""
    times = run.fluid_times()
    if len(times) == 0:
        raise Skip("no fluid.pvd")
    stages = run.stages(args.stages, times)
    if not stages:
        raise Skip("no stage lies within the run")
    spacing = fluid_spacing(run)
    thickness = args.fluid_layer if args.fluid_layer else max(0.005, spacing)
    count = int(math.ceil(0.12 / thickness))
    rows, profiles = [], {}
    for label, k1, k2 in stages:
        indices, errors = run.phase_frames(times, k1, k2, args.phase_tolerance)[1]
        if not len(indices):
            print(f"  fig16: {label}: no frame within {args.phase_tolerance:g}° of tank phase π/2 (seed φ = π)")
            continue
        totals = sum(strain_profiles(run, index, spacing, thickness, count) for index in indices)
        means = [layer_means(totals[5 * j:5 * j + 5]) for j in range(2)]  # all; interior
        profiles[label] = (len(indices), means)
        for layer in range(count):
            if totals[1][layer]:
                row = [label, k1, k2, len(indices), float(np.mean(np.abs(errors))), layer, layer * thickness,
                       (layer + 1) * thickness]
                for j, (s2, q_pos, q_all) in enumerate(means):
                    row += [int(totals[5 * j + 1][layer]), float(s2[layer]), int(totals[5 * j + 3][layer]),
                            float(q_pos[layer]), float(q_all[layer])]
                rows.append(row)
    if not profiles:
        raise Skip("no fluid frame at the seed's φ = π in any stage")
    if not rows:
        raise Skip("no fluid particle has a gradient (fewer than three neighbours out of a plane within r_e)")
    columns = ["particles", "mean_S2_1_s2", "particles_Q_positive", "mean_positive_Q_1_s2", "mean_Q_1_s2"]
    write_csv(out / "fig16_strain_q.csv",
              ["stage", "period_first", "period_last", "frames", "mean_abs_phase_error_deg", "sublayer", "z_low_m",
               "z_high_m"] + columns + [f"interior_{c}" for c in columns], rows)
    figure, axes = plt.subplots(1, 2, figsize=(9, 4.8), sharey=True, constrained_layout=True)
    z = (np.arange(count) + 0.5) * thickness / 0.005
    for j, (label, (used, means)) in enumerate(profiles.items()):
        for (s2, q_pos, _), style, which in zip(means, ("-", "--"), ("all", "not free-surface")):
            axes[0].plot(s2, z, ls=style, marker=".", color=f"C{j}", label=f"{label} ({used} frames), {which}")
            axes[1].plot(q_pos, z, ls=style, marker=".", color=f"C{j}", label=f"{label} ({used} frames), {which}")
    axes[0].set_xlabel("mean |S|² [1/s²]")
    axes[1].set_xlabel("mean of the positive Q [1/s²]")
    axes[0].set_ylabel(f"z / d_s1 ({1e3 * thickness:g} mm sub-layers, d_s1 = 5 mm)")
    for ax in axes:
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    figure.suptitle(f"Fig. 16 shape: rate of strain and Q-criterion of the fluid at seed φ = π (tank phase π/2); "
                    f"least-squares gradient over r_e = 2.1 l0 = {2.1e3 * spacing:.3g} mm", fontsize=9)
    return [out / "fig16_strain_q.csv", save(figure, out / "fig16_strain_q.png")]


FIGURES = {"fig03": fig03, "fig04": fig04, "fig06": fig06, "fig07_08": fig07_08, "fig09": fig09, "fig10": fig10,
           "fig11": fig11, "fig12": fig12, "fig13": fig13, "fig14": fig14, "fig15": fig15, "fig16": fig16,
           "fig17_19": fig17_19, "fig19": fig19, "fig20": fig20, "drift": drift}


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("out_dir", type=pathlib.Path, help="a run's output directory")
    parser.add_argument("--figures", nargs="+", choices=ALL_FIGURES, default=ALL_FIGURES, metavar="NAME",
                        help="which figures (default all): " + " ".join(ALL_FIGURES))
    parser.add_argument("--out", type=pathlib.Path, metavar="DIR",
                        help="where to write the figures (default OUT_DIR/figures)")
    parser.add_argument("--scene", type=pathlib.Path,
                        help="the run's scene file (default: the one named in OUT_DIR/riffle.log)")
    parser.add_argument("--times", type=float, nargs="+",
                        help="fig03/fig04 snapshot times in t/T (default 0 5 10 30 85 100, those within the run)")
    parser.add_argument("--conc-times", type=float, nargs="+", default=[0, 5, 10, 30, 85],
                        help="fig11 and fig07_08 times in t/T (default 0 5 10 30 85)")
    parser.add_argument("--profile-times", type=float, nargs="+", default=[10, 85],
                        help="fig12 times in t/T (default 10 85)")
    parser.add_argument("--stages", nargs="+", metavar="K[-K2]",
                        help="fig09/10/13/14/15/16/19/20 stages (fig19 plots the first; fig10/fig13 show the last "
                             "period of each): period k or periods k-k2 (default 10 85 where run, else all periods "
                             "after the ramp; fig19: 10-12; fig09: 5 10 30 85)")
    parser.add_argument("--slab", type=float, default=0.015, metavar="METRES",
                        help="fig10 thickness of the x-z slab at mid-depth (default 0.015, one large diameter)")
    parser.add_argument("--view-depth", type=float, default=0.015, metavar="METRES",
                        help="fig09: pixels of the front view count when the grain seen lies within this distance "
                             "of the front wall (default 0.015, one large diameter)")
    parser.add_argument("--phase-tolerance", type=float, default=20.0,
                        help="largest phase difference [deg] of a frame used for a phase (default 20)")
    parser.add_argument("--frame", choices=["tank", "lab"], default="tank",
                        help="fig14/15 velocities relative to the tank (default) or in the lab frame")
    parser.add_argument("--fluid-layer", type=float, metavar="METRES",
                        help="fig15 sub-layer thickness (default max(5 mm, fluid.spacing))")
    parser.add_argument("--drift-windows", nargs="+", metavar="K1-K2", default=["10-20", "40-50", "70-80", "90-100"],
                        help="drift windows in t/T (default 10-20 40-50 70-80 90-100, those within the run)")
    parser.add_argument("--window", type=float, nargs=2, metavar=("T1", "T2"),
                        help="fig17_19 plot window in t/T (default the whole run; the CSV has every frame)")
    args = parser.parse_args(argv)

    if not args.out_dir.is_dir():
        sys.exit(f"seed_figures: {args.out_dir} is not a directory")
    try:
        run = Run(args.out_dir, args.scene)
    except vtp.VtpError as error:
        sys.exit(f"seed_figures: {error}")
    out = args.out if args.out else args.out_dir / "figures"
    out.mkdir(parents=True, exist_ok=True)
    failed = False
    for name in args.figures:
        try:
            written = FIGURES[name](run, out, args)
            print(f"{name}: " + ", ".join(str(p.name) for p in written))
        except Skip as reason:
            print(f"{name}: skipped: {reason}")
        except vtp.VtpError as error:
            print(f"{name}: failed: {error}")
            failed = True
    print(f"seed_figures: wrote into {out}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())

"""The launcher's dispatch: tools/riffle-tools COMMAND [ARGS...] runs riffle_tools.<module>.main(ARGS).

COMMANDS is the index (tools/README.md repeats it with the shell scripts); a test checks that every tool module is
in it and that each command answers --help.
"""
import importlib
import sys

# (command, module, what it is for), grouped as tools/README.md lists them.
COMMANDS = [
    # run outputs
    ("plot-diagnostics", "plot_diagnostics", "plot a run's diagnostics.csv: energies, grain speed and CFL, tank "
                                             "motion, wall time per step"),
    ("plot-bed", "plot_bed", "plot a run's class centroids against t/T and its coordination and overlap profiles"),
    ("bedload-plots", "bedload_plots", "plot one run's bed-load probes: moving fraction, packing, flux, shear, "
                                       "velocity profiles"),
    # the seed experiment (sloshing tank)
    ("seed-figures", "seed_figures", "the seed sloshing experiment's figures (CSV + PNG) from one run's output"),
    ("seed-checklist", "seed_checklist", "the seed's checkable claims measured on one run's figure tables "
                                         "(Markdown)"),
    ("study", "study", "run, resume and watch a study: variants of a scene on several settled beds "
                       "(run/status/collect)"),
    ("study-collect", "study_collect", "a study's measures of any run (measure) or over several studies' runs "
                                       "(merge)"),
    ("resolution-summary", "resolution_summary", "summary table of a water-spacing study (resolution_study.sh)"),
    ("motion-table", "motion_table", "write riffle's sinusoidal tank motion, start-up ramp included, as a motion "
                                     "table CSV"),
    ("mobilisation-gauges", "bed_mobilisation.gauges", "sloshing tank: per-period wall-gauge range, largest "
                                                       "fluid speed and kinetic energy"),
    ("mobilisation-layers", "bed_mobilisation.layers", "sloshing tank: fluid and grain velocities per depth below "
                                                       "the bed surface, top-layer forces"),
    ("mobilisation-load-budget", "bed_mobilisation.load_budget", "sloshing tank: the whole bed's horizontal "
                                                                 "force budget per frame"),
    ("mobilisation-load-depth", "bed_mobilisation.load_depth", "sloshing tank: cumulative horizontal load over "
                                                               "submerged weight above each depth"),
    ("mobilisation-linear-slosh", "bed_mobilisation.linear_slosh", "sloshing tank: linear long-wave model of the "
                                                                   "wall amplitude and bed load"),
    # sheared beds (bed load)
    ("seed003-plots", "seed003_plots", "the sheared-bed figures (Shields, flux, packing) and summary of a set of "
                                       "runs"),
    ("bedload-sweep", "bedload_sweep", "a Shields-number sweep of the bed-load channel (mean-flow fluid): q*, "
                                       "moving fraction, u_p/u*, the threshold, beside the bed-load laws"),
    ("single-grain", "single_grain", "one grain over a fixed bed (seed 004): its regime at each Galileo number "
                                     "from its path"),
    ("momentum-budget", "momentum_budget", "the water's x momentum budget of a sheared-bed run"),
    ("bed-force-profile", "bed_force_profile", "where a sheared bed takes the water's stress, per height band"),
    # verification and studies of the physics
    ("settling-study", "settling_study", "a lone sphere settling in still liquid against Schiller-Naumann "
                                         "(runs riffle)"),
    ("self-disturbance", "self_disturbance", "a lone grain's own disturbance of the water: the MPS water's, the "
                                             "self-induced model's and the continuum's, from its frames"),
    ("particle-scatter", "particle_scatter", "the MPS water's particle-scale velocity scatter and number-density "
                                             "spread, frame by frame"),
    ("lattice-response", "lattice_response", "the MPS water's response at a grain's kernel on the particle lattice "
                                             "against the continuum the self-induced correction models"),
    ("bed-creep", "bed_creep", "a settled bed with nothing driving it: how fast it creeps at each sub-step "
                               "(runs riffle)"),
    ("bed-tilt", "bed_tilt", "a settled bed tilted in gravity: the slope at which it starts to flow (runs "
                             "riffle)"),
    ("ten-cate", "ten_cate", "ten Cate et al.'s sphere settling onto a box's floor against the measurements "
                             "(runs riffle)"),
    ("hindered-settling", "hindered_settling", "hindered settling of a suspension against Richardson & Zaki "
                                               "(runs riffle)"),
    ("wet-restitution", "wet_restitution", "wet restitution against Stokes number, coupled (runs riffle)"),
    ("ergun-plug", "ergun_plug", "pressure drop across the fixed plug of scenes/ergun_plug.toml against Ergun"),
    ("driven-flow-study", "driven_flow_study", "driven-flow convergence sweeps against analytic profiles "
                                               "(runs riffle)"),
    ("impact-study", "impact_study", "dam-break impact pressures at several spacings and Courant numbers "
                                     "(runs riffle)"),
    ("returning-wave", "returning_wave", "the dam break's returning wave against Lobovsky et al. (runs riffle)"),
    ("plot-fluid-accuracy", "plot_fluid_accuracy", "speed against error of the MPS fluid "
                                                   "(riffle_fluid_accuracy's table)"),
    ("pressure-solver-study", "pressure_solver_study", "one scene's pressure solve under each solver "
                                                       "(in-house PCG, hypre BoomerAMG), interleaved (runs riffle)"),
    ("ppe-preconditioner-study", "ppe_preconditioner_study", "PCG iterations of one dumped pressure system under "
                                                             "other preconditioners"),
    # the docs against the code
    ("scene-keys", "scene_keys", "docs/SCENES.md's key tables written from what riffle's scene reading asks, or "
                                 "checked against it (runs riffle keys)"),
]

# Modules that are libraries of the others, not commands.
LIBRARIES = ("cli", "plotting", "run_outputs", "seed_views", "study_jobs", "tank_motion", "vtp")


def index():
    width = max(len(name) for name, _, _ in COMMANDS)
    lines = ["usage: tools/riffle-tools COMMAND [ARGS...]   (tools/riffle-tools COMMAND --help: its options)", "",
             "riffle's Python tools (tools/README.md also lists the shell scripts):", ""]
    lines += [f"  {name:<{width}}  {text}" for name, _, text in COMMANDS]
    return "\n".join(lines) + "\n"


def main(argv=None):
    argv = sys.argv[1:] if argv is None else list(argv)
    if not argv or argv[0] in ("-h", "--help", "help"):
        sys.stdout.write(index())
        return 0 if argv else 2
    name, rest = argv[0], argv[1:]
    modules = {command: module for command, module, _ in COMMANDS}
    if name not in modules:
        sys.stderr.write(f"riffle-tools: no command {name!r}\n\n" + index())
        return 2
    module = importlib.import_module(f"riffle_tools.{modules[name]}")
    sys.argv[0] = f"riffle-tools {name}"  # argparse's prog in usage and errors
    return module.main(rest)

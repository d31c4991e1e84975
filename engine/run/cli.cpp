#include "engine/run/cli.hpp"

#include <CLI/CLI.hpp>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <new>

#include "engine/output/vtk_output.hpp"
#include "engine/setup/budget.hpp"
#include "engine/scene/scene.hpp"
#include "engine/run/registry.hpp"
#include "engine/run/simulation.hpp"
#include "engine/run/stepper.hpp"
#include "engine/setup/initial_state.hpp"
#include "engine/toml/scene_reader.hpp"
#include "systems/physics/geometry/tank_kinematics.hpp"
#include "systems/physics/mps/particle_packing.hpp"
#include "systems/physics/ranks/rank_comm.hpp"

namespace riffle {

namespace {

const char* kExitCodes =
    "Exit codes:\n"
    "  0    success\n"
    "  1    bad command line\n"
    "  2    invalid scene or checkpoint (each problem is printed as file:line:column: key: message)\n"
    "  3    the run stopped with a diagnosis (NaN, particle left the domain, out of memory during the run, an\n"
    "       internal error); the last good checkpoint is kept\n"
    "  4    output could not be written: the output folder or riffle.log cannot be created, or another run is\n"
    "       writing into the same output folder (OUT/.riffle.lock is held)\n"
    "  130  interrupted by SIGINT (a checkpoint was written first; a step still running 2 s after the signal is\n"
    "       abandoned instead, and the last good checkpoint is named)\n"
    "  143  terminated by SIGTERM (as for SIGINT)\n";

extern "C" void handle_stop_signal(int signal_number) { request_stop(signal_number); }

std::string default_out_dir(const Model& model) { return "out/" + model.name; }

/// `riffle check`'s line on the ParaView frames a run will write: how many, and their size in the scene's format
/// (estimate_frame_bytes), so that a study of many runs knows its disk before it starts.
std::string describe_frames(const SceneBudget& budget, const Model& model) {
  const OutputModel& output = model.output;
  if (!(output.vtk_interval > 0.0)) return "  frames: none (output.vtk_interval = 0)\n";
  const double frames = std::floor((model.end_time + 0.5 * model.dt) / output.vtk_interval) + 1.0;
  const VtkFormat format = vtk_format(output);
  const double shown = model.fluid.enabled ? budget.fluid_particles + budget.wall_particles +
                                                 (format.dummy_particles ? budget.dummy_particles : 0.0)
                                           : 0.0;
  const FrameBytes bytes = estimate_frame_bytes(format, budget.grains, shown);
  const double frame = bytes.grains + bytes.water;
  std::string parts;
  if (bytes.grains > 0.0) parts += "grains " + format_bytes(bytes.grains);
  if (bytes.water > 0.0) parts += std::string(parts.empty() ? "" : ", ") + "water " + format_bytes(bytes.water);
  char text[512];
  std::snprintf(text, sizeof text,
                "  frames: %.0f, every %g s, of about %s each (%s): about %s in all (%s, %s precision%s)\n", frames,
                output.vtk_interval, format_bytes(frame).c_str(), parts.c_str(), format_bytes(frames * frame).c_str(),
                format.appended ? "appended" : "inline base64", format.single_precision ? "single" : "double",
                model.fluid.enabled ? (format.dummy_particles ? ", dummies included" : ", no dummies") : "");
  return text;
}

int report_run(const RunOutcome& outcome) {
  if (!outcome.last_checkpoint.empty() && outcome.exit_code != kExitOk)
    spdlog::info("resume with: riffle resume {}", outcome.last_checkpoint);
  return outcome.exit_code;
}

/// `riffle check`'s answer for a valid scene, from the model and its budget alone: the counts a run would lay out,
/// the DEM sub-step and what sets it, the tank's motion, the water, the budget.
void print_check(const std::string& scene_path, const Model& model) {
  // Counted from the scene's descriptions: a bed or fill is generated only when a run starts, and then has exactly
  // its classes' counts (or the run is refused, naming the table whose random grains jam).
  const SolidsModel& solids = model.solids;
  const long long grains = solids.enabled ? static_cast<long long>(scene_grain_sizes(solids).count) : 0;
  std::printf("%s: valid scene '%s': %lld grains, %zu walls, t_end = %g s, dt = %g s, %lld solid sub-steps\n",
              scene_path.c_str(), model.name.c_str(), grains, tank_walls(model.tank).size(), model.end_time, model.dt,
              static_cast<long long>(model.solid_substeps));
  long long in_blocks = 0;
  for (const SphereBlockSpec& block : solids.blocks) in_blocks += block.count;
  const long long in_beds = static_cast<long long>(scene_sphere_count(solids)) -
                            static_cast<long long>(solids.spheres.size()) - in_blocks;
  if (grains > 0)
    std::printf("  grains: %lld from initial_state, %zu listed, %lld in blocks, %lld in layered beds and fills "
                "(blocks, beds and fills are generated when a run starts)\n",
                solids.initial_grains ? static_cast<long long>(solids.initial_grains->size()) : 0LL,
                solids.spheres.size(), in_blocks, in_beds);
  if (model.contact.enabled && model.contact.stable_solid_dt > 0.0)
    std::printf("  DEM sub-step %.4g s (%lld per step); stable estimate %.4g s, set by %s\n"
                "  restitution at this sub-step, head-on at max_impact_speed = %g m/s: within %.3g of the requested "
                "(tolerance %g; worst: %s)\n",
                model.solid_dt(), static_cast<long long>(model.solid_substeps), model.contact.stable_solid_dt,
                model.contact.stable_solid_dt_reason.c_str(), model.contact.max_impact_speed,
                model.contact.restitution_error, model.contact.restitution_tolerance,
                model.contact.restitution_error_pair.c_str());
  const TankMotionModel& motion = model.tank.motion;
  const Vec3 sweep = tank_motion_sweep(motion);
  if (motion.kind == TankMotionModel::Kind::kTable)
    std::printf("  tank motion: table %s, %zu rows, t in [%g, %g] s, largest |displacement| (%.4g, %.4g, %.4g) m\n",
                motion.table.file.c_str(), motion.table.time.size(), motion.table.time.front(),
                motion.table.time.back(), sweep.x(), sweep.y(), sweep.z());
  else if (motion.kind == TankMotionModel::Kind::kSinusoidal)
    std::printf("  tank motion: sinusoidal, A = %g m, f = %g Hz, ramp %g s, phase %g deg, start %g s\n",
                motion.amplitude, motion.frequency, motion.ramp_time, motion.phase * 180.0 / 3.14159265358979323846,
                motion.start_time);
  const SceneBudget budget = estimate_budget(model);
  if (model.fluid.enabled)
    std::printf("  fluid: %.0f MPS particles, %.0f of them fluid, spacing %g m, r_e = %g spacing\n",
                budget.fluid_particles + budget.wall_particles + budget.dummy_particles, budget.fluid_particles,
                model.fluid.spacing, model.fluid.effective_radius_ratio);
  if (model.fluid.enabled && model.fluid.initial_arrangement == FluidModel::Arrangement::kPacked) {
    const double floor = packed_start_viscosity_floor(model.fluid.spacing, model.gravity.norm());
    std::printf("  fluid: a packed start (off the lattice)%s\n",
                packed_water_may_not_rest(model.fluid.kinematic_viscosity, model.fluid.scatter_viscosity,
                                          model.fluid.spacing, model.gravity.norm())
                    ? (", but nu = " + format_number(model.fluid.kinematic_viscosity) + " m^2/s is below 0.01 l0 sqrt(g l0) = " +
                       format_number(floor) + " m^2/s: packed water at rest may not come to rest; [fluid] "
                       "scatter_viscosity = 2 holds it (docs/FLUID.md)")
                          .c_str()
                    : "");
  }
  if (model.mean_flow.enabled) {
    const MeanFlowModel& flow = model.mean_flow;
    std::printf("  mean-flow fluid: %zu cells of %.4g m from z = %g to %g m (%s top), %s\n", flow.cells,
                flow.cell_size, flow.bottom, flow.top, flow.top_boundary == MeanFlowModel::Top::kLid ? "lid" : "free",
                flow.turbulence == MeanFlowModel::Turbulence::kMixingLength ? "mixing-length turbulence" : "laminar");
    if (flow.shields_number > 0.0)
      std::printf("  drive: Shields number %g of d = %g m, rho_s = %g kg/m^3 (a slope; the body force follows the "
                  "bed surface)\n",
                  flow.shields_number, flow.shields_diameter, flow.shields_density);
    if (flow.profile_forcing.enabled) {
      const MeanFlowModel::ProfileForcing& forcing = flow.profile_forcing;
      std::printf("  drive: pulled towards u = %g m/s ((z - %g m) / %g m)^%.4g at %.4g /s (%g m/s^2 over %g m/s on "
                  "%g of the water; relaxes in %.3g s)\n",
                  forcing.velocity, forcing.base, flow.top - forcing.base, forcing.exponent, forcing.rate(),
                  forcing.strength, std::abs(forcing.velocity), forcing.volume_fraction, 1.0 / forcing.rate());
    }
  }
  std::printf("%s", describe_budget(budget, model).c_str());
  std::printf("%s", describe_frames(budget, model).c_str());
  // Before a job is queued on many ranks: whether `mpirun -np N riffle run` can spread this scene.
  const std::string spread = Simulation::over_ranks_problem(model);
  if (spread.empty())
    std::printf("  over MPI ranks: can be spread (mpirun -np N riffle run)\n");
  else
    std::printf("  over MPI ranks: one rank only: %s\n", spread.c_str());
}

/// `riffle keys`: the union of the keys every scene's reading asks for (engine/toml/scene_reader.hpp, SceneKey),
/// one tab-separated line each: key, kind, its ranges and unit, its defaults (" | " between several), whether a
/// scene sets it. Exits 2 after printing the keys if a scene is invalid (its problems on stderr).
int print_scene_keys(const std::vector<std::string>& scenes, const SceneLimits& limits,
                     const std::vector<std::string>& overrides) {
  SceneKeyCatalogue catalogue;
  int exit_code = kExitOk;
  for (const std::string& scene : scenes) {
    try {
      load_scene_file(scene, limits, overrides, &catalogue);
    } catch (const SceneError& error) {
      for (const std::string& problem : error.problems()) std::fprintf(stderr, "error: %s\n", problem.c_str());
      exit_code = kExitInvalidInput;
    }
  }
  std::printf("key\tkind\trange\tunit\tdefault\tgiven\n");
  for (const auto& [name, key] : catalogue.keys()) {
    std::string ranges, defaults;
    for (const std::string& range : key.ranges) ranges += (ranges.empty() ? "" : " | ") + range;
    for (const std::string& fallback : key.defaults) defaults += (defaults.empty() ? "" : " | ") + fallback;
    std::printf("%s\t%s\t%s\t%s\t%s\t%s\n", name.c_str(), key.kind.c_str(), ranges.c_str(), key.unit.c_str(),
                defaults.c_str(), key.given ? "yes" : "no");
  }
  return exit_code;
}

/// Why `until` cannot end a run that starts at `start` with steps of at most `dt`, or "" if it can: the same
/// checks as run.end_time (finite, positive, at most 1e12 steps), and at least one step after the start.
std::string until_problem(double until, double start, double dt) {
  char text[256];
  if (!std::isfinite(until) || until <= 0.0) {
    std::snprintf(text, sizeof text, "--until: expected a finite time > 0 s, got %g", until);
  } else if (until <= start) {
    std::snprintf(text, sizeof text, "--until %g s is not after the checkpoint's time t = %.17g s", until, start);
  } else if ((until - start) / dt > 1e12) {
    std::snprintf(text, sizeof text, "--until %g s is more than 1e12 steps of dt = %g s away", until, dt);
  } else if (until - start < dt * (1.0 - 1e-9)) {  // the tolerance absorbs the rounding of t = step * dt
    std::snprintf(text, sizeof text,
                  "--until %g s is less than one step (dt = %g s) after the start time t = %.17g s: the run would "
                  "end before its first step",
                  until, dt, start);
  } else {
    return "";
  }
  return text;
}

int run_command(int argc, char** argv);

}  // namespace

/// Every failure ends in a documented exit code with a message, never in std::terminate.
int cli_main(int argc, char** argv) {
  // Under `mpirun -np N` (N > 1) the grains are spread over the ranks (Simulation::split_over_ranks); a build
  // without MPI would run the whole scene N times into one folder, so it refuses. The launchers' environment tells
  // before any MPI call (Open MPI, then MPICH/Hydra and PMIx).
  for (const char* variable : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_SIZE"}) {
    const char* value = std::getenv(variable);
    if (value != nullptr && std::atoi(value) > 1) {
      if (!ranks::mpi_built()) {
        std::fprintf(stderr,
                     "error: this riffle was built without MPI (it was started as one of %s = %s ranks): build it with "
                     "libhypre-dev installed (tools/setup.sh), or run it without mpirun, with --threads for the cores\n",
                     variable, value);
        return kExitUsage;
      }
      try {
        ranks::start_mpi();
      } catch (const std::exception& error) {
        std::fprintf(stderr, "error: %s\n", error.what());
        return kExitUsage;
      }
      break;
    }
  }
  try {
    return run_command(argc, argv);
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "error: out of memory (std::bad_alloc); the scene is too large for this machine\n");
    return kExitUnstable;
  } catch (const std::exception& error) {
    std::fprintf(stderr, "error: internal error: %s\n", error.what());
    return kExitUnstable;
  } catch (...) {
    std::fprintf(stderr, "error: internal error (an unknown exception)\n");
    return kExitUnstable;
  }
}

namespace {

int run_command(int argc, char** argv) {
  CLI::App app{"riffle: sediment moved by water. DEM grains coupled to an MPS free-surface fluid.", "riffle"};
  app.footer(kExitCodes);
  app.require_subcommand(1);
  // Whether this build can spread a run over MPI ranks (and solve with hypre): scripts and tests ask here.
  app.set_version_flag("--version", std::string(RIFFLE_VERSION) +
                                        (ranks::mpi_built() ? " (MPI: grains over ranks, hypre)" : " (no MPI)"));
  std::string log_level = "info";
  // Accepted before and after the subcommand (riffle --log-level debug run ... / riffle run ... --log-level debug).
  auto add_log_level = [&log_level](CLI::App* command) {
    command->add_option("--log-level", log_level, "Log verbosity")
        ->check(CLI::IsMember({"trace", "debug", "info", "warn", "error", "off"}))
        ->capture_default_str();
  };
  add_log_level(&app);
  // [GiB] raises (or lowers) the memory limit scenes are checked against (engine/setup/budget.hpp); beats run.memory_limit.
  double memory_limit_gib = 0.0;
  auto add_memory_limit = [&memory_limit_gib](CLI::App* command) {
    command->add_option("--memory-limit", memory_limit_gib,
                        "Memory limit [GiB] for the scene's estimated budget (default: run.memory_limit, else 3/4 of "
                        "physical memory)")
        ->check(CLI::PositiveNumber);
  };

  std::string scene_path, checkpoint_path, out_dir;
  std::vector<std::string> overrides;  // --set KEY=VALUE, in order (engine/scene/scene_overrides.hpp)
  auto add_overrides = [&overrides](CLI::App* command) {
    command->add_option("--set", overrides,
                        "Override a scene key, KEY=VALUE with VALUE in TOML (a bare word is a string); repeatable, "
                        "e.g. --set contact.friction=0.3 --set solids.layered_beds[0].seed=2. A run stores the changed "
                        "scene in its checkpoints")
        ->allow_extra_args(false);  // one value per --set, every occurrence kept in order
  };
  int threads = 0;
  double until = -1.0;

  CLI::App* run = app.add_subcommand("run", "Validate and run a scene file");
  run->add_option("scene", scene_path, "Scene file (TOML)")->required();
  run->add_option("--out", out_dir, "Output directory (default: out/<run.name>)");
  run->add_option("--threads", threads, "Worker threads (default: all cores)")->check(CLI::PositiveNumber);
  // Checked after the scene or checkpoint is read (until_problem): the bounds depend on its time and dt.
  CLI::Option* run_until = run->add_option("--until", until, "End time [s], overrides run.end_time");
  add_log_level(run);
  add_memory_limit(run);
  add_overrides(run);
  run->footer(kExitCodes);

  CLI::App* check = app.add_subcommand("check", "Validate a scene file without running it");
  check->add_option("scene", scene_path, "Scene file (TOML)")->required();
  add_log_level(check);
  add_memory_limit(check);
  add_overrides(check);
  check->footer(kExitCodes);

  CLI::App* graph = app.add_subcommand(
      "graph", "Print the scene's step graph as Graphviz DOT (the grains' sub-step loop as a cluster) without running it");
  graph->add_option("scene", scene_path, "Scene file (TOML)")->required();
  add_log_level(graph);
  add_memory_limit(graph);
  add_overrides(graph);
  graph->footer(kExitCodes);

  std::vector<std::string> key_scenes;
  CLI::App* keys = app.add_subcommand(
      "keys", "Print every key the scenes' reading asks for, with its kind, range, unit and default, and whether a "
              "scene sets it (tab-separated, one key a line)");
  keys->add_option("scenes", key_scenes, "Scene files (TOML)")->required();
  add_log_level(keys);
  add_memory_limit(keys);
  add_overrides(keys);
  keys->footer(kExitCodes);

  CLI::App* resume = app.add_subcommand("resume", "Continue a run from a checkpoint");
  resume->add_option("checkpoint", checkpoint_path, "Checkpoint file (.ckpt)")->required();
  resume->add_option("--out", out_dir, "Output directory (default: the checkpoint's run directory)");
  resume->add_option("--threads", threads, "Worker threads (default: all cores)")->check(CLI::PositiveNumber);
  CLI::Option* resume_until = resume->add_option("--until", until, "End time [s], overrides run.end_time");
  add_log_level(resume);
  add_memory_limit(resume);
  resume->footer(kExitCodes);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    const int code = app.exit(error);
    return code == 0 ? kExitOk : kExitUsage;
  }
  const bool until_given = (*run && run_until->count() > 0) || (*resume && resume_until->count() > 0);

  auto console = spdlog::stderr_color_mt("riffle");
  spdlog::set_default_logger(console);
  spdlog::set_pattern("[%H:%M:%S.%e] [%^%l%$] %v");
  spdlog::set_level(spdlog::level::from_str(log_level));
  // Every line reaches riffle.log as it is logged: a run killed from outside (a job's time limit, mpirun ending the
  // ranks when one dies) keeps its log up to that moment. The lines are few (outputs, progress, the end).
  spdlog::flush_on(spdlog::level::info);
  // Over MPI ranks rank 0 speaks for the run (it gathers the others' diagnoses); the others say only errors.
  if (ranks::rank() != 0) spdlog::set_level(spdlog::level::err);

  SceneLimits limits;
  limits.memory_limit = memory_limit_gib * 1024.0 * 1024.0 * 1024.0;
  if (*keys) return print_scene_keys(key_scenes, limits, overrides);
  std::unique_ptr<Simulation> simulation;
  // check and graph answer from the model alone: the systems and the step graph are built from it, as a run builds
  // them, but nothing is laid out (no grain, particle or grid array), so they answer in about the time it takes to
  // read the scene whatever its size. The budget (engine/setup/budget.hpp) gives the counts a run would lay out.
  std::unique_ptr<const Model> model_only;
  std::unique_ptr<World> unlaid;
  std::unique_ptr<Stepper> graph_only;
  try {
    if (*check || *graph) {
      model_only = std::make_unique<const Model>(load_scene_file(scene_path, limits, overrides));
      unlaid = std::make_unique<World>(unlaid_world(*model_only));
      graph_only = std::make_unique<Stepper>(build_pipeline(*model_only), *unlaid, *model_only);
    } else if (*resume) {
      simulation = Simulation::from_checkpoint(checkpoint_path, limits);
      if (out_dir.empty()) out_dir = checkpoint_run_directory(checkpoint_path).string();
    } else {
      simulation = Simulation::from_scene_file(scene_path, limits, overrides);
      if (out_dir.empty()) out_dir = default_out_dir(simulation->model());
    }
  } catch (const SceneError& error) {
    if (ranks::rank() == 0) {  // every rank read the same scene: one says what is wrong
      for (const std::string& problem : error.problems()) std::fprintf(stderr, "error: %s\n", problem.c_str());
      std::fprintf(stderr, "%zu problem(s) found; nothing was run\n", error.problems().size());
    }
    return kExitInvalidInput;
  } catch (const CheckpointError& error) {
    if (ranks::rank() == 0) std::fprintf(stderr, "error: %s\n", error.what());
    return kExitInvalidInput;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "error: out of memory while setting up the run (std::bad_alloc): the scene needs more "
                         "memory than this machine has\n");
    return kExitInvalidInput;
  } catch (const std::exception& error) {
    // Scheduler or set-up errors are bugs or unsupported combinations; name them rather than abort.
    std::fprintf(stderr, "error: cannot set up the run: %s\n", error.what());
    return kExitInvalidInput;
  }

  if (*check) {
    print_check(scene_path, *model_only);
    return kExitOk;
  }

  if (*graph) {
    // Edges labelled with the components that order them; tests/data/seed_step_graph.dot pins the seed scene's.
    std::printf("%s", graph_only->dot().c_str());
    return kExitOk;
  }

  if (ranks::distributed()) {
    const std::string problem = Simulation::over_ranks_problem(simulation->model());
    if (!problem.empty()) {
      if (ranks::rank() == 0)
        std::fprintf(stderr, "error: riffle cannot spread this scene over %d MPI ranks: %s; run it on one rank, with "
                     "--threads for the cores\n", ranks::size(), problem.c_str());
      return kExitUsage;
    }
    simulation->split_over_ranks();
  }

  if (until_given) {
    const std::string problem = until_problem(until, simulation->world().time, simulation->model().dt);
    if (!problem.empty()) {
      std::fprintf(stderr, "error: %s\n", problem.c_str());
      return kExitUsage;
    }
  }

  std::signal(SIGINT, handle_stop_signal);
  std::signal(SIGTERM, handle_stop_signal);
  RunOptions options;
  options.out_dir = out_dir;
  options.threads = threads;
  if (until_given) options.until = until;
  options.progress = isatty(fileno(stderr)) != 0;
  return report_run(simulation->run(options));
}

}  // namespace

}  // namespace riffle

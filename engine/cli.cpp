#include "engine/cli.hpp"

#include <CLI/CLI.hpp>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <csignal>
#include <cstdio>

#include "engine/budget.hpp"
#include "engine/scene.hpp"
#include "engine/simulation.hpp"

namespace riffle {

namespace {

const char* kExitCodes =
    "Exit codes:\n"
    "  0    success\n"
    "  1    bad command line\n"
    "  2    invalid scene or checkpoint (each problem is printed as file:line:column: key: message)\n"
    "  3    the run stopped with a diagnosis (NaN, particle left the domain); the last good checkpoint is kept\n"
    "  4    output could not be written\n"
    "  130  interrupted by SIGINT (a checkpoint was written first)\n"
    "  143  terminated by SIGTERM (a checkpoint was written first)\n";

extern "C" void handle_stop_signal(int signal_number) { request_stop(signal_number); }

std::string default_out_dir(const Model& model) { return "out/" + model.name; }

int report_run(const RunOutcome& outcome) {
  if (!outcome.last_checkpoint.empty() && outcome.exit_code != kExitOk)
    spdlog::info("resume with: riffle resume {}", outcome.last_checkpoint);
  return outcome.exit_code;
}

}  // namespace

int cli_main(int argc, char** argv) {
  CLI::App app{"riffle: sediment moved by water. DEM grains coupled to an MPS free-surface fluid.", "riffle"};
  app.footer(kExitCodes);
  app.require_subcommand(1);
  app.set_version_flag("--version", RIFFLE_VERSION);
  std::string log_level = "info";
  // Accepted before and after the subcommand (riffle --log-level debug run ... / riffle run ... --log-level debug).
  auto add_log_level = [&log_level](CLI::App* command) {
    command->add_option("--log-level", log_level, "Log verbosity")
        ->check(CLI::IsMember({"trace", "debug", "info", "warn", "error", "off"}))
        ->capture_default_str();
  };
  add_log_level(&app);
  // [GiB] raises (or lowers) the memory limit scenes are checked against (engine/budget.hpp); beats run.memory_limit.
  double memory_limit_gib = 0.0;
  auto add_memory_limit = [&memory_limit_gib](CLI::App* command) {
    command->add_option("--memory-limit", memory_limit_gib,
                        "Memory limit [GiB] for the scene's estimated budget (default: run.memory_limit, else 3/4 of "
                        "physical memory)")
        ->check(CLI::PositiveNumber);
  };

  std::string scene_path, checkpoint_path, out_dir;
  int threads = 0;
  double until = -1.0;

  CLI::App* run = app.add_subcommand("run", "Validate and run a scene file");
  run->add_option("scene", scene_path, "Scene file (TOML)")->required();
  run->add_option("--out", out_dir, "Output directory (default: out/<run.name>)");
  run->add_option("--threads", threads, "Worker threads (default: all cores)")->check(CLI::PositiveNumber);
  run->add_option("--until", until, "End time [s], overrides run.end_time")->check(CLI::PositiveNumber);
  add_log_level(run);
  add_memory_limit(run);
  run->footer(kExitCodes);

  CLI::App* check = app.add_subcommand("check", "Validate a scene file without running it");
  check->add_option("scene", scene_path, "Scene file (TOML)")->required();
  add_log_level(check);
  add_memory_limit(check);
  check->footer(kExitCodes);

  CLI::App* resume = app.add_subcommand("resume", "Continue a run from a checkpoint");
  resume->add_option("checkpoint", checkpoint_path, "Checkpoint file (.ckpt)")->required();
  resume->add_option("--out", out_dir, "Output directory (default: the checkpoint's run directory)");
  resume->add_option("--threads", threads, "Worker threads (default: all cores)")->check(CLI::PositiveNumber);
  resume->add_option("--until", until, "End time [s], overrides run.end_time")->check(CLI::PositiveNumber);
  add_log_level(resume);
  add_memory_limit(resume);
  resume->footer(kExitCodes);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    const int code = app.exit(error);
    return code == 0 ? kExitOk : kExitUsage;
  }

  auto console = spdlog::stderr_color_mt("riffle");
  spdlog::set_default_logger(console);
  spdlog::set_pattern("[%H:%M:%S.%e] [%^%l%$] %v");
  spdlog::set_level(spdlog::level::from_str(log_level));

  SceneLimits limits;
  limits.memory_limit = memory_limit_gib * 1024.0 * 1024.0 * 1024.0;
  std::unique_ptr<Simulation> simulation;
  try {
    if (*resume) {
      simulation = Simulation::from_checkpoint(checkpoint_path, limits);
      if (out_dir.empty()) {
        // The run directory is the one holding checkpoints/, also when the path is a bare name inside checkpoints/.
        auto run_dir = (std::filesystem::path(checkpoint_path).parent_path() / "..").lexically_normal();
        if (!run_dir.has_filename()) run_dir = run_dir.parent_path();  // "A/" -> "A"
        out_dir = run_dir.string();
      }
    } else {
      simulation = Simulation::from_scene_file(scene_path, limits);
      if (out_dir.empty()) out_dir = default_out_dir(simulation->model());
    }
  } catch (const SceneError& error) {
    for (const std::string& problem : error.problems()) std::fprintf(stderr, "error: %s\n", problem.c_str());
    std::fprintf(stderr, "%zu problem(s) found; nothing was run\n", error.problems().size());
    return kExitInvalidInput;
  } catch (const CheckpointError& error) {
    std::fprintf(stderr, "error: %s\n", error.what());
    return kExitInvalidInput;
  } catch (const std::exception& error) {
    // Scheduler or set-up errors are bugs or unsupported combinations; name them rather than abort.
    std::fprintf(stderr, "error: cannot set up the run: %s\n", error.what());
    return kExitInvalidInput;
  }

  if (*check) {
    const Model& model = simulation->model();
    std::printf("%s: valid scene '%s': %zu grains, %zu walls, t_end = %g s, dt = %g s, %lld solid sub-steps\n",
                scene_path.c_str(), model.name.c_str(),
                simulation->world().solids ? simulation->world().solids->size() : 0,
                simulation->world().walls ? simulation->world().walls->size() : 0, model.end_time, model.dt,
                static_cast<long long>(model.solid_substeps));
    if (const FluidParticles* fluid = simulation->world().fluid ? &*simulation->world().fluid : nullptr)
      std::printf("  fluid: %zu MPS particles, %zu of them fluid, spacing %g m, r_e = %g spacing\n", fluid->size(),
                  simulation->world().fluid_summary->fluid_count, model.fluid.spacing,
                  model.fluid.effective_radius_ratio);
    std::printf("%s", describe_budget(estimate_budget(model), model).c_str());
    return kExitOk;
  }

  std::signal(SIGINT, handle_stop_signal);
  std::signal(SIGTERM, handle_stop_signal);
  RunOptions options;
  options.out_dir = out_dir;
  options.threads = threads;
  if (until > 0.0) options.until = until;
  options.progress = isatty(fileno(stderr)) != 0;
  return report_run(simulation->run(options));
}

}  // namespace riffle

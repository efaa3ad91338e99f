// owval bench engine|io|render|gradient: in-process benchmarks, JSON on stdout (and --json-out
// FILE). The whole-process comparison of backends is cmd_bench_backends.cpp.
#include <filesystem>
#include <iostream>

#include "command.hpp"
#include "owval/backends/engine_bench.hpp"
#include "owval/base/atomic_output.hpp"
#include "owval/engine/run.hpp"
#include "owval/render/render_benchmark.hpp"
#include "owval/trajectory/io_benchmark.hpp"
#include "resolve.hpp"
#include "run_flags.hpp"

namespace owval::cli {
namespace {
namespace fs = std::filesystem;

// --json-out is checked before the benchmark runs (`--json-out CONFIG` replaced the configuration
// it had timed) and written atomically after it.
void AddJsonOut(CLI::App* cmd, std::string* json_out, const std::string* input = nullptr) {
  cmd->add_option("--json-out", *json_out, "Also write the JSON result here")->check(OutputPath());
  cmd->parse_complete_callback([json_out, input] {
    if (json_out->empty()) return;
    CheckOutputPath(*json_out);
    if (input) CheckOutputIsNotAnInput(*json_out, {*input});
  });
}
void Emit(const nlohmann::json& result, const std::string& json_out) {
  std::cout << result.dump(2) << "\n";
  if (!json_out.empty()) WriteFileAtomically(json_out, result.dump(2) + "\n");
}

struct BenchArgs {
  std::string json_out;
  std::string config = "demo1";  // engine
  bool whole_run = false;
  backends::EngineBenchOptions engine;
  IoBenchmarkOptions io;
  render::RenderBenchmarkOptions render;
  engine::GradientOptions gradient;
  double alpha_density = -1;  // gradient: < 0, the model's
};

void SetUpBenchEngine(CLI::App& bench, const std::shared_ptr<BenchArgs>& a) {
  backends::EngineBenchOptions& o = a->engine;
  CLI::App* cmd =
      bench.add_subcommand("engine", "PCISPH engine speed (steps/s), one thread and all threads");
  cmd->add_option("config", a->config,
                  "demo1, one_sprig (Sibernetic's files in ../shared), a scenario or a file")
      ->check(GivenName());
  cmd->add_option("--steps", o.steps, "Steps to time")->check(PositiveCount());
  AddJsonOut(cmd, &a->json_out, &a->config);
  AddBackendFlag(cmd, &o.backend, " to time: pcisph or xpbd (default pcisph)");
  cmd->add_flag("--phases", o.phases,
                "Time each phase of the step and the frames' fields (one run, --threads)");
  cmd->add_flag("--whole-run", a->whole_run,
                "With a reference folder: profile its whole run (meta.json's time and log step)");
  AddThreadsFlag(cmd, &o.threads, " for --phases (default: the engine's rule)");
  AddTimeFlag(cmd, &o.time_s, " for --phases instead of --steps")->check(Positive());
  AddLogStepFlag(cmd, &o.log_step, " for --phases");
  cmd->callback([a] {
    Emit(backends::BenchEngineNamed(a->config, SharedReference(), DataDir(), a->whole_run,
                                    a->engine),
         a->json_out);
  });
}

void SetUpBenchIo(CLI::App& bench, const std::shared_ptr<BenchArgs>& a) {
  IoBenchmarkOptions& o = a->io;
  CLI::App* cmd =
      bench.add_subcommand("io", "Text parse and HDF5 read throughput on a large generated file");
  cmd->add_option("--size-mb", o.text_size_mb, "Size of the generated position_buffer.txt (MB)")
      ->check(Positive());
  cmd->add_option("--dir", o.directory, "Where to write the generated files")->check(OutputPath());
  AddJsonOut(cmd, &a->json_out);
  cmd->add_option("--hdf5-level", o.hdf5.compression_level, "HDF5 deflate level (0-9)");
  cmd->add_option("--hdf5-chunk-frames", o.hdf5.frames_per_chunk, "HDF5 frames per chunk");
  cmd->add_flag("--keep", o.keep_files, "Keep the generated files");
  cmd->callback([a] {
    a->io.quiet = QuietMode();
    Emit(RunIoBenchmark(a->io), a->json_out);
  });
}

void SetUpBenchRender(CLI::App& bench, const std::shared_ptr<BenchArgs>& a) {
  CLI::App* cmd = bench.add_subcommand("render", "Render + H.264 encode frames per second (JSON)");
  cmd->add_option("--frames", a->render.frames, "Frames per case")->check(PositiveCount());
  AddJsonOut(cmd, &a->json_out);
  cmd->callback([a] {
    a->render.demo1_trajectory = SharedReference() / "demo1/position_buffer.txt";
    Emit(render::RunRenderBenchmark(a->render), a->json_out);
  });
}

void SetUpBenchGradient(CLI::App& bench, const std::shared_ptr<BenchArgs>& a) {
  CLI::App* cmd = bench.add_subcommand(
      "gradient", "XPBD reverse pass: backward cost per step over forward, tape memory (JSON)");
  AddInput(cmd, "config", &a->config, "Scenario name or Sibernetic configuration");
  cmd->add_option("--steps", a->gradient.steps, "Steps of the window")
      ->check(CLI::Range(1, 10000000));
  AddTapeCheckpointFlag(cmd, &a->gradient.checkpoint_every);
  cmd->add_option("--alpha-density", a->alpha_density,
                  "Density compliance (s^2/cu^2, >= 0; 0 is a value, a rigid constraint, as in "
                  "gradcheck); default the model's")
      ->check(NonNegative());
  AddJsonOut(cmd, &a->json_out, &a->config);
  cmd->callback([a] {
    nlohmann::json result =
        backends::BenchGradient(ResolveConfig(a->config), a->gradient, a->alpha_density);
    result["config"] = a->config;
    Emit(result, a->json_out);
  });
}

void SetUpBench(CLI::App& app) {
  auto a = std::make_shared<BenchArgs>();
  SetUpBenchEngine(Bench(app), a);
  SetUpBenchIo(Bench(app), a);
  SetUpBenchRender(Bench(app), a);
  SetUpBenchGradient(Bench(app), a);
}

const bool bench_registered = RegisterCommand(&SetUpBench);

}  // namespace
}  // namespace owval::cli

// owval bench gradient CONFIG: the XPBD reverse pass's cost per step against its forward pass,
// and the memory its checkpointing holds (JSON).
#include <iostream>
#include <nlohmann/json.hpp>

#include "command.hpp"
#include "owval/engine/gradient.hpp"
#include "resolve.hpp"

namespace owval::cli {
namespace {

struct BenchGradientArgs {
  std::string config;
  engine::GradientOptions options;
  double alpha_density = -1;
};

void RunBenchGradient(const BenchGradientArgs& a) {
  const engine::SiberneticConfig config = ResolveConfig(a.config);
  const engine::DifferentiableXpbd model(config, engine::PhysicsConstants{});
  std::vector<double> theta = model.DefaultParameters();
  if (a.alpha_density >= 0) theta[4] = a.alpha_density;
  // Every moving particle against its initial position at the last step: a loss touching all.
  engine::LossTerm loss;
  loss.target = engine::LossTerm::Target::kAllMoving;
  loss.frame_steps = {a.options.steps};
  std::vector<engine::Vec3d> start;
  for (std::int32_t i : model.moving()) start.push_back(model.initial_positions()[std::size_t(i)]);
  loss.reference = {start};
  const engine::GradientSummary g = model.Gradient(theta, {loss}, a.options);
  const double steps = double(a.options.steps);
  const nlohmann::json j = {{"benchmark", "gradient"},
                            {"config", a.config},
                            {"particles", model.particle_count()},
                            {"moving", model.moving().size()},
                            {"steps", a.options.steps},
                            {"checkpoint_every", a.options.checkpoint_every},
                            {"forward_s_per_step", g.forward_seconds / steps},
                            {"backward_s_per_step", g.backward_seconds / steps},
                            {"backward_over_forward", g.backward_seconds / g.forward_seconds},
                            {"forward_steps_run", g.forward_steps},
                            {"stored_states", g.stored_states},
                            {"peak_tape_bytes", g.peak_tape_bytes},
                            {"peak_tape_mib", double(g.peak_tape_bytes) / (1024.0 * 1024.0)},
                            {"loss", g.loss}};
  std::cout << j.dump(2) << "\n";
}

void SetUp(CLI::App& app) {
  auto a = std::make_shared<BenchGradientArgs>();
  CLI::App* cmd = Bench(app).add_subcommand(
      "gradient", "XPBD reverse pass: backward cost per step over forward, tape memory (JSON)");
  cmd->add_option("config", a->config, "Scenario name or Sibernetic configuration")->required();
  cmd->add_option("--steps", a->options.steps, "Steps of the window")
      ->check(CLI::Range(1, 10000000));
  cmd->add_option("--checkpoint-every", a->options.checkpoint_every,
                  "States kept every k steps (0: full tape)");
  cmd->add_option("--alpha-density", a->alpha_density,
                  "Density compliance (s^2); default the run's");
  cmd->callback([a] { RunBenchGradient(*a); });
}

const bool registered = RegisterCommand(&SetUp);

}  // namespace
}  // namespace owval::cli

// Elastic beads on springs hanging vertically under gravity: the static equilibrium of
// Sibernetic's one-sided springs. Bead i feels only the springs its own [connection] rows list
// (sphFluid.cl), each adding k*f*(r - L0) along the spring, plus gravity. In y that is linear:
//   sum_rows k f (y_j - y_i) - sum_rows sigma k f L0 + g_y/s = 0,  sigma = +1 partner above,
// a linear system A*y = b whose matrix A (s⁻²) is also the stiffness of the small oscillations.
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "owval/base/errors.hpp"
#include "prediction_parts.hpp"

namespace owval::predict::internal {
namespace {

struct ChainSystem {
  Eigen::MatrixXd a;  // s⁻²
  Eigen::VectorXd b;  // s⁻² * cu
  std::size_t springs = 0;
  double min_bead_distance_cu = 1e30;
};

ChainSystem Assemble(const engine::SiberneticConfig& c, const engine::PhysicsConstants& k,
                     const PredictOptions& o) {
  const std::size_t n = c.elastic_count();
  ChainSystem sys{Eigen::MatrixXd::Zero(n, n), Eigen::VectorXd::Zero(n)};
  for (std::size_t i = 0; i < n; ++i) {
    sys.b[i] = k.gravity[1] / k.simulation_scale;
    for (int slot = 0; slot < engine::kConnectionSlots; ++slot) {
      const engine::Row4& row = c.connection[i * engine::kConnectionSlots + slot];
      if (row[0] < 0) break;  // Sibernetic stops at the first empty slot
      const std::size_t j = static_cast<std::size_t>(row[0]);
      const engine::Row4 &pi = c.position[i], &pj = c.position[j];
      if (std::abs(pi[0] - pj[0]) > 1e-3f || std::abs(pi[2] - pj[2]) > 1e-3f)
        throw InputError(c.source, 0,
                         "hanging_chain predicts vertical chains only (springs " +
                             std::to_string(i) + "-" + std::to_string(j) + ")");
      const double kf = k.elasticity_coefficient * SpringFactor(pi[3], pj[3], k, o);
      const double sigma = pj[1] > pi[1] ? 1.0 : -1.0;
      sys.a(i, i) += kf;
      sys.b[i] -= sigma * kf * row[1];
      if (j < n) {
        sys.a(i, j) -= kf;
        sys.min_bead_distance_cu =
            std::min(sys.min_bead_distance_cu, double(std::abs(pi[1] - pj[1])));
      } else {
        sys.b[i] += kf * pj[1];
      }
      ++sys.springs;
    }
  }
  return sys;
}

// Lowest angular frequency of the linearised chain (rad/s): sqrt of A's smallest eigenvalue.
double FundamentalOmega(const Eigen::MatrixXd& a) {
  const Eigen::VectorXcd lambda = Eigen::EigenSolver<Eigen::MatrixXd>(a, false).eigenvalues();
  double lowest = 1e300;
  for (Eigen::Index i = 0; i < lambda.size(); ++i) lowest = std::min(lowest, lambda[i].real());
  return std::sqrt(std::max(lowest, 0.0));
}

}  // namespace

Prediction HangingChain(const engine::SiberneticConfig& c, const engine::PhysicsConstants& k,
                        const PredictOptions& o) {
  const std::size_t n = c.elastic_count();
  const ChainSystem sys = Assemble(c, k, o);
  Eigen::FullPivLU<Eigen::MatrixXd> lu(sys.a);
  if (n == 0 || !lu.isInvertible())
    throw InputError(c.source, 0,
                     "hanging_chain: the springs do not hold every bead to a wall particle");
  const Eigen::VectorXd y = lu.solve(sys.b);
  std::size_t tip = 0;
  for (std::size_t i = 1; i < n; ++i) tip = y[i] < y[tip] ? i : tip;
  const double s = k.simulation_scale, sag = c.position[tip][1] - y[tip];
  const double omega = FundamentalOmega(sys.a);
  const double period = SymplecticEulerPeriod(omega, k.time_step_s);
  nlohmann::json beads = nlohmann::json::array();
  for (std::size_t i = 0; i < n; ++i)
    beads.push_back(
        {{"particle", i}, {"start_y_cu", c.position[i][1]}, {"equilibrium_y_cu", y[i]}});
  Prediction p;
  p.predictor = "hanging_chain";
  p.inputs = {
      Input("beads", double(n), "1",
            "configuration [position]: elastic rows 0.." + std::to_string(n - 1)),
      Input("springs", double(sys.springs), "1",
            "non-empty [connection] rows from " + ConfigSource(c, Section::kConnection, 0)),
      Input("tip_start_y", c.position[tip][1], "cu", ConfigSource(c, Section::kPosition, tip)),
      Input("elasticity_coefficient", k.elasticity_coefficient, "s^-2",
            DefaultSource("4*1.5e-4/mass")),
      Input("non_worm_body_spring_factor",
            o.omit_quarter_factor ? 1.0 : k.non_worm_body_spring_factor, "1",
            o.omit_quarter_factor ? "omitted on request (--no-quarter-factor)"
                                  : "sphFluid.cl: springs not between two worm-body particles"),
      Input("gravity_y", k.gravity[1], "m/s^2", DefaultSource("gravity_y")),
      Input("simulation_scale", s, "m/cu", DefaultSource("simulationScale")),
      Input("time_step", k.time_step_s, "s", DefaultSource("timeStep"))};
  PredictedQuantity equilibrium =
      Quantity("equilibrium", y[tip], "cu", y[tip] * s, "m",
               "solve sum_rows k*f*(y_j - y_i - sigma*L0) + g_y/s = 0 for every bead; tip row",
               0.01, kAbsoluteCu);
  equilibrium.detail_key = "beads";
  equilibrium.detail = beads;
  p.predictions = {
      equilibrium,
      Quantity("tip_sag", sag, "cu", sag * s, "m", "tip start_y - equilibrium", 0, kInformative),
      Quantity("fundamental_period", period, "s", period, "s",
               "semi-implicit Euler period of sqrt(smallest eigenvalue of the stiffness matrix)", 0,
               kInformative)};
  if (sys.min_bead_distance_cu < k.h_cu)
    p.notes.push_back(
        "beads closer than h interact through SPH forces, which this static "
        "balance of springs and gravity leaves out");
  p.track = Track{tip, "", Axis::kY};
  return p;
}

}  // namespace owval::predict::internal

// The engine's SPH kernels tested as SPlisHSPlasH tests its kernels (Tests/CubicKernelTest and
// friends): W integrates to one over a sampled grid, the gradients and the Laplacian agree with
// finite differences of W, and everything vanishes outside the support. Every check calls the
// functions the phases call (kernels/kernels.hpp), with the coefficients SphConstants uses.
#include "kernels/kernels.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "kernels/sph_constants.hpp"

namespace owval::engine::internal {
namespace {

// Sibernetic's h in metres, and 1 (the kernels must not depend on the unit).
constexpr double kRadii[] = {2.47159969e-05, 1.0};

// ∫ W dV by the midpoint rule on an n³ grid over [−h, h]³.
template <typename Kernel>
double IntegrateOverGrid(double h, int n, Kernel w) {
  const double step = 2 * h / n;
  double sum = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) {
        const double x = -h + (i + 0.5) * step, y = -h + (j + 0.5) * step,
                     z = -h + (k + 0.5) * step;
        sum += w(h, std::sqrt(x * x + y * y + z * z));
      }
  return sum * step * step * step;
}

TEST(Kernels, EachKernelIntegratesToOneOverASampledGrid) {
  for (double h : kRadii) {
    // 100³ samples: the midpoint rule's error is ~1e-4 for the smooth kernels; Wviscosity's
    // h/(2r) singularity at the origin costs more.
    EXPECT_NEAR(IntegrateOverGrid(h, 100, Wpoly6<double>), 1.0, 1e-3) << h;
    EXPECT_NEAR(IntegrateOverGrid(h, 100, Wspiky<double>), 1.0, 1e-3) << h;
    EXPECT_NEAR(IntegrateOverGrid(h, 100, Wviscosity<double>), 1.0, 1e-2) << h;
  }
}

// Offsets inside the support, away from r = 0 and r = h where the derivatives are not smooth.
std::vector<std::array<double, 3>> SamplePoints(double h) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-h, h);
  std::vector<std::array<double, 3>> points;
  while (points.size() < 200) {
    const std::array<double, 3> p{u(rng), u(rng), u(rng)};
    const double r = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    if (r > 0.05 * h && r < 0.95 * h) points.push_back(p);
  }
  return points;
}

template <typename Kernel, typename Gradient>
void ExpectGradientMatchesCentralDifferences(double h, Kernel w, Gradient gradient) {
  const double e = 1e-6 * h;
  for (const auto& p : SamplePoints(h)) {
    double g[3];
    gradient(h, p.data(), g);
    for (int a = 0; a < 3; ++a) {
      auto plus = p, minus = p;
      plus[a] += e;
      minus[a] -= e;
      auto radius = [](const std::array<double, 3>& x) {
        return std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
      };
      const double numeric = (w(h, radius(plus)) - w(h, radius(minus))) / (2 * e);
      // Relative to the gradient's scale at this h (W ~ 1/h³, ∇W ~ 1/h⁴).
      EXPECT_NEAR(g[a], numeric, 1e-6 / std::pow(h, 4)) << "h " << h << " axis " << a;
    }
  }
}

TEST(Kernels, GradientsMatchCentralDifferencesOfTheKernels) {
  for (double h : kRadii) {
    ExpectGradientMatchesCentralDifferences(h, Wpoly6<double>, Wpoly6Gradient<double>);
    ExpectGradientMatchesCentralDifferences(h, Wspiky<double>, SpikyGradient<double>);
  }
}

TEST(Kernels, ViscosityLaplacianMatchesFiniteDifferences) {
  // ∇²W(r) = W'' + 2W'/r for a radial W, by central differences in r.
  for (double h : kRadii) {
    for (double x : {0.1, 0.3, 0.5, 0.7, 0.9}) {
      const double r = x * h, e = 1e-4 * h;
      const double w0 = Wviscosity(h, r), wp = Wviscosity(h, r + e), wm = Wviscosity(h, r - e);
      const double laplacian = (wp - 2 * w0 + wm) / (e * e) + 2 / r * (wp - wm) / (2 * e);
      EXPECT_NEAR(ViscosityLaplacian(h, r), laplacian, 1e-5 * ViscosityLaplacian(h, 0.0))
          << "h " << h << " r/h " << x;
    }
  }
}

TEST(Kernels, EverythingVanishesOutsideTheSupport) {
  for (double h : kRadii) {
    for (double x : {1.0, 1.0 + 1e-12, 1.5, 3.0}) {
      const double r = x * h, offset[3] = {r, 0, 0};
      EXPECT_EQ(Wpoly6(h, r), 0.0);
      EXPECT_EQ(Wspiky(h, r), 0.0);
      EXPECT_EQ(Wviscosity(h, r), 0.0);
      EXPECT_EQ(ViscosityLaplacian(h, r), 0.0);
      double g[3];
      Wpoly6Gradient(h, offset, g);
      EXPECT_EQ(g[0], 0.0);
      SpikyGradient(h, offset, g);
      EXPECT_EQ(g[0], 0.0);
    }
  }
  // The float accumulation the density phases use adds nothing at or beyond h.
  const SphConstants k = SphConstants::From(PhysicsConstants{});
  const float sum = k.hs6;
  EXPECT_EQ(AccumulateWpoly6(k.hs2_m2, k.hs2_m2, sum), sum);
  EXPECT_EQ(AccumulateWpoly6(k.hs2_m2, 2 * k.hs2_m2, sum), sum);
  EXPECT_FLOAT_EQ(AccumulateWpoly6(k.hs2_m2, 0.0f, sum), 2 * sum);
  EXPECT_EQ(BoundaryWeight(k.r0_cu, k.r0_cu), 0.0f);
  EXPECT_EQ(BoundaryWeight(k.r0_cu, 2 * k.r0_cu), 0.0f);
  EXPECT_EQ(BoundaryWeight(k.r0_cu, 0.0f), 1.0f);
}

TEST(Kernels, ThePhasesFloatShapesTimesSphConstantsAreTheKernels) {
  // What a phase computes per pair (float shape × the float coefficient SphConstants holds)
  // equals m·W of the double kernel to float precision, at Sibernetic's constants.
  const SphConstants k = SphConstants::From(PhysicsConstants{});
  const double h = k.hs_m, m = k.mass_kg;
  for (double x : {0.0, 0.2, 0.5, 0.8, 0.99}) {
    const float r = float(x * h);
    const double poly6 = m * Wpoly6(h, double(r));
    EXPECT_NEAR(k.mass_wpoly6 * Wpoly6Shape(k.hs2_m2, r * r), poly6, 1e-5 * m * Wpoly6(h, 0.0));
    const double offset[3] = {double(r), 0, 0};
    double g[3];
    SpikyGradient(h, offset, g);
    if (x > 0) {
      EXPECT_NEAR(k.mass_grad_wspiky * SpikyGradientShape(k.hs_m, r), m * g[0],
                  1e-5 * std::abs(m * SpikyGradientCoefficient(h)) * h * h);
    }
    EXPECT_NEAR(k.mass_lap_wviscosity * ViscosityLaplacianShape(k.hs_m, r),
                m * ViscosityLaplacian(h, double(r)),
                1e-5 * m * ViscosityLaplacianCoefficient(h) * h);
  }
}

}  // namespace
}  // namespace owval::engine::internal

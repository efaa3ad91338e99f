// acceleration.worst_stencil's measure streamed through a window (stencil_excess.hpp): the same
// worst stencil and value as every stencil kept and judged at the end, in memory that does not
// grow with the run.
#include "stencil_excess.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace owval::compare::internal {
namespace {

struct Medians {
  double reference, candidate;
};

// The measure as its definition says, over every stencil at once.
StencilExcess EveryStencilJudged(const std::vector<Medians>& stencils, double mean) {
  const std::size_t window = StencilExcesses::kStencilWindow;
  StencilExcess worst;
  for (std::size_t i = 0; i < stencils.size(); ++i)
    for (int run = 0; run < 2; ++run) {
      const auto median = [&](std::size_t k, int r) {
        return r == 0 ? stencils[k].reference : stencils[k].candidate;
      };
      double largest = 0;
      for (std::size_t k = i > window ? i - window : 0;
           k < std::min(stencils.size(), i + window + 1); ++k)
        largest = std::max(largest, median(k, 1 - run));
      const double excess = std::max(0.0, median(i, run) - largest);
      double value = excess == 0 ? 0 : excess / std::max(largest, mean);
      if (std::isnan(value)) value = INFINITY;
      if (value > worst.value) worst = {value, 10 * i, {median(i, 0), median(i, 1)}};
    }
  return worst;
}

StencilExcess Streamed(const std::vector<Medians>& stencils, double mean,
                       std::size_t* kept = nullptr) {
  StencilExcesses excesses;
  for (std::size_t i = 0; i < stencils.size(); ++i)
    excesses.Push(10 * i, stencils[i].reference, stencils[i].candidate);
  if (kept) *kept = excesses.kept();
  return excesses.Worst(mean);
}

void ExpectSame(const StencilExcess& streamed, const StencilExcess& judged) {
  EXPECT_EQ(streamed.value, judged.value);
  EXPECT_EQ(streamed.reference_frame, judged.reference_frame);
  EXPECT_EQ(streamed.median[0], judged.median[0]);
  EXPECT_EQ(streamed.median[1], judged.median[1]);
}

// Runs of 1-400 stencils whose medians wander, spike, rest at zero and overflow, judged at means
// from zero to past every median: the same stencil and value, bit for bit.
TEST(StencilExcesses, StreamedGivesTheSameWorstAsEveryStencilJudged) {
  std::mt19937_64 random(20261130);
  std::uniform_real_distribution<double> uniform(0, 1);
  for (int run = 0; run < 400; ++run) {
    const std::size_t n = 1 + random() % 400;
    std::vector<Medians> stencils(n);
    double level = 1 + 99 * uniform(random);
    for (Medians& m : stencils) {
      level *= std::exp(0.2 * (uniform(random) - 0.5));
      m = {level * (0.5 + uniform(random)), level * (0.5 + uniform(random))};
      const double roll = uniform(random);
      if (roll < 0.05)
        m.candidate *= 20;  // a displaced frame
      else if (roll < 0.08)
        m.reference = 0;  // at rest
      else if (roll < 0.09)
        m.candidate = INFINITY;
      else if (roll < 0.10)
        m.candidate = NAN;  // skipped as a neighbour
      else if (roll < 0.11)
        m = {0, 0};
    }
    for (double mean : {0.0, 1.0, level, 1e3 * level, double(NAN)}) {
      SCOPED_TRACE(::testing::Message() << "run " << run << ", mean " << mean);
      ExpectSame(Streamed(stencils, mean), EveryStencilJudged(stencils, mean));
    }
  }
}

// Identical runs whose accelerations decay: no stencil exceeds, and though each has a smaller
// largest than the last, none is kept past the first.
TEST(StencilExcesses, IdenticalRunsGiveZeroAtTheFirstStencilAndKeepOnePair) {
  std::vector<Medians> stencils;
  for (int i = 0; i < 1000; ++i)
    stencils.push_back({1e3 * std::pow(0.99, i), 1e3 * std::pow(0.99, i)});
  std::size_t kept = 0;
  const StencilExcess worst = Streamed(stencils, 2, &kept);
  EXPECT_EQ(worst.value, 0);
  EXPECT_EQ(worst.reference_frame, 0u);
  EXPECT_EQ(kept, 1u);
}

// Two bodies at rest, judged against a mean of zero: no excess is worth zero, not 0/0.
TEST(StencilExcesses, RunsAtRestGiveZero) {
  const std::vector<Medians> stencils(30, Medians{0, 0});
  EXPECT_EQ(Streamed(stencils, 0).value, 0);
  EXPECT_EQ(EveryStencilJudged(stencils, 0).value, 0);
}

// A run whose candidate exceeds the reference's nearby largest by a little more each stencil
// while the reference grows: every excess could be the worst for some mean, so each is kept, up
// to kMaxKept. Past it neighbours merge, and the value can only be overstated: by 1.5% here, where
// 20,000 pairs' largests span 4.3 decades.
TEST(StencilExcesses, KeepsAtMostItsBoundAndNeverUnderstatesTheWorst) {
  const auto reference = [](int i) { return 1.0 * std::pow(1.0005, i); };  // 4.3 decades
  std::vector<Medians> stencils;
  for (int i = 0; i < 20000; ++i)
    stencils.push_back({reference(i), reference(i + 5) + 1e-4 * (1 + i)});
  for (double mean : {0.0, 1.0, 50.0, 1e3, 1e5}) {
    SCOPED_TRACE(::testing::Message() << "mean " << mean);
    std::size_t kept = 0;
    const StencilExcess streamed = Streamed(stencils, mean, &kept);
    const StencilExcess judged = EveryStencilJudged(stencils, mean);
    EXPECT_LE(kept, StencilExcesses::kMaxKept);
    EXPECT_GE(streamed.value, judged.value);
    EXPECT_LE(streamed.value, judged.value * 1.02);
  }
}

}  // namespace
}  // namespace owval::compare::internal

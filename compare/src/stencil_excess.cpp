#include "stencil_excess.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace owval::compare::internal {
namespace {

// What acceleration.worst_stencil judges of a pair once the mean is known.
template <typename Pair>
double Value(const Pair& pair, double mean) {
  if (pair.excess == 0) return 0;  // no excess, whatever it is divided by
  const double value = pair.excess / std::max(pair.largest, mean);
  return std::isnan(value) ? INFINITY : value;  // an overflowed median over an overflowed one
}

// `a` is worth at least `b` whatever the mean.
template <typename Pair>
bool AtLeast(const Pair& a, const Pair& b) {
  return a.excess >= b.excess && a.largest <= b.largest;
}

// `a` is worth more than `b` whatever the (finite) mean.
template <typename Pair>
bool Beats(const Pair& a, const Pair& b) {
  return a.excess > b.excess && a.largest < b.largest;
}

}  // namespace

void StencilExcesses::Push(std::size_t reference_frame, double reference_median,
                           double candidate_median) {
  const std::size_t j = pushed_++;
  ring_[j % ring_.size()] = {reference_frame, {reference_median, candidate_median}};
  if (j < kStencilWindow) return;  // the first stencils' windows are complete only later
  for (const Pair& pair : PairsAt(j - kStencilWindow, j)) Keep(pair);
}

std::array<StencilExcesses::Pair, 2> StencilExcesses::PairsAt(std::size_t i,
                                                              std::size_t last) const {
  const Stencil& at = ring_[i % ring_.size()];
  std::array<Pair, 2> pairs;
  for (int run = 0; run < 2; ++run) {
    double largest = 0;  // the other run's largest median within the window (a NaN skipped)
    for (std::size_t k = i > kStencilWindow ? i - kStencilWindow : 0; k <= last; ++k)
      largest = std::max(largest, ring_[k % ring_.size()].median[1 - run]);
    pairs[run] = {std::max(0.0, at.median[run] - largest), largest, at};
  }
  return pairs;
}

void StencilExcesses::Keep(const Pair& pair) {
  if (pair.excess == 0 && !kept_.empty()) return;  // worth zero, as the first pair at least
  for (const Pair& earlier : kept_)
    if (AtLeast(earlier, pair)) return;
  kept_.erase(std::remove_if(kept_.begin(), kept_.end(),
                             [&pair](const Pair& earlier) { return Beats(pair, earlier); }),
              kept_.end());
  kept_.push_back(pair);
  if (kept_.size() > kMaxKept) MergeClosest();
}

// The kept pairs in the order of their largest medians have excesses that do not decrease (else
// one would have dropped the other). The two neighbours whose largests are closest in ratio
// become one: the larger excess (its stencil) over the smaller largest, worth at least either
// whatever the mean, by that ratio at most more than the better of the two. (Choosing by the
// excesses' ratio as well compounds: a pair absorbs neighbour after neighbour of similar excess
// and ever smaller largest.)
void StencilExcesses::MergeClosest() {
  std::vector<std::size_t> order(kept_.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(),
            [this](std::size_t a, std::size_t b) { return kept_[a].largest < kept_[b].largest; });
  std::size_t closest = 0;
  double closest_ratio = INFINITY;
  for (std::size_t n = 0; n + 1 < order.size(); ++n) {
    const double low = kept_[order[n]].largest, high = kept_[order[n + 1]].largest;
    const double ratio = high == low ? 1 : high / low;
    if (ratio < closest_ratio) closest_ratio = ratio, closest = n;
  }
  Pair& low = kept_[order[closest]];
  Pair& high = kept_[order[closest + 1]];
  Pair& survivor = low.excess >= high.excess ? low : high;
  survivor.largest = std::min(low.largest, high.largest);
  survivor.excess = std::max(low.excess, high.excess);
  kept_.erase(kept_.begin() +
              std::ptrdiff_t(&survivor == &low ? order[closest + 1] : order[closest]));
}

StencilExcess StencilExcesses::Worst(double mean) const {
  StencilExcess worst;
  const auto consider = [&worst, mean](const Pair& pair) {
    const double value = Value(pair, mean);
    if (value > worst.value)
      worst = {
          value, pair.stencil.reference_frame, {pair.stencil.median[0], pair.stencil.median[1]}};
  };
  for (const Pair& pair : kept_) consider(pair);
  // The last stencils, whose windows the run ended.
  const std::size_t first_open = pushed_ > kStencilWindow ? pushed_ - kStencilWindow : 0;
  for (std::size_t i = first_open; i < pushed_; ++i)
    for (const Pair& pair : PairsAt(i, pushed_ - 1)) consider(pair);
  return worst;
}

}  // namespace owval::compare::internal

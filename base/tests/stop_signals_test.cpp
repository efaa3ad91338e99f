#include "owval/base/stop_signals.hpp"

#include <gtest/gtest.h>

#include <csignal>

namespace owval {
namespace {

TEST(StopSignals, ASignalWhileGuardedIsRecordedNotFatal) {
  {
    const StopSignals guard;
    EXPECT_FALSE(StopRequested());
    std::raise(SIGTERM);
    EXPECT_EQ(StopSignal(), SIGTERM);
  }
  // A new guard starts without the old request.
  const StopSignals again;
  EXPECT_FALSE(StopRequested());
  std::raise(SIGINT);
  EXPECT_EQ(StopSignal(), SIGINT);
}

TEST(StopSignals, ThePreviousHandlerComesBack) {
  static volatile std::sig_atomic_t seen = 0;
  auto* before = std::signal(SIGINT, [](int s) { seen = s; });
  { const StopSignals guard; }
  std::raise(SIGINT);
  EXPECT_EQ(seen, SIGINT);
  std::signal(SIGINT, before);
}

}  // namespace
}  // namespace owval

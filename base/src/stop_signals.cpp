#include "owval/base/stop_signals.hpp"

#include <csignal>

namespace owval {
namespace {
volatile std::sig_atomic_t g_stop_signal = 0;
extern "C" void RecordStopSignal(int signal) { g_stop_signal = signal; }
}  // namespace

StopSignals::StopSignals() {
  g_stop_signal = 0;
  previous_interrupt_ = std::signal(SIGINT, RecordStopSignal);
  previous_terminate_ = std::signal(SIGTERM, RecordStopSignal);
}

StopSignals::~StopSignals() {
  std::signal(SIGINT, previous_interrupt_);
  std::signal(SIGTERM, previous_terminate_);
}

int StopSignal() { return int(g_stop_signal); }

}  // namespace owval

#pragma once
// SIGINT and SIGTERM as a request to stop, for long work that polls between steps and then leaves
// a partial, resumable result. The handler only records the signal (nothing else is
// async-signal-safe); nothing unwinds from inside it.
namespace owval {

// While one exists, SIGINT and SIGTERM set the stop request instead of killing the process; the
// previous handlers come back when it is destroyed. Creating one clears an earlier request.
class StopSignals {
 public:
  StopSignals();
  ~StopSignals();
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;

 private:
  void (*previous_interrupt_)(int);
  void (*previous_terminate_)(int);
};

// The signal that asked to stop (SIGINT, SIGTERM), or 0.
int StopSignal();
inline bool StopRequested() { return StopSignal() != 0; }

}  // namespace owval

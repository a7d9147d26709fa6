#include "hoidslam/core/interrupt.h"

#include <atomic>
#include <csignal>

#include "hoidslam/core/error.h"

namespace hoidslam::core {
namespace {

// Written by the signal handler, read by worker threads polling for a stop: a lock-free atomic is safe for both.
std::atomic<int> g_signal{0};
static_assert(std::atomic<int>::is_always_lock_free, "the signal flag must be usable from a signal handler");

extern "C" void RecordSignal(int signal) { g_signal = signal; }

// Installs RecordSignal for `signal` unless the signal is ignored (e.g. under nohup); returns the old handler.
void (*Catch(int signal))(int) {
  const auto previous = std::signal(signal, RecordSignal);
  if (previous == SIG_IGN) std::signal(signal, SIG_IGN);
  return previous;
}

}  // namespace

InterruptGuard::InterruptGuard() : previous_int_(Catch(SIGINT)), previous_term_(Catch(SIGTERM)) { g_signal = 0; }

InterruptGuard::~InterruptGuard() { Restore(); }

int InterruptGuard::signal() const { return g_signal; }

void InterruptGuard::Restore() {
  if (restored_) return;
  std::signal(SIGINT, previous_int_);
  std::signal(SIGTERM, previous_term_);
  restored_ = true;
}

void InterruptGuard::Reraise() {
  const int caught = g_signal;
  Restore();
  if (caught != 0) std::raise(caught);
  throw Error("interrupted");
}

}  // namespace hoidslam::core

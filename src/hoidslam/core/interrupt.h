#pragma once
// Ctrl-C and SIGTERM as a polite request. While an InterruptGuard lives, these signals only set a flag that
// long jobs poll between frames, so they can stop and remove their unfinished output (outputs are complete or
// absent); the earlier handlers come back on destruction. One guard at a time per process.

namespace hoidslam::core {

class InterruptGuard {
 public:
  InterruptGuard();
  ~InterruptGuard();
  InterruptGuard(const InterruptGuard&) = delete;
  InterruptGuard& operator=(const InterruptGuard&) = delete;

  bool requested() const { return signal() != 0; }
  int signal() const;  // the signal caught, 0 if none

  // Restores the earlier handlers and raises the caught signal again, so the process ends as an interrupted
  // program does (exit status 128 + signal); throws core::Error when a handler lets the program go on.
  [[noreturn]] void Reraise();

 private:
  using Handler = void (*)(int);
  void Restore();

  Handler previous_int_;
  Handler previous_term_;
  bool restored_ = false;
};

}  // namespace hoidslam::core

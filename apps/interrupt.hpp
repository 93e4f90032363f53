#pragma once
// Ctrl-C (SIGINT), SIGTERM and SIGHUP as a request to stop: long commands poll requested()
// and either finish their output with the frames so far (capture, live, track) or abandon
// it (play, synth, speak, eval: throw_if_requested()), never leaving half a file. The
// handler only sets a flag, the one thing a signal handler may safely do.
//
// Outside an InterruptScope the same signals end the program after removing the
// temporaries of unfinished outputs (install_signal_cleanup()).

#include <stdexcept>
#include <string>

namespace rostro::app {

class InterruptScope {
 public:
  InterruptScope();   // installs the handlers and clears the flag
  ~InterruptScope();  // restores the previous handlers
  InterruptScope(const InterruptScope&) = delete;
  InterruptScope& operator=(const InterruptScope&) = delete;

  bool requested() const;
  // "Ctrl-C", "SIGTERM" or "SIGHUP": what asked to stop.
  std::string signal_name() const;
  // Throws Interrupted when a stop was requested.
  void throw_if_requested() const;
};

// A command stopped by a signal before its output was complete: nothing was written.
// main() prints one line and exits with 128 + the signal number.
class Interrupted : public std::runtime_error {
 public:
  Interrupted(int signal, const std::string& name)
      : std::runtime_error("stopped by " + name + " before finishing: no output written"),
        signal_(signal) {}
  int signal() const { return signal_; }

 private:
  int signal_;
};

// Makes SIGINT, SIGTERM and SIGHUP remove unfinished AtomicFile temporaries before the
// program ends. Called once by main().
void install_signal_cleanup();

}  // namespace rostro::app

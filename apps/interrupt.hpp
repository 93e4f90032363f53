#pragma once
// Ctrl-C as a request to stop: long commands (capture, live) poll requested() and finish
// their output instead of dying with half a file. The handler only sets a flag, the one
// thing a signal handler may safely do.

namespace rostro::app {

class InterruptScope {
 public:
  InterruptScope();   // installs the SIGINT handler and clears the flag
  ~InterruptScope();  // restores the previous handler
  InterruptScope(const InterruptScope&) = delete;
  InterruptScope& operator=(const InterruptScope&) = delete;

  bool requested() const;

 private:
  void (*previous_)(int);
};

}  // namespace rostro::app

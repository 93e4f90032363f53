#include "apps/interrupt.hpp"

#include <csignal>

namespace rostro::app {
namespace {

volatile std::sig_atomic_t g_interrupted = 0;

extern "C" void on_interrupt(int) {
  g_interrupted = 1;
}

}  // namespace

InterruptScope::InterruptScope() {
  g_interrupted = 0;
  previous_ = std::signal(SIGINT, on_interrupt);
}

InterruptScope::~InterruptScope() {
  std::signal(SIGINT, previous_);
}

bool InterruptScope::requested() const {
  return g_interrupted != 0;
}

}  // namespace rostro::app

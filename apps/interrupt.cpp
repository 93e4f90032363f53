#include "apps/interrupt.hpp"

#include <csignal>

#include "facecore/atomic_file.hpp"

namespace rostro::app {
namespace {

constexpr int kSignals[] = {SIGINT, SIGTERM, SIGHUP};
volatile std::sig_atomic_t g_signal = 0;
struct sigaction g_previous[3];

extern "C" void on_interrupt(int signal) {
  g_signal = signal;
}

extern "C" void on_fatal_signal(int signal) {
  AtomicFile::remove_temporaries_from_signal_handler();
  std::signal(signal, SIG_DFL);
  std::raise(signal);
}

void install(void (*handler)(int), struct sigaction* previous) {
  struct sigaction action {};
  action.sa_handler = handler;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART;  // reads and writes carry on; the loops poll the flag
  for (int i = 0; i < 3; ++i)
    sigaction(kSignals[i], &action, previous != nullptr ? &previous[i] : nullptr);
}

}  // namespace

InterruptScope::InterruptScope() {
  g_signal = 0;
  install(on_interrupt, g_previous);
}

InterruptScope::~InterruptScope() {
  for (int i = 0; i < 3; ++i) sigaction(kSignals[i], &g_previous[i], nullptr);
}

bool InterruptScope::requested() const {
  return g_signal != 0;
}

std::string InterruptScope::signal_name() const {
  switch (g_signal) {
    case SIGINT:
      return "Ctrl-C";
    case SIGTERM:
      return "SIGTERM";
    case SIGHUP:
      return "SIGHUP";
    default:
      return "a signal";
  }
}

void InterruptScope::throw_if_requested() const {
  if (requested()) throw Interrupted(g_signal, signal_name());
}

void install_signal_cleanup() {
  install(on_fatal_signal, nullptr);
}

}  // namespace rostro::app

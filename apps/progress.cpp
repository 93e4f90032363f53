#include "apps/progress.hpp"

#include <unistd.h>

#include <cstdio>

namespace rostro::app {
namespace {

using Clock = std::chrono::steady_clock;
constexpr auto kBarInterval = std::chrono::milliseconds(200);
constexpr auto kLogInterval = std::chrono::seconds(5);

}  // namespace

Progress::Progress(std::string label, long total)
    : label_(std::move(label)),
      total_(total),
      terminal_(isatty(STDERR_FILENO) == 1),
      start_(Clock::now()),
      last_draw_(start_) {}

Progress::~Progress() {
  finish();
}

void Progress::update(long done) {
  done_ = done;
  const auto now = Clock::now();
  if (now - last_draw_ < (terminal_ ? kBarInterval : kLogInterval)) return;
  last_draw_ = now;
  if (terminal_)
    draw_bar();
  else
    log_line();
}

void Progress::update(long done, long total) {
  if (total > 0) total_ = total;
  update(done);
}

void Progress::finish() {
  if (finished_) return;
  finished_ = true;
  if (terminal_) {
    draw_bar();
    std::fputc('\n', stderr);
  } else if (logged_) {
    log_line();  // the end, after the lines that said it was under way
  }
}

void Progress::draw_bar() {
  const double elapsed = std::chrono::duration<double>(Clock::now() - start_).count();
  if (total_ > 0) {
    const double share = static_cast<double>(done_) / static_cast<double>(total_);
    constexpr int kWidth = 30;
    const int filled = static_cast<int>(share * kWidth);
    std::string bar(static_cast<std::size_t>(filled), '#');
    bar.resize(kWidth, '.');
    std::fprintf(stderr, "\r%s [%s] %3.0f%% %ld/%ld %.1fs", label_.c_str(), bar.c_str(),
                 share * 100.0, done_, total_, elapsed);
  } else {
    std::fprintf(stderr, "\r%s %ld %.1fs", label_.c_str(), done_, elapsed);
  }
  std::fflush(stderr);
}

void Progress::log_line() {
  logged_ = true;
  const double elapsed = std::chrono::duration<double>(Clock::now() - start_).count();
  if (total_ > 0)
    std::fprintf(stderr, "%s: %ld/%ld (%.0f%%) after %.0f s\n", label_.c_str(), done_, total_,
                 100.0 * static_cast<double>(done_) / static_cast<double>(total_), elapsed);
  else
    std::fprintf(stderr, "%s: %ld after %.0f s\n", label_.c_str(), done_, elapsed);
  std::fflush(stderr);
}

}  // namespace rostro::app

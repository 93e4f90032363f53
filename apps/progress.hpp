#pragma once
// Progress of long offline work on stderr. On a terminal: a one-line bar redrawn at most a
// few times a second. Redirected (a log, CI, a workflow): a plain line every few seconds, so
// a long run shows it is alive, and nothing at all for work shorter than that.

#include <chrono>
#include <string>

namespace rostro::app {

class Progress {
 public:
  // `total` may be 0 when unknown: then the bar shows a count instead of a percentage.
  Progress(std::string label, long total);
  ~Progress();
  void update(long done);
  // The same, with the total as the work counts it once it runs (a clip with a neutral lead-in
  // is longer than its drive).
  void update(long done, long total);
  void finish();

 private:
  std::string label_;
  long total_;
  long done_ = 0;
  bool terminal_;
  bool finished_ = false;
  bool logged_ = false;  // a plain line was printed (not a terminal)
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_draw_;
  void draw_bar();
  void log_line();
};

}  // namespace rostro::app

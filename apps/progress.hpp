#pragma once
// A one-line progress bar on stderr for long offline work. It draws only when stderr is a
// terminal (logs and CI stay clean) and at most a few times a second.

#include <chrono>
#include <string>

namespace rostro::app {

class Progress {
 public:
  // `total` may be 0 when unknown: then the bar shows a count instead of a percentage.
  Progress(std::string label, long total);
  ~Progress();
  void update(long done);
  void finish();

 private:
  std::string label_;
  long total_;
  long done_ = 0;
  bool enabled_;
  bool finished_ = false;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_draw_;
  void draw();
};

}  // namespace rostro::app

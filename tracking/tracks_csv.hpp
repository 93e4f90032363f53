#pragma once
// The tracks CSV of DESIGN.md, written by `rostro track` and `rostro synth` (ground truth)
// and read by `rostro eval` and `rostro capture`:
//   frame,time_s,marker,fp,x,y,valid,quality
// one row per marker per frame, rows of a frame together, frames in increasing order.
// Details: `fp` is empty for a marker on no MPEG-4 point (a headband tag); `valid` is 0 or 1;
// x and y may be empty on an invalid row; numbers are written in their shortest exact form.
// Lines starting with '#' are comments; "# identification: TEXT" before a frame's rows is
// that frame's TrackedFrame::identification (the markers were identified there, and how
// surely). A CSV reader that skips comments (pandas: comment='#') reads the rows alone.

#include <chrono>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "facecore/atomic_file.hpp"
#include "tracking/tracked_frame.hpp"

namespace rostro::tracking {

// Streams frames out; the file appears at `path` only on finish(). Until then it grows as
// PATH.tmp-PID, handed to the kernel at least once a second, so that a killed process
// leaves every whole row up to its last second (a reader stops at a row cut short after
// handing out every whole frame before it).
class TracksWriter {
 public:
  explicit TracksWriter(const std::filesystem::path& path);
  void write(const TrackedFrame& frame);
  void finish();
  // The same under another name (a take kept after a failure).
  void finish_as(const std::filesystem::path& destination);

 private:
  AtomicFile file_;
  std::chrono::steady_clock::time_point next_flush_;
};

// Streams frames in. Throws InputError naming the file, the line and what was expected.
class TracksReader {
 public:
  explicit TracksReader(const std::filesystem::path& path);
  // Reads `text` from memory; `name` stands for the path in messages.
  TracksReader(std::string name, std::string_view text);
  ~TracksReader();
  // The next frame's rows gathered into one TrackedFrame; false at the end.
  bool next(TrackedFrame& frame);

 private:
  void read_header();
  struct State;
  std::unique_ptr<State> state_;
};

// "3.5", or "" for FeaturePointId{} (a marker that sits on no MPEG-4 point).
std::string feature_point_text(FeaturePointId id);

std::vector<TrackedFrame> read_tracks(const std::filesystem::path& path);
void write_tracks(const std::filesystem::path& path, const std::vector<TrackedFrame>& frames);

}  // namespace rostro::tracking

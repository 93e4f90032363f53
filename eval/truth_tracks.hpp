#pragma once
// Reads ground-truth tracks from either form `rostro eval` accepts: a tracks CSV, or an iBUG
// .pts sequence (a folder of .pts files, a list file naming them, or a single .pts file).

#include <filesystem>
#include <vector>

#include "eval/ibug_pts.hpp"
#include "tracking/tracked_frame.hpp"

namespace rostro::eval {

struct TruthOptions {
  std::filesystem::path pts_mapping;  // empty: data/eval/ibug68_to_mpeg4.json
  long pts_first_frame = 0;           // frame number of the first .pts file
  double pts_fps = 30.0;              // for the time column of .pts truth
};

// True when `path` is read as an iBUG .pts sequence rather than a tracks CSV.
bool is_pts_truth(const std::filesystem::path& path);

// Throws InputError naming the file for anything unreadable.
std::vector<tracking::TrackedFrame> read_truth_tracks(const std::filesystem::path& path,
                                                      const TruthOptions& options = {});

}  // namespace rostro::eval

#pragma once
// Ground truth as an iBUG .pts sequence (300-W / 300-VW annotations): one file per frame,
//   version: 1
//   n_points: 68
//   {
//   x y        (n_points lines, pixels)
//   }
// turned into tracks through a mapping from the 68 iBUG points to rostro markers
// (tracking/ibug_mapping.hpp; data/eval/ibug68_to_mpeg4.json by default).

#include <filesystem>
#include <opencv2/core.hpp>
#include <vector>

#include "tracking/ibug_mapping.hpp"
#include "tracking/tracked_frame.hpp"

namespace rostro::eval {

using tracking::default_ibug_mapping;
using tracking::IbugMapping;
using tracking::IbugMarker;
using tracking::read_ibug_mapping;

// Throws InputError naming the file and line for a malformed file.
std::vector<cv::Point2d> read_pts(const std::filesystem::path& path);

// A folder gives its *.pts files in natural order ("2.pts" before "10.pts"); any other
// file is a list with one .pts path per line (relative to the list's folder; blank lines
// and lines starting with '#' skipped). Throws InputError when nothing is found.
std::vector<std::filesystem::path> list_pts_sequence(const std::filesystem::path& path);

// Reads the sequence as tracks: file k becomes frame first_frame + k at time k / fps, every
// mapped marker visible. Throws InputError when a file has too few points for the mapping.
std::vector<tracking::TrackedFrame> read_pts_sequence(
    const std::vector<std::filesystem::path>& files, const IbugMapping& mapping,
    long first_frame = 0, double fps = 30.0);

// "a2b10" < "a2b9"? No: digit runs compare as numbers, so "frame_2" < "frame_10".
bool natural_less(const std::string& a, const std::string& b);

}  // namespace rostro::eval

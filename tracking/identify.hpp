#pragma once
// Naming the markers at the start of a take, with no clicks: the AprilTags found fix where
// the layout's frontal arrangement lies in the image (a similarity from their corners), the
// detected dots are matched to the layout's dots by proximity, and the mapping is refitted
// as an affine transform from the matches, a few rounds. Without tags the first guess comes
// from the dot cloud's centre and spread (face upright and frontal). The take should start
// with the face frontal and neutral, every marker visible.

#include <map>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "tracking/apriltag_detector.hpp"
#include "tracking/dot_detector.hpp"
#include "tracking/layout.hpp"

namespace rostro::tracking {

struct Identification {
  std::map<std::string, Dot> dots;           // layout id -> the detection it was given
  std::map<std::string, TagDetection> tags;  // layout id -> detection
  cv::Matx23d layout_to_image;               // frontal millimetres -> pixels
  bool mapped = false;                       // false when nothing could be placed

  cv::Point2d project(cv::Point2d frontal_mm) const;
};

// `gate` is the fraction of a dot's distance to its nearest layout neighbour within which a
// detection may be given to it.
Identification identify_markers(const MarkerLayout& layout, const std::vector<Dot>& dots,
                                const std::vector<TagDetection>& tags, double gate = 0.45);

// Starting positions from a file instead: the first frame of a tracks CSV (valid rows only).
std::map<std::string, cv::Point2d> read_start_positions(const std::filesystem::path& path,
                                                        const MarkerLayout& layout);

}  // namespace rostro::tracking

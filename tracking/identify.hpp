#pragma once
// Naming the markers at the start of a take, with no clicks: the AprilTags found fix where
// the layout's frontal arrangement lies in the image (a similarity from their corners), the
// detected dots are matched to the layout's dots by proximity, and the mapping is refitted
// as an affine transform from the matches, a few rounds. Without tags the first guesses come
// from the dot cloud's centre and spread (face upright and frontal) at a range of rolls.
//
// A real face carries many dark blobs beside the dots (pupils, nostrils, lip corners, hair),
// and a blurred frame may show no tag: an arrangement shifted by a row can then explain the
// blobs nearly as well as the right one. So every identification says how sure it is
// (IdentificationConfidence): how many of the layout's dots the fitted arrangement explains
// and how closely, by how much it beats the next-best distinct assignment, and whether the
// tags were read and agree with it. The tracker starts only on a confident frame.
#include <map>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "tracking/apriltag_detector.hpp"
#include "tracking/dot_detector.hpp"
#include "tracking/layout.hpp"

namespace rostro::tracking {

struct IdentificationOptions {
  // The fraction of a dot's distance to its nearest layout neighbour within which a detection
  // may be given to it.
  double gate = 0.45;
  // The layout's dots share one size: a detection more than this factor larger or smaller
  // than the matched detections' median diameter (a pupil, a nostril, a clump of hair) is
  // given to no dot.
  double size_factor = 1.8;
  // A confident identification meets all of these.
  double min_explained = 0.8;  // share of the layout's dots given a detection
  double max_residual = 0.3;   // RMS distance from the fitted arrangement, in dot spacings
  double min_margin = 0.2;     // lead over the next-best distinct assignment (share of its score)
  int min_tags = 2;            // tags read, of a layout with tags (all of them when fewer)
  // A tag agrees when its centre lies within this many tag sides of where the fitted
  // arrangement puts it; arrangements that more than half the tags read disagree with are not
  // considered at all.
  double max_tag_error = 0.5;

  // Throws InputError naming the first option out of range.
  void validate() const;
};

struct IdentificationConfidence {
  int dots = 0;         // the layout's dots
  int matched = 0;      // given a detection
  double residual = 0;  // RMS distance of the matched from the fitted arrangement, in spacings
  double margin = 0;    // 1 - (next-best distinct assignment's score / this one's); 1: no rival
  int tags = 0;         // the layout's tags
  int tags_seen = 0;    // read in the image
  int tags_agreeing = 0;
  bool confident = false;
  std::string doubt;  // why not confident, in words ("1 of 3 tags read"); empty when confident
};

// "29/31 dots, residual 0.06, margin 0.71, tags 3/3 read, 3 agree"
std::string describe(const IdentificationConfidence& confidence);

struct Identification {
  std::map<std::string, Dot> dots;           // layout id -> the detection it was given
  std::map<std::string, TagDetection> tags;  // layout id -> detection
  cv::Matx23d layout_to_image;               // frontal millimetres -> pixels
  bool mapped = false;                       // false when nothing could be placed
  IdentificationConfidence confidence;

  cv::Point2d project(cv::Point2d frontal_mm) const;
};

Identification identify_markers(const MarkerLayout& layout, const std::vector<Dot>& dots,
                                const std::vector<TagDetection>& tags,
                                const IdentificationOptions& options = {});

// Starting positions from a file instead: the first frame of a tracks CSV (valid rows only).
std::map<std::string, cv::Point2d> read_start_positions(const std::filesystem::path& path,
                                                        const MarkerLayout& layout);

}  // namespace rostro::tracking

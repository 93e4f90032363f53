#pragma once
// The 68 iBUG 300-W landmarks (what dlib's shape predictor and the 300-VW annotations give)
// named by MPEG-4 feature point. data/eval/ibug68_to_mpeg4.json is the default mapping:
//   {"index_base": 1, "markers": [{"marker": "3.7", "fp": "3.7", "ibug": [46]}, ...]}
// A marker may average several iBUG points ("ibug": [38, 39] is the midpoint of 38 and 39).
// "marker" is optional and defaults to the feature point's name. The same mapping names the
// landmark tracker's observations and reads .pts ground truth, so the two compare directly.

#include <filesystem>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "facecore/fapu.hpp"
#include "tracking/layout.hpp"

namespace rostro::tracking {

struct IbugMarker {
  std::string marker;
  FeaturePointId feature_point;
  std::vector<int> points;  // 0-based iBUG indices, averaged
};

struct IbugMapping {
  int point_count = 68;  // the largest index + 1 any entry needs
  std::vector<IbugMarker> markers;
};

// Throws InputError naming the file and the entry for anything malformed.
IbugMapping read_ibug_mapping(const std::filesystem::path& path);
// data/eval/ibug68_to_mpeg4.json.
IbugMapping default_ibug_mapping();

// The mapped position of `marker` from a full set of landmarks (the mean of its points).
cv::Point2d mapped_position(const IbugMarker& marker, const std::vector<cv::Point2d>& landmarks);

// The mapping as a layout of MarkerKind::Landmark markers, for calibration and the fit: each
// at its feature point on `neutral` (a neutral face in mm, x to the face's left, y up, z out),
// moved so the nose tip (9.3) is the origin as layouts have it. Throws InputError when
// `neutral` lacks one of the mapping's feature points.
MarkerLayout landmark_layout(const IbugMapping& mapping, const FeaturePointPositions& neutral);

}  // namespace rostro::tracking

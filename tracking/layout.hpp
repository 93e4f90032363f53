#pragma once
// A marker layout: which markers the actor wears, where on the face, and how they look.
// JSON (data/layouts/default.json is the reference):
//   { "name": ..., "description": ...,
//     "dot": { "diameter_mm": 4, "polarity": "dark" | "bright" },
//     "markers": [
//       { "id": "brow_l_in", "type": "dot", "fp": "4.1", "position": [15, 52, -20] },
//       { "id": "lid_l_up", "type": "dot", "fp": "3.1", "beside": [0, 4], ... },
//       { "type": "apriltag", "family": "tag36h11", "tag_id": 0, "size_mm": 20,
//         "rigid": true, "position": [0, 92, -12], "rotation_deg": 0 } ] }
// Positions are the markers' nominal neutral places in millimetres on a frontal face: origin
// at the nose tip, x toward the face's own left (the viewer's right in an unmirrored
// camera), y up, z toward the camera. Identification uses (x, y) as the frontal arrangement.
// "beside" (dots, optional): the dot is painted this far from its feature point on the skin
// (x, y in millimetres, the same axes), where the point lies on a line of the face a dot cannot
// sit on: the lid margins with their lashes, the eye corners. "position" stays the point's:
// identification and the tracker's eye rules read the arrangement of the points (moved to the
// dots' places, the rendered head's suite failed on 31 % of its frames). Calibration takes the
// face prior's shape and motion at the dot's own place, and the FAPU at the point.

#include <filesystem>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "facecore/feature_point.hpp"

namespace rostro::tracking {

// Landmark: a point a face landmark model finds on a bare face (tracking/ibug_mapping.hpp),
// not something the actor wears; landmark layouts are built in code, not read from JSON.
enum class MarkerKind { Dot, AprilTag, Landmark };
enum class DotPolarity { Dark, Bright };

struct MarkerSpec {
  std::string id;  // dots: the layout's label; tags: "<family>:<tag_id>"
  MarkerKind kind = MarkerKind::Dot;
  FeaturePointId feature_point;          // {} when the marker sits on no MPEG-4 point
  bool rigid = false;                    // moves only with the skull: head pose, not FAPs
  cv::Point3d position_mm;               // nominal neutral position (see above)
  std::optional<cv::Point2d> beside_mm;  // dots: where from its feature point it is painted
  // AprilTags only.
  std::string family;  // "tag36h11"
  int tag_id = -1;
  double size_mm = 0;       // edge of the black square (libapriltag's tag size)
  double rotation_deg = 0;  // in-plane turn of the printed tag, counter-clockwise

  bool is_tag() const { return kind == MarkerKind::AprilTag; }
  // The frontal-plane position in "image-like" axes (x right, y down), millimetres.
  cv::Point2d frontal() const { return {position_mm.x, -position_mm.y}; }
  // The tag's corners in the same frontal axes, in libapriltag's corner order.
  std::vector<cv::Point2d> tag_corners_frontal() const;
};

struct MarkerLayout {
  std::string name;
  std::string description;
  double dot_diameter_mm = 4;
  DotPolarity polarity = DotPolarity::Dark;
  std::vector<MarkerSpec> markers;

  const MarkerSpec* find(const std::string& id) const;
  std::vector<std::string> tag_families() const;  // distinct, in layout order
  int dot_count() const;
  int tag_count() const;
};

// Throws InputError naming the file and the marker at fault.
MarkerLayout load_layout(const std::filesystem::path& path);
MarkerLayout parse_layout(const std::string& json_text, const std::string& source_name);
// data/layouts/default.json
std::filesystem::path default_layout_path();

}  // namespace rostro::tracking

#include "tracking/layout.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <set>
#include <sstream>

#include "facecore/data_path.hpp"
#include "facecore/error.hpp"
#include "facecore/json_file.hpp"

namespace rostro::tracking {
namespace {

using nlohmann::json;

const std::set<std::string> kFamilies = {"tag36h11", "tag25h9", "tag16h5", "tagStandard41h12",
                                         "tagCircle21h7"};

[[noreturn]] void fail(const std::string& source, const std::string& what) {
  throw InputError(where(source, 0, what));
}

double number_at(const json& j, const char* key, const std::string& source,
                 const std::string& context) {
  if (!j.contains(key) || !j[key].is_number())
    fail(source, context + ": '" + key + "' should be a number");
  return j[key].get<double>();
}

MarkerSpec parse_marker(const json& m, size_t index, const std::string& source) {
  std::string context = "marker " + std::to_string(index + 1);
  if (!m.is_object()) fail(source, context + " should be an object");
  MarkerSpec spec;
  const std::string here = source + ": " + context;
  std::string type = json_string_or(m, "type", "dot", here);
  if (type == "dot") {
    spec.kind = MarkerKind::Dot;
    if (!m.contains("id") || !m["id"].is_string() || m["id"].get<std::string>().empty())
      fail(source, context + ": a dot needs a non-empty string 'id'");
    spec.id = m["id"].get<std::string>();
    if (spec.id.find_first_of(",:\"\n") != std::string::npos)
      fail(source, context + ": dot id '" + spec.id + "' may not hold ',', ':' or quotes");
  } else if (type == "apriltag") {
    spec.kind = MarkerKind::AprilTag;
    spec.family = json_string_or(m, "family", "tag36h11", here);
    if (!kFamilies.count(spec.family))
      fail(source, context + ": unknown AprilTag family '" + spec.family + "'");
    if (!m.contains("tag_id"))
      fail(source, context + ": an AprilTag needs a non-negative integer 'tag_id'");
    spec.tag_id = static_cast<int>(json_integer(m, "tag_id", 0, 1 << 20, here));
    spec.id = spec.family + ":" + std::to_string(spec.tag_id);
    if (m.contains("id") && m["id"] != spec.id)
      fail(source, context + ": an AprilTag's id is '" + spec.id + "', not " + m["id"].dump());
    spec.size_mm = number_at(m, "size_mm", source, context);
    if (spec.size_mm <= 0) fail(source, context + ": 'size_mm' should be positive");
    spec.rotation_deg = json_number_or(m, "rotation_deg", 0.0, here);
  } else {
    fail(source, context + ": 'type' should be \"dot\" or \"apriltag\", not '" + type + "'");
  }
  context = "marker '" + spec.id + "'";
  if (m.contains("fp") && !m["fp"].is_null()) {
    if (!m["fp"].is_string()) fail(source, context + ": 'fp' should be a string like \"4.1\"");
    auto fp = parse_feature_point(m["fp"].get<std::string>());
    if (!fp) fail(source, context + ": unknown feature point '" + m["fp"].get<std::string>() + "'");
    spec.feature_point = *fp;
  } else if (spec.kind == MarkerKind::Dot) {
    fail(source, context + ": a dot needs the feature point 'fp' it sits on");
  }
  spec.rigid = json_bool_or(m, "rigid", spec.kind == MarkerKind::AprilTag, source + ": " + context);
  if (!m.contains("position") || !m["position"].is_array() || m["position"].size() != 3)
    fail(source, context + ": 'position' should be [x, y, z] in millimetres");
  for (const auto& v : m["position"])
    if (!v.is_number()) fail(source, context + ": 'position' should hold three numbers");
  spec.position_mm = {m["position"][0].get<double>(), m["position"][1].get<double>(),
                      m["position"][2].get<double>()};
  if (m.contains("beside")) {
    const auto& b = m["beside"];
    if (spec.kind != MarkerKind::Dot)
      fail(source, context + ": only a dot can sit 'beside' its point");
    if (!b.is_array() || b.size() != 2 || !b[0].is_number() || !b[1].is_number())
      fail(source, context + ": 'beside' should be [x, y] in millimetres");
    spec.beside_mm = cv::Point2d(b[0].get<double>(), b[1].get<double>());
    if (!(cv::norm(*spec.beside_mm) <= 20))
      fail(source, context + ": 'beside' should be within 20 mm of the feature point");
  }
  return spec;
}

}  // namespace

std::vector<cv::Point2d> MarkerSpec::tag_corners_frontal() const {
  // libapriltag's order on an upright tag seen in an image (y down): bottom-left,
  // bottom-right, top-right, top-left.
  const double h = size_mm / 2;
  const cv::Point2d local[4] = {{-h, h}, {h, h}, {h, -h}, {-h, -h}};
  // Counter-clockwise as the viewer sees it is clockwise in y-down axes.
  const double a = -rotation_deg * std::numbers::pi / 180;
  const double c = std::cos(a), s = std::sin(a);
  std::vector<cv::Point2d> out;
  for (const cv::Point2d& p : local)
    out.push_back(frontal() + cv::Point2d(c * p.x - s * p.y, s * p.x + c * p.y));
  return out;
}

const MarkerSpec* MarkerLayout::find(const std::string& id) const {
  for (const MarkerSpec& m : markers)
    if (m.id == id) return &m;
  return nullptr;
}

std::vector<std::string> MarkerLayout::tag_families() const {
  std::vector<std::string> out;
  for (const MarkerSpec& m : markers)
    if (m.is_tag() && std::find(out.begin(), out.end(), m.family) == out.end())
      out.push_back(m.family);
  return out;
}

int MarkerLayout::dot_count() const {
  return static_cast<int>(std::count_if(markers.begin(), markers.end(), [](const MarkerSpec& m) {
    return m.kind == MarkerKind::Dot;
  }));
}

int MarkerLayout::tag_count() const {
  return static_cast<int>(std::count_if(markers.begin(), markers.end(),
                                        [](const MarkerSpec& m) { return m.is_tag(); }));
}

MarkerLayout parse_layout(const std::string& json_text, const std::string& source_name) {
  json j;
  try {
    j = json::parse(json_text);
  } catch (const json::exception& e) {  // parse_error, or out_of_range for a number
    fail(source_name, std::string("not valid JSON: ") + e.what());
  }
  if (!j.is_object()) fail(source_name, "a layout should be a JSON object");
  MarkerLayout layout;
  layout.name = json_string_or(j, "name", "", source_name);
  layout.description = json_string_or(j, "description", "", source_name);
  if (j.contains("dot")) {
    const json& d = j["dot"];
    if (!d.is_object()) fail(source_name, "'dot' should be an object");
    layout.dot_diameter_mm =
        json_number_or(d, "diameter_mm", layout.dot_diameter_mm, source_name + ": dot");
    if (layout.dot_diameter_mm <= 0) fail(source_name, "dot 'diameter_mm' should be positive");
    std::string polarity = json_string_or(d, "polarity", "dark", source_name + ": dot");
    if (polarity == "dark")
      layout.polarity = DotPolarity::Dark;
    else if (polarity == "bright")
      layout.polarity = DotPolarity::Bright;
    else
      fail(source_name, "dot 'polarity' should be \"dark\" or \"bright\", not '" + polarity + "'");
  }
  if (!j.contains("markers") || !j["markers"].is_array() || j["markers"].empty())
    fail(source_name, "'markers' should be a non-empty array");
  std::set<std::string> ids;
  for (size_t i = 0; i < j["markers"].size(); ++i) {
    MarkerSpec spec = parse_marker(j["markers"][i], i, source_name);
    if (!ids.insert(spec.id).second) fail(source_name, "marker '" + spec.id + "' appears twice");
    layout.markers.push_back(std::move(spec));
  }
  return layout;
}

MarkerLayout load_layout(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw InputError(where(path.string(), 0, "cannot open the marker layout"));
  std::stringstream text;
  text << in.rdbuf();
  return parse_layout(text.str(), path.string());
}

std::filesystem::path default_layout_path() {
  return data_file("layouts/default.json");
}

}  // namespace rostro::tracking

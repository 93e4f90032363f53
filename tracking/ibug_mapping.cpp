#include "tracking/ibug_mapping.hpp"

#include <algorithm>
#include <nlohmann/json.hpp>

#include "facecore/data_path.hpp"
#include "facecore/error.hpp"
#include "facecore/json_file.hpp"

namespace rostro::tracking {

IbugMapping read_ibug_mapping(const std::filesystem::path& path) {
  const std::string name = path.string();
  const nlohmann::json j = read_json_file(path, "the iBUG mapping");
  if (!j.is_object() || !j.contains("markers") || !j["markers"].is_array())
    throw InputError(name + ": expected an object with a \"markers\" array");
  const int base = j.value("index_base", 1);
  if (base != 0 && base != 1) throw InputError(name + ": \"index_base\" must be 0 or 1");

  IbugMapping mapping;
  mapping.point_count = 0;
  std::size_t n = 0;
  for (const auto& entry : j["markers"]) {
    const std::string at = name + ": markers[" + std::to_string(n++) + "]";
    if (!entry.is_object() || !entry.contains("fp") || !entry["fp"].is_string() ||
        !entry.contains("ibug") || !entry["ibug"].is_array() || entry["ibug"].empty())
      throw InputError(at + ": expected {\"fp\": \"3.7\", \"ibug\": [46]}");
    IbugMarker m;
    const auto fp = parse_feature_point(entry["fp"].get<std::string>());
    if (!fp)
      throw InputError(at + ": '" + entry["fp"].get<std::string>() +
                       "' is not an MPEG-4 feature point");
    m.feature_point = *fp;
    m.marker = entry.contains("marker") && entry["marker"].is_string()
                   ? entry["marker"].get<std::string>()
                   : fp->str();
    for (const auto& index : entry["ibug"]) {
      if (!index.is_number_integer() || index.get<int>() < base)
        throw InputError(at + ": iBUG indices must be integers from " + std::to_string(base));
      m.points.push_back(index.get<int>() - base);
      mapping.point_count = std::max(mapping.point_count, m.points.back() + 1);
    }
    mapping.markers.push_back(std::move(m));
  }
  if (mapping.markers.empty()) throw InputError(name + ": the \"markers\" array is empty");
  return mapping;
}

IbugMapping default_ibug_mapping() {
  return read_ibug_mapping(data_file("eval/ibug68_to_mpeg4.json"));
}

cv::Point2d mapped_position(const IbugMarker& marker, const std::vector<cv::Point2d>& landmarks) {
  cv::Point2d sum(0, 0);
  for (int i : marker.points) sum += landmarks.at(static_cast<std::size_t>(i));
  return sum / static_cast<double>(marker.points.size());
}

MarkerLayout landmark_layout(const IbugMapping& mapping, const FeaturePointPositions& neutral) {
  const auto nose = neutral.find(*parse_feature_point("9.3"));
  const Eigen::Vector3d origin = nose != neutral.end() ? nose->second : Eigen::Vector3d::Zero();
  MarkerLayout layout;
  layout.name = "ibug68";
  layout.description = "the 68 iBUG landmarks of a bare face, named by MPEG-4 feature point";
  for (const IbugMarker& m : mapping.markers) {
    const auto at = neutral.find(m.feature_point);
    if (at == neutral.end())
      throw InputError("landmark layout: the neutral face has no feature point " +
                       m.feature_point.str() + " (marker " + m.marker + ")");
    const Eigen::Vector3d p = at->second - origin;
    MarkerSpec spec;
    spec.id = m.marker;
    spec.kind = MarkerKind::Landmark;
    spec.feature_point = m.feature_point;
    spec.position_mm = {p.x(), p.y(), p.z()};
    layout.markers.push_back(std::move(spec));
  }
  return layout;
}

}  // namespace rostro::tracking

#include "mapping/seed2d_mapper.hpp"

#include <cmath>

#include "facecore/error.hpp"
#include "mapping/marker_model.hpp"

namespace rostro::mapping {

Seed2dMapper::Seed2dMapper(const calib::ActorProfile& profile) : profile_(profile) {
  const calib::NeutralMarker* nose = nullptr;
  for (const auto& m : profile.markers)
    if (m.feature_point == FeaturePointId{9, 3}) nose = &m;
  if (!nose)
    throw InputError("seed2d: actor profile '" + profile.name +
                     "' has no nose-tip (9.3) marker, the method's reference point");
  reference_ = nose->marker;
  for (const auto& m : profile.markers) {
    if (m.marker == reference_) continue;  // the reference cannot move relative to itself
    Marker s{m.marker, m.image - nose->image, faps_moving(m.feature_point, false)};
    if (!s.faps.empty()) markers_.push_back(std::move(s));
  }
}

FapFrame Seed2dMapper::map(const tracking::TrackedFrame& frame) const {
  FapFrame out;
  out.index = frame.frame;
  out.time_s = frame.time_s;
  auto find = [&](const std::string& id) -> const tracking::MarkerObservation* {
    for (const auto& o : frame.markers)
      if (o.marker == id && o.valid && std::isfinite(o.position.x) && std::isfinite(o.position.y))
        return &o;
    return nullptr;
  };
  const auto* nose = find(reference_);
  if (!nose) return out;
  for (const Marker& m : markers_) {
    const auto* o = find(m.id);
    if (!o) continue;
    const cv::Point2d d = (o->position - nose->position) - m.neutral_offset;
    const double face_x = d.x, face_y = -d.y;
    for (int id : m.faps) {
      const FapInfo& info = fap_info(id);
      const auto axis = fap_axis(info);
      const double unit = profile_.fapu_image.unit_size(info.unit);
      if (unit <= 0) continue;
      double value = (axis[0] * face_x + axis[1] * face_y) / unit;
      if (!info.bidirectional && value < 0) value = 0;  // unidirectional FAPs are never negative
      out.set(id, profile_.apply_gain(id, value));
    }
  }
  return out;
}

}  // namespace rostro::mapping

#include "mapping/marker_model.hpp"

#include <algorithm>
#include <sstream>

#include "facecore/error.hpp"
#include "facecore/fap_table.hpp"

namespace rostro::mapping {

std::vector<int> faps_moving(FeaturePointId fp, bool include_depth) {
  std::vector<int> out;
  const std::string name = fp.str();
  for (const FapInfo& fap : fap_table()) {
    if (fap.feature_point != name) continue;
    const auto axis = fap_axis(fap);
    if (axis[0] == 0 && axis[1] == 0 && (axis[2] == 0 || !include_depth)) continue;
    out.push_back(fap.id);
  }
  return out;
}

MarkerModel build_marker_model(const calib::ActorProfile& profile,
                               const MarkerModelOptions& options) {
  MarkerModel model;
  std::set<int> faps;
  for (const calib::NeutralMarker& m : profile.markers) {
    if (!m.position) continue;
    ModelMarker mm{m.marker, m.feature_point, *m.position, {}};
    const std::vector<int> moving =
        m.rigid ? std::vector<int>{} : faps_moving(m.feature_point, options.fit_depth_faps);
    for (int id : moving) {
      if (options.excluded_faps.count(id)) continue;
      const FapInfo& info = fap_info(id);
      const auto axis = fap_axis(info);
      const double unit = profile.fapu.unit_size(info.unit);
      mm.faps.push_back({id, Eigen::Vector3d(axis[0], axis[1], axis[2]) * unit});
      faps.insert(id);
    }
    model.markers.push_back(std::move(mm));
  }
  if (model.markers.empty())
    throw InputError("actor profile '" + profile.name +
                     "': no marker has a 3D neutral position (recalibrate the actor)");
  model.faps.assign(faps.begin(), faps.end());
  return model;
}

}  // namespace rostro::mapping

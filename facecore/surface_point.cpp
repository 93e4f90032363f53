#include "facecore/surface_point.hpp"

#include <algorithm>
#include <iterator>
#include <limits>

namespace rostro {

SurfacePoint SurfacePoint::at_vertex(int vertex) {
  SurfacePoint p;
  p.vertices = {vertex, -1, -1};
  p.weights = Eigen::Vector3f(1, 0, 0);
  return p;
}

Eigen::Vector3f SurfacePoint::on(const std::vector<Eigen::Vector3f>& per_vertex) const {
  Eigen::Vector3f sum = Eigen::Vector3f::Zero();
  for (std::size_t k = 0; k < 3; ++k)
    if (vertices[k] >= 0)
      sum +=
          weights[static_cast<Eigen::Index>(k)] * per_vertex[static_cast<std::size_t>(vertices[k])];
  return sum;
}

std::optional<SurfacePoint> front_skin_point(const FaceModel& model, double x, double y) {
  const auto named = std::find(model.materials.begin(), model.materials.end(), "skin");
  const int skin = named == model.materials.end()
                       ? -1
                       : static_cast<int>(std::distance(model.materials.begin(), named));
  const auto px = static_cast<float>(x), py = static_cast<float>(y);
  std::optional<SurfacePoint> best;
  float best_z = -std::numeric_limits<float>::max();
  for (std::size_t t = 0; t < model.triangles.size(); ++t) {
    if (skin >= 0 && t < model.triangle_materials.size() && model.triangle_materials[t] != skin)
      continue;
    const Eigen::Vector3i& tri = model.triangles[t];
    const Eigen::Vector3f& a = model.positions[static_cast<std::size_t>(tri[0])];
    const Eigen::Vector3f& b = model.positions[static_cast<std::size_t>(tri[1])];
    const Eigen::Vector3f& c = model.positions[static_cast<std::size_t>(tri[2])];
    // Twice the signed area seen from the front: positive when the triangle faces the viewer.
    const float area = (b.x() - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (b.y() - a.y());
    if (!(area > 0)) continue;
    const float wb = ((px - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (py - a.y())) / area;
    const float wc = ((b.x() - a.x()) * (py - a.y()) - (px - a.x()) * (b.y() - a.y())) / area;
    const float wa = 1 - wb - wc;
    if (wa < 0 || wb < 0 || wc < 0) continue;
    const float z = wa * a.z() + wb * b.z() + wc * c.z();
    if (z <= best_z) continue;
    best_z = z;
    best = SurfacePoint{{tri[0], tri[1], tri[2]}, Eigen::Vector3f(wa, wb, wc)};
  }
  return best;
}

}  // namespace rostro

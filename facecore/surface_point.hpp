#pragma once
// A point on a face model's surface between its vertices: a triangle's three vertices and
// their weights, so that it moves with the deformed mesh. Used to place what sits beside a
// feature point rather than on its vertex (a painted dot beside the lashes).

#include <Eigen/Core>
#include <array>
#include <optional>
#include <vector>

#include "facecore/face_model.hpp"

namespace rostro {

struct SurfacePoint {
  std::array<int, 3> vertices{-1, -1, -1};
  Eigen::Vector3f weights = Eigen::Vector3f::Zero();

  // The point on a vertex itself.
  static SurfacePoint at_vertex(int vertex);
  // Its place (or any per-vertex value, e.g. normals) on a mesh of the model.
  Eigen::Vector3f on(const std::vector<Eigen::Vector3f>& per_vertex) const;
};

// The skin seen at (x, y) from the front (along -z, model millimetres): the front-facing
// triangle of the "skin" material (any material when the model names none) nearest the viewer
// over that point; nullopt where there is none.
std::optional<SurfacePoint> front_skin_point(const FaceModel& model, double x, double y);

}  // namespace rostro

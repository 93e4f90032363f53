#include "render/render_mesh.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace rostro::render {

std::array<float, 3> Bounds::center() const {
  return {(min[0] + max[0]) / 2, (min[1] + max[1]) / 2, (min[2] + max[2]) / 2};
}

std::array<float, 3> Bounds::size() const {
  return {max[0] - min[0], max[1] - min[1], max[2] - min[2]};
}

void validate(const RenderMesh& mesh) {
  if (mesh.positions.empty() || mesh.positions.size() % 3 != 0) {
    throw std::invalid_argument("render mesh: positions must be a non-empty list of x, y, z");
  }
  if (mesh.colors.size() != mesh.positions.size()) {
    throw std::invalid_argument("render mesh: " + std::to_string(mesh.colors.size() / 3) +
                                " colours for " + std::to_string(mesh.vertex_count()) +
                                " vertices");
  }
  if (!mesh.texcoords.empty() && mesh.texcoords.size() != 2 * mesh.vertex_count()) {
    throw std::invalid_argument("render mesh: " + std::to_string(mesh.texcoords.size() / 2) +
                                " texture coordinates for " + std::to_string(mesh.vertex_count()) +
                                " vertices");
  }
  if (!mesh.texcoords.empty() &&
      (mesh.texture.width <= 0 || mesh.texture.height <= 0 ||
       mesh.texture.rgb.size() != 3 * static_cast<std::size_t>(mesh.texture.width) *
                                      static_cast<std::size_t>(mesh.texture.height))) {
    throw std::invalid_argument("render mesh: texture coordinates without a whole RGB texture");
  }
  if (mesh.triangles.size() % 3 != 0) {
    throw std::invalid_argument("render mesh: triangle index count is not a multiple of 3");
  }
  const auto n = mesh.vertex_count();
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    if (mesh.triangles[i] >= n) {
      throw std::invalid_argument("render mesh: triangle " + std::to_string(i / 3) +
                                  " uses vertex " + std::to_string(mesh.triangles[i]) +
                                  ", the mesh has " + std::to_string(n));
    }
  }
}

Bounds bounds_of(std::span<const float> positions) {
  Bounds b;
  if (positions.size() < 3) return b;
  constexpr float inf = std::numeric_limits<float>::infinity();
  b.min = {inf, inf, inf};
  b.max = {-inf, -inf, -inf};
  for (std::size_t i = 0; i + 2 < positions.size(); i += 3) {
    for (std::size_t k = 0; k < 3; ++k) {
      b.min[k] = std::min(b.min[k], positions[i + k]);
      b.max[k] = std::max(b.max[k], positions[i + k]);
    }
  }
  return b;
}

void compute_vertex_normals(std::span<const float> positions,
                            std::span<const std::uint32_t> triangles, std::vector<float>& normals) {
  normals.assign(positions.size(), 0.0f);
  for (std::size_t t = 0; t + 2 < triangles.size(); t += 3) {
    const std::size_t a = 3 * std::size_t{triangles[t]};
    const std::size_t b = 3 * std::size_t{triangles[t + 1]};
    const std::size_t c = 3 * std::size_t{triangles[t + 2]};
    const float e1[3] = {positions[b] - positions[a], positions[b + 1] - positions[a + 1],
                         positions[b + 2] - positions[a + 2]};
    const float e2[3] = {positions[c] - positions[a], positions[c + 1] - positions[a + 1],
                         positions[c + 2] - positions[a + 2]};
    // The unnormalised cross product weights each face by its area.
    const float n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                        e1[0] * e2[1] - e1[1] * e2[0]};
    for (const std::size_t v : {a, b, c}) {
      normals[v] += n[0];
      normals[v + 1] += n[1];
      normals[v + 2] += n[2];
    }
  }
  for (std::size_t v = 0; v + 2 < normals.size(); v += 3) {
    const float len = std::sqrt(normals[v] * normals[v] + normals[v + 1] * normals[v + 1] +
                                normals[v + 2] * normals[v + 2]);
    if (len > 0.0f) {
      normals[v] /= len;
      normals[v + 1] /= len;
      normals[v + 2] /= len;
    } else {
      normals[v] = 0.0f;
      normals[v + 1] = 0.0f;
      normals[v + 2] = 1.0f;
    }
  }
}

}  // namespace rostro::render

#pragma once
// Small meshes for renderer tests that need no face model: a coloured ellipsoid.

#include <cmath>
#include <numbers>

#include "render/render_mesh.hpp"

namespace rostro::render::testing {

// An ellipsoid centred at the origin with radii (rx, ry, rz), skin-coloured, with its lower
// half (y < 0) in `lower` colour so tests can tell the halves apart.
inline RenderMesh make_ellipsoid(float rx, float ry, float rz, int rings = 24, int segments = 32,
                                 std::array<float, 3> upper = {0.85f, 0.65f, 0.55f},
                                 std::array<float, 3> lower = {0.85f, 0.65f, 0.55f}) {
  RenderMesh mesh;
  const float pi = std::numbers::pi_v<float>;
  for (int r = 0; r <= rings; ++r) {
    const float theta = pi * static_cast<float>(r) / static_cast<float>(rings);  // 0 at the top
    for (int s = 0; s < segments; ++s) {
      const float phi = 2.0f * pi * static_cast<float>(s) / static_cast<float>(segments);
      const float y = ry * std::cos(theta);
      mesh.positions.insert(mesh.positions.end(), {rx * std::sin(theta) * std::sin(phi), y,
                                                   rz * std::sin(theta) * std::cos(phi)});
      const auto& c = y >= 0.0f ? upper : lower;
      mesh.colors.insert(mesh.colors.end(), c.begin(), c.end());
    }
  }
  const auto index = [&](int r, int s) {
    return static_cast<std::uint32_t>(r * segments + (s % segments));
  };
  for (int r = 0; r < rings; ++r) {
    for (int s = 0; s < segments; ++s) {
      mesh.triangles.insert(mesh.triangles.end(),
                            {index(r, s), index(r + 1, s), index(r + 1, s + 1)});
      mesh.triangles.insert(mesh.triangles.end(),
                            {index(r, s), index(r + 1, s + 1), index(r, s + 1)});
    }
  }
  return mesh;
}

}  // namespace rostro::render::testing

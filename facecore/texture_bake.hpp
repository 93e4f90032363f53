#pragma once
// Painting a texture from a colour function of the surface: each texel inside a textured
// triangle (in texture space) takes the colour of the point of the mesh it shows. Used by the
// head generator, whose skin colours (brows, lips, lash lines, hairline) are functions of
// where on the head a point lies.

#include <Eigen/Core>
#include <functional>
#include <vector>

#include "facecore/face_model.hpp"
#include "facecore/texture.hpp"

namespace rostro {

// A texel's place on the mesh: the point it shows (the neutral mesh, interpolated over its
// triangle) and its texture coordinates (u continued past 1 on triangles across u = 0).
struct TexelPoint {
  Eigen::Vector3d position;
  Eigen::Vector2d uv;
};

// A `width` x `height` texture over `triangles` (indices into model.triangles whose corners all
// have texture coordinates). Texels no triangle covers take the nearest covered texel's colour
// along rows, then columns, so that filtering at an island's edge blends nothing foreign in.
Texture bake_texture(const FaceModel& model, const std::vector<int>& triangles, int width,
                     int height, const std::function<Eigen::Vector3f(const TexelPoint&)>& colour);

// The texture's colour at (u, v) (u wraps, v clamps; v up), bilinear, in 0..1.
Eigen::Vector3f sample_texture(const Texture& texture, const Eigen::Vector2f& uv);

}  // namespace rostro

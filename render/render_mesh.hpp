#pragma once
// The renderer's narrow input: a triangle mesh with one colour per vertex and, optionally, a
// texture the textured vertices show instead. Positions change every frame (the deformer moves
// them); colours, texture and triangles are fixed per model.
// Units are whatever the model uses; the camera frames the mesh from its bounding box.

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "facecore/texture.hpp"

namespace rostro::render {

struct RenderMesh {
  std::vector<float> positions;          // x, y, z per vertex (face frame: x left, y up, z out)
  std::vector<float> colors;             // r, g, b per vertex, 0..1
  std::vector<std::uint32_t> triangles;  // three vertex indices per triangle, counter-clockwise
  // u, v per vertex into `texture` (v up, u wraps around); NaN: the vertex shows its colour.
  // Empty: no vertex is textured.
  std::vector<float> texcoords;
  Texture texture;

  std::size_t vertex_count() const { return positions.size() / 3; }
  std::size_t triangle_count() const { return triangles.size() / 3; }
};

struct Bounds {
  std::array<float, 3> min{0, 0, 0};
  std::array<float, 3> max{0, 0, 0};
  std::array<float, 3> center() const;
  std::array<float, 3> size() const;
};

// Throws std::invalid_argument when sizes disagree, an index is out of range or texture
// coordinates come without a texture.
void validate(const RenderMesh& mesh);

Bounds bounds_of(std::span<const float> positions);

// Area-weighted vertex normals (x, y, z per vertex), recomputed each frame after deformation.
// Vertices used by no triangle get (0, 0, 1).
void compute_vertex_normals(std::span<const float> positions,
                            std::span<const std::uint32_t> triangles, std::vector<float>& normals);

}  // namespace rostro::render

#pragma once
// Reading and writing the Wavefront OBJ subset face models use: `v x y z [r g b]`,
// `vt u v`, `f a b c ...` (also a/b/c forms and negative indices; polygons are fanned into
// triangles) and `usemtl name` for per-triangle materials. Other records are ignored.
// Texture coordinates are kept per vertex (the first a face gives it, u wrapped into 0..1).

#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

namespace rostro {

struct ObjMesh {
  std::vector<Eigen::Vector3f> positions;
  std::vector<Eigen::Vector3f> colors;     // empty unless every vertex has a colour
  std::vector<Eigen::Vector2f> texcoords;  // per vertex, NaN where no face gives one; empty: none
  std::vector<Eigen::Vector3i> triangles;
  std::vector<std::string> materials;
  std::vector<int> triangle_materials;  // empty when the file has no usemtl
};

// Throws InputError naming the file and line for malformed records.
ObjMesh read_obj(const std::filesystem::path& path);

// Writes atomically; colours and texture coordinates are written when present (a face across
// u = 0 gets coordinates past 1, so that other programs take the short way too).
void write_obj(const ObjMesh& mesh, const std::filesystem::path& path);

}  // namespace rostro

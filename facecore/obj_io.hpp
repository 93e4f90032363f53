#pragma once
// Reading and writing the Wavefront OBJ subset face models use: `v x y z [r g b]`,
// `f a b c ...` (also a/b/c forms and negative indices; polygons are fanned into
// triangles) and `usemtl name` for per-triangle materials. Other records are ignored.

#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

namespace rostro {

struct ObjMesh {
  std::vector<Eigen::Vector3f> positions;
  std::vector<Eigen::Vector3f> colors;  // empty unless every vertex has a colour
  std::vector<Eigen::Vector3i> triangles;
  std::vector<std::string> materials;
  std::vector<int> triangle_materials;  // empty when the file has no usemtl
};

// Throws InputError naming the file and line for malformed records.
ObjMesh read_obj(const std::filesystem::path& path);

// Writes atomically; colours are written when present.
void write_obj(const ObjMesh& mesh, const std::filesystem::path& path);

}  // namespace rostro

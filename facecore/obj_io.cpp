#include "facecore/obj_io.hpp"

#include <fmt/format.h>

#include <charconv>
#include <fstream>
#include <map>
#include <sstream>

#include "facecore/atomic_file.hpp"
#include "facecore/error.hpp"

namespace rostro {
namespace {

// Resolves an OBJ vertex reference ("12", "12/3/4", "-1") to a 0-based index.
int vertex_index(const std::string& token, int vertex_count, const std::string& path, long line) {
  const std::string head = token.substr(0, token.find('/'));
  int value = 0;
  const auto [ptr, ec] = std::from_chars(head.data(), head.data() + head.size(), value);
  if (ec != std::errc() || ptr != head.data() + head.size() || value == 0)
    throw InputError(where(path, line, "bad face vertex reference '" + token + "'"));
  const int index = value > 0 ? value - 1 : vertex_count + value;
  if (index < 0 || index >= vertex_count)
    throw InputError(where(path, line,
                           fmt::format("face vertex {} is out of range (the file has {} vertices "
                                       "so far)",
                                       value, vertex_count)));
  return index;
}

}  // namespace

ObjMesh read_obj(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path.string() + ": cannot open the OBJ mesh");
  const std::string name = path.string();
  ObjMesh mesh;
  std::map<std::string, int> material_ids;
  int current_material = -1;
  bool all_coloured = true;
  std::string text;
  long line = 0;
  while (std::getline(in, text)) {
    ++line;
    std::istringstream s(text);
    std::string tag;
    if (!(s >> tag) || tag[0] == '#') continue;
    if (tag == "v") {
      std::vector<float> values;
      float x = 0;
      while (s >> x) values.push_back(x);
      if (!s.eof())
        throw InputError(where(name, line, "a vertex coordinate or colour is not a number"));
      if (values.size() != 3 && values.size() != 6 && values.size() != 4 && values.size() != 7)
        throw InputError(where(name, line, "expected 'v x y z' or 'v x y z r g b'"));
      mesh.positions.emplace_back(values[0], values[1], values[2]);
      if (values.size() == 6)
        mesh.colors.emplace_back(values[3], values[4], values[5]);
      else
        all_coloured = false;
    } else if (tag == "f") {
      std::vector<int> face;
      std::string token;
      const int count = static_cast<int>(mesh.positions.size());
      while (s >> token) face.push_back(vertex_index(token, count, name, line));
      if (face.size() < 3) throw InputError(where(name, line, "a face needs 3 or more vertices"));
      for (std::size_t i = 1; i + 1 < face.size(); ++i) {
        mesh.triangles.emplace_back(face[0], face[i], face[i + 1]);
        if (current_material >= 0) mesh.triangle_materials.push_back(current_material);
      }
    } else if (tag == "usemtl") {
      std::string material;
      s >> material;
      auto [it, added] =
          material_ids.try_emplace(material, static_cast<int>(mesh.materials.size()));
      if (added) mesh.materials.push_back(material);
      if (current_material < 0 && !mesh.triangles.empty())
        // Triangles before the first usemtl get an unnamed default material.
        throw InputError(where(name, line, "usemtl after faces without a material"));
      current_material = it->second;
    }
  }
  if (!all_coloured) mesh.colors.clear();
  if (mesh.triangle_materials.size() != mesh.triangles.size()) mesh.triangle_materials.clear();
  if (mesh.positions.empty()) throw InputError(name + ": the OBJ mesh has no vertices");
  return mesh;
}

void write_obj(const ObjMesh& mesh, const std::filesystem::path& path) {
  AtomicFile file(path);
  std::string out;
  out.reserve(mesh.positions.size() * 64 + mesh.triangles.size() * 24);
  out += "# rostro face mesh: v x y z r g b (model units, linear colour 0..1)\n";
  const bool coloured = mesh.colors.size() == mesh.positions.size();
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    const Eigen::Vector3f& p = mesh.positions[i];
    if (coloured) {
      const Eigen::Vector3f& c = mesh.colors[i];
      out += fmt::format("v {:.5f} {:.5f} {:.5f} {:.4f} {:.4f} {:.4f}\n", p.x(), p.y(), p.z(),
                         c.x(), c.y(), c.z());
    } else {
      out += fmt::format("v {:.5f} {:.5f} {:.5f}\n", p.x(), p.y(), p.z());
    }
  }
  const bool materials = mesh.triangle_materials.size() == mesh.triangles.size();
  int current = -1;
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    if (materials && mesh.triangle_materials[i] != current) {
      current = mesh.triangle_materials[i];
      out += "usemtl " + mesh.materials[static_cast<std::size_t>(current)] + "\n";
    }
    const Eigen::Vector3i& t = mesh.triangles[i];
    out += fmt::format("f {} {} {}\n", t.x() + 1, t.y() + 1, t.z() + 1);
  }
  file.write(out);
  file.commit();
}

}  // namespace rostro

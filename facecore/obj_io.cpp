#include "facecore/obj_io.hpp"

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>

#include "facecore/atomic_file.hpp"
#include "facecore/error.hpp"

namespace rostro {
namespace {

// Resolves one number of an OBJ face reference (1-based, or negative: counted back from the
// last of `count` so far) to a 0-based index; `what` names the kind ("face vertex", "texture
// coordinate") and `plural` what the file counts ("vertices") in the error.
int reference_index(const std::string& number, int count, const std::string& what,
                    const std::string& plural, const std::string& token, const std::string& path,
                    long line) {
  int value = 0;
  const auto [ptr, ec] = std::from_chars(number.data(), number.data() + number.size(), value);
  if (ec != std::errc() || ptr != number.data() + number.size() || value == 0)
    throw InputError(where(path, line, "bad " + what + " reference '" + token + "'"));
  const int index = value > 0 ? value - 1 : count + value;
  if (index < 0 || index >= count)
    throw InputError(where(path, line,
                           fmt::format("{} {} is out of range (the file has {} {} so far)", what,
                                       value, count, plural)));
  return index;
}

// The vertex of a face reference ("12", "12/3/4", "-1"), 0-based.
int vertex_index(const std::string& token, int vertex_count, const std::string& path, long line) {
  return reference_index(token.substr(0, token.find('/')), vertex_count, "face vertex", "vertices",
                         token, path, line);
}

// The texture coordinate of a face reference ("12/3", "12/3/4"), 0-based; -1 for none.
int texcoord_index(const std::string& token, int texcoord_count, const std::string& path,
                   long line) {
  const std::size_t slash = token.find('/');
  if (slash == std::string::npos) return -1;
  const std::string rest = token.substr(slash + 1);
  const std::string number = rest.substr(0, rest.find('/'));
  if (number.empty()) return -1;
  return reference_index(number, texcoord_count, "texture coordinate", "texture coordinates", token,
                         path, line);
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
  std::vector<Eigen::Vector2f> texcoords;  // the file's vt records
  constexpr float kNone = std::numeric_limits<float>::quiet_NaN();
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
    } else if (tag == "vt") {
      float u = 0, v = 0;
      if (!(s >> u >> v)) throw InputError(where(name, line, "expected 'vt u v'"));
      texcoords.emplace_back(u, v);
    } else if (tag == "f") {
      std::vector<int> face;
      std::string token;
      const int count = static_cast<int>(mesh.positions.size());
      const int texcoord_count = static_cast<int>(texcoords.size());
      while (s >> token) {
        face.push_back(vertex_index(token, count, name, line));
        const int t = texcoord_index(token, texcoord_count, name, line);
        if (t < 0) continue;
        if (mesh.texcoords.size() < mesh.positions.size())
          mesh.texcoords.resize(mesh.positions.size(), Eigen::Vector2f(kNone, kNone));
        Eigen::Vector2f& uv = mesh.texcoords[static_cast<std::size_t>(face.back())];
        if (!uv.allFinite()) {
          const Eigen::Vector2f& given = texcoords[static_cast<std::size_t>(t)];
          uv = {given.x() - std::floor(given.x()), given.y()};
        }
      }
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
  if (!mesh.texcoords.empty())
    mesh.texcoords.resize(mesh.positions.size(), Eigen::Vector2f(kNone, kNone));
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
  // Texture coordinates: one per textured vertex (vt k is vertex k's), then one past u = 1 for
  // each corner of a face across the seam, written as its face is.
  const bool textured = mesh.texcoords.size() == mesh.positions.size();
  std::vector<int> vt_of(textured ? mesh.positions.size() : 0, 0);
  int vt_count = 0;
  for (std::size_t i = 0; i < vt_of.size(); ++i) {
    if (!mesh.texcoords[i].allFinite()) continue;
    vt_of[i] = ++vt_count;
    out += fmt::format("vt {:.6f} {:.6f}\n", mesh.texcoords[i].x(), mesh.texcoords[i].y());
  }
  const bool materials = mesh.triangle_materials.size() == mesh.triangles.size();
  int current = -1;
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    if (materials && mesh.triangle_materials[i] != current) {
      current = mesh.triangle_materials[i];
      out += "usemtl " + mesh.materials[static_cast<std::size_t>(current)] + "\n";
    }
    const Eigen::Vector3i& t = mesh.triangles[i];
    const bool face_textured = textured && vt_of[static_cast<std::size_t>(t.x())] > 0 &&
                               vt_of[static_cast<std::size_t>(t.y())] > 0 &&
                               vt_of[static_cast<std::size_t>(t.z())] > 0;
    if (!face_textured) {
      out += fmt::format("f {} {} {}\n", t.x() + 1, t.y() + 1, t.z() + 1);
      continue;
    }
    float u_max = 0;
    for (int k = 0; k < 3; ++k)
      u_max = std::max(u_max, mesh.texcoords[static_cast<std::size_t>(t[k])].x());
    std::string face = "f";
    for (int k = 0; k < 3; ++k) {
      const auto v = static_cast<std::size_t>(t[k]);
      int vt = vt_of[v];
      if (u_max - mesh.texcoords[v].x() > 0.5f) {  // across the seam: this corner past u = 1
        out += fmt::format("vt {:.6f} {:.6f}\n", mesh.texcoords[v].x() + 1, mesh.texcoords[v].y());
        vt = ++vt_count;
      }
      face += fmt::format(" {}/{}", v + 1, vt);
    }
    out += face + "\n";
  }
  file.write(out);
  file.commit();
}

}  // namespace rostro

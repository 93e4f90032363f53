#include "facecore/face_model.hpp"

#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>

#include "facecore/atomic_file.hpp"
#include "facecore/data_path.hpp"
#include "facecore/error.hpp"
#include "facecore/json_file.hpp"
#include "facecore/obj_io.hpp"

namespace rostro {
namespace {

using nlohmann::json;

constexpr const char* kFormat = "rostro-face-model/1";

struct KindName {
  InfluenceKind kind;
  const char* name;
};
constexpr KindName kKinds[] = {{InfluenceKind::RaisedCosine, "raised_cosine"},
                               {InfluenceKind::Rbf, "rbf"},
                               {InfluenceKind::AveragedCosine, "averaged_cosine"},
                               {InfluenceKind::Rigid, "rigid"}};

const char* kind_name(InfluenceKind kind) {
  for (const KindName& k : kKinds)
    if (k.kind == kind) return k.name;
  return "?";
}

// Reads the JSON description, turning every type or shape mistake into one InputError line.
class DescriptionReader {
 public:
  explicit DescriptionReader(std::string source) : source_(std::move(source)) {}

  [[noreturn]] void fail(const std::string& what) const { throw InputError(source_ + ": " + what); }

  FeaturePointId point(const json& j, const std::string& context) const {
    if (!j.is_string()) fail(context + ": a feature point must be a string like \"2.1\"");
    const auto id = parse_feature_point(j.get<std::string>());
    if (!id) fail(context + ": unknown feature point '" + j.get<std::string>() + "'");
    return *id;
  }

  std::vector<int> indices(const json& j, const std::string& context) const {
    if (!j.is_array()) fail(context + ": expected an array of vertex indices");
    std::vector<int> out;
    out.reserve(j.size());
    for (const json& v : j) {
      if (!v.is_number_integer()) fail(context + ": vertex indices must be integers");
      out.push_back(v.get<int>());
    }
    return out;
  }

  Eigen::Vector3d vec3(const json& j, const std::string& context) const {
    if (!j.is_array() || j.size() != 3 || !j[0].is_number() || !j[1].is_number() ||
        !j[2].is_number())
      fail(context + ": expected [x, y, z]");
    return {j[0].get<double>(), j[1].get<double>(), j[2].get<double>()};
  }

  double number(const json& obj, const char* key, double fallback,
                const std::string& context) const {
    if (!obj.contains(key)) return fallback;
    if (!obj[key].is_number()) fail(context + ": '" + key + "' must be a number");
    return obj[key].get<double>();
  }

  InfluenceRegion region(const json& j, std::size_t i) const {
    InfluenceRegion r;
    r.name = j.value("name", fmt::format("#{}", i));
    const std::string ctx = fmt::format("region '{}'", r.name);
    const std::string function = j.value("function", "");
    bool known = false;
    for (const KindName& k : kKinds)
      if (function == k.name) r.kind = k.kind, known = true;
    if (!known)
      fail(ctx + ": function must be raised_cosine, rbf, averaged_cosine or rigid, not '" +
           function + "'");
    if (j.contains("feature_points")) {
      if (!j["feature_points"].is_array()) fail(ctx + ": feature_points must be an array");
      for (const json& p : j["feature_points"]) r.feature_points.push_back(point(p, ctx));
    }
    if (!j.contains("vertices")) fail(ctx + ": has no 'vertices'");
    r.vertices = indices(j["vertices"], ctx + " vertices");
    if (j.contains("weights")) {
      if (!j["weights"].is_array()) fail(ctx + ": weights must be an array of numbers");
      for (const json& w : j["weights"]) {
        if (!w.is_number()) fail(ctx + ": weights must be numbers");
        r.vertex_weights.push_back(w.get<double>());
      }
    }
    if (j.contains("axis")) {
      const std::string axis = j["axis"].is_string() ? j["axis"].get<std::string>() : "";
      if (axis == "x")
        r.metric = {1, 0, 0};
      else if (axis == "y")
        r.metric = {0, 1, 0};
      else if (axis == "z")
        r.metric = {0, 0, 1};
      else
        fail(ctx + ": axis must be \"x\", \"y\" or \"z\"");
    }
    if (j.contains("metric")) r.metric = vec3(j["metric"], ctx + " metric");
    r.d_max = number(j, "d_max", 0.0, ctx);
    r.gain = number(j, "gain", 1.0, ctx);
    if (j.contains("anchors")) r.anchors = indices(j["anchors"], ctx + " anchors");
    if (j.contains("faps")) {
      if (!j["faps"].is_array()) fail(ctx + ": faps must be an array of FAP ids");
      for (const json& f : j["faps"]) {
        if (!f.is_number_integer() || !is_fap_id(f.get<int>()))
          fail(ctx + ": faps must hold FAP ids 1..68");
        r.faps.push_back(f.get<int>());
      }
    }
    return r;
  }

  TurnWeights turn_weights(const json& j) const {
    TurnWeights t;
    if (!j.is_object()) fail("'turn_weights' must be an object with vertices and weights");
    if (!j.contains("vertices") || !j.contains("weights"))
      fail("'turn_weights' needs both 'vertices' and 'weights'");
    t.vertices = indices(j["vertices"], "turn_weights vertices");
    if (!j["weights"].is_array()) fail("turn_weights: weights must be an array of numbers");
    for (const json& w : j["weights"]) {
      if (!w.is_number()) fail("turn_weights: weights must be numbers");
      t.weights.push_back(w.get<double>());
    }
    return t;
  }

  RigidPart part(const json& j, const std::string& name) const {
    RigidPart p;
    const std::string ctx = "rigid part '" + name + "'";
    if (!j.is_object()) fail(ctx + ": expected an object");
    if (j.contains("vertices")) p.vertices = indices(j["vertices"], ctx + " vertices");
    if (j.contains("pivot")) p.pivot = vec3(j["pivot"], ctx + " pivot");
    p.jaw_gain = number(j, "jaw_gain", 0.0, ctx);
    return p;
  }

 private:
  std::string source_;
};

json indices_json(const std::vector<int>& v) {
  return json(v);
}

json vec3_json(const Eigen::Vector3d& v) {
  return json::array({v.x(), v.y(), v.z()});
}

json part_json(const RigidPart& p) {
  json j;
  j["vertices"] = indices_json(p.vertices);
  j["pivot"] = vec3_json(p.pivot);
  if (p.jaw_gain != 0.0) j["jaw_gain"] = p.jaw_gain;
  return j;
}

struct PartSlot {
  const char* name;
  RigidPart RigidParts::*member;
};
constexpr PartSlot kParts[] = {{"left_eyeball", &RigidParts::left_eyeball},
                               {"right_eyeball", &RigidParts::right_eyeball},
                               {"upper_teeth", &RigidParts::upper_teeth},
                               {"lower_teeth", &RigidParts::lower_teeth},
                               {"tongue", &RigidParts::tongue},
                               {"jaw", &RigidParts::jaw}};

}  // namespace

Eigen::Vector3d FaceModel::feature_point(FeaturePointId id) const {
  auto it = feature_points.find(id);
  if (it == feature_points.end())
    throw InputError("face model '" + name + "' has no feature point " + id.str());
  return positions[static_cast<std::size_t>(it->second)].cast<double>();
}

FeaturePointPositions FaceModel::feature_point_positions() const {
  FeaturePointPositions out;
  for (const auto& [id, v] : feature_points)
    out[id] = positions[static_cast<std::size_t>(v)].cast<double>();
  return out;
}

void FaceModel::validate(const std::string& source) const {
  const DescriptionReader reader(source);
  const auto n = static_cast<long>(positions.size());
  auto check_index = [&](int v, const std::string& context) {
    if (v < 0 || v >= n)
      reader.fail(
          fmt::format("{}: vertex index {} is out of range (the mesh has {} vertices, "
                      "0..{})",
                      context, v, n, n - 1));
  };
  for (const Eigen::Vector3i& t : triangles)
    for (int k = 0; k < 3; ++k) check_index(t[k], "triangle");
  if (!colors.empty() && colors.size() != positions.size())
    reader.fail("colour count differs from the vertex count");
  if (!texcoords.empty() && texcoords.size() != positions.size())
    reader.fail("texture coordinate count differs from the vertex count");
  if (!texcoords.empty() && texture.empty())
    reader.fail("the mesh has texture coordinates but the model no texture");
  for (const auto& [id, v] : feature_points) check_index(v, "feature point " + id.str());
  for (const InfluenceRegion& r : regions) {
    const std::string ctx = "region '" + r.name + "'";
    if (r.feature_points.empty()) reader.fail(ctx + ": has no feature point");
    for (FeaturePointId p : r.feature_points)
      if (!has_feature_point(p))
        reader.fail(ctx + ": feature point " + p.str() +
                    " is not in the model's feature_points map");
    if (r.vertices.empty()) reader.fail(ctx + ": has no vertices");
    for (int v : r.vertices) check_index(v, ctx);
    for (int v : r.anchors) check_index(v, ctx + " anchors");
    if (!r.vertex_weights.empty() && r.vertex_weights.size() != r.vertices.size())
      reader.fail(fmt::format("{}: {} weights for {} vertices", ctx, r.vertex_weights.size(),
                              r.vertices.size()));
    if (r.kind == InfluenceKind::RaisedCosine && r.feature_points.size() != 1)
      reader.fail(ctx + ": raised_cosine takes exactly one feature point (use averaged_cosine)");
    if (r.metric.minCoeff() < 0 || r.metric.maxCoeff() <= 0)
      reader.fail(ctx + ": metric must be non-negative and not all zero");
  }
  for (const PartSlot& slot : kParts)
    for (int v : (parts.*slot.member).vertices)
      check_index(v, std::string("rigid part ") + slot.name);
  for (int v : turn_weights.vertices) check_index(v, "turn_weights");
  if (turn_weights.weights.size() != turn_weights.vertices.size())
    reader.fail(fmt::format("turn_weights: {} weights for {} vertices", turn_weights.weights.size(),
                            turn_weights.vertices.size()));
  for (double w : turn_weights.weights)
    if (!(w >= 0.0 && w <= 1.0))
      reader.fail(fmt::format("turn_weights: a weight is {}, not a share from 0 to 1", w));
}

FaceModel load_face_model(const std::filesystem::path& description) {
  const std::string source = description.string();
  const json j = read_json_file(description, "the face model description");
  const DescriptionReader reader(source);
  if (!j.is_object()) reader.fail("expected a JSON object");
  if (j.contains("format") && j["format"] != kFormat)
    reader.fail(std::string("unsupported format (expected \"") + kFormat + "\")");
  if (!j.contains("mesh") || !j["mesh"].is_string())
    reader.fail("'mesh' (the OBJ file name) is missing");

  FaceModel model;
  model.name = j.value("name", description.stem().string());
  ObjMesh mesh = read_obj(description.parent_path() / j["mesh"].get<std::string>());
  model.positions = std::move(mesh.positions);
  model.colors = std::move(mesh.colors);
  model.texcoords = std::move(mesh.texcoords);
  if (j.contains("texture")) {
    if (!j["texture"].is_string())
      reader.fail("'texture' (the image's file name) must be a string");
    model.texture = read_texture(description.parent_path() / j["texture"].get<std::string>());
  } else {
    model.texcoords.clear();  // coordinates into no image: the colours stand
  }
  model.triangles = std::move(mesh.triangles);
  model.materials = std::move(mesh.materials);
  model.triangle_materials = std::move(mesh.triangle_materials);

  if (!j.contains("feature_points") || !j["feature_points"].is_object())
    reader.fail("'feature_points' (point -> vertex index) is missing");
  for (const auto& [key, value] : j["feature_points"].items()) {
    const auto id = parse_feature_point(key);
    if (!id) reader.fail("unknown feature point '" + key + "'");
    if (!value.is_number_integer())
      reader.fail("feature point " + key + ": the vertex index must be an integer");
    model.feature_points[*id] = value.get<int>();
  }
  if (j.contains("regions")) {
    if (!j["regions"].is_array()) reader.fail("'regions' must be an array");
    for (std::size_t i = 0; i < j["regions"].size(); ++i)
      model.regions.push_back(reader.region(j["regions"][i], i));
  }
  if (j.contains("rigid_parts")) {
    const json& parts = j["rigid_parts"];
    if (!parts.is_object()) reader.fail("'rigid_parts' must be an object");
    for (const auto& [key, value] : parts.items()) {
      bool known = false;
      for (const PartSlot& slot : kParts)
        if (key == slot.name) model.parts.*slot.member = reader.part(value, key), known = true;
      if (!known) reader.fail("unknown rigid part '" + key + "'");
    }
  }
  if (j.contains("turn_weights")) model.turn_weights = reader.turn_weights(j["turn_weights"]);
  model.validate(source);
  if (j.contains("head_pivot"))
    model.head_pivot = reader.vec3(j["head_pivot"], "head_pivot");
  else if (model.has_feature_point({7, 1}))
    model.head_pivot = model.feature_point({7, 1});
  try {
    model.fapu = fapu_from_feature_points(model.feature_point_positions());
  } catch (const InputError& e) {
    reader.fail(e.what());
  }
  return model;
}

FaceModel load_default_face_model() {
  return load_face_model(data_file("head/head.json"));
}

FaceModel load_face_model_or_default(const std::filesystem::path& description) {
  return description.empty() ? load_default_face_model() : load_face_model(description);
}

void save_face_model(const FaceModel& model, const std::filesystem::path& dir,
                     const std::string& stem) {
  std::filesystem::create_directories(dir);
  const bool textured = !model.texture.empty() && model.texcoords.size() == model.positions.size();
  ObjMesh mesh{
      model.positions, model.colors,    textured ? model.texcoords : std::vector<Eigen::Vector2f>{},
      model.triangles, model.materials, model.triangle_materials};
  if (textured) write_texture(model.texture, dir / (stem + ".png"));
  write_obj(mesh, dir / (stem + ".obj"));

  json j;
  j["format"] = kFormat;
  j["name"] = model.name;
  j["mesh"] = stem + ".obj";
  if (textured) j["texture"] = stem + ".png";
  j["units"] = "mm";
  json points = json::object();
  for (const auto& [id, v] : model.feature_points) points[id.str()] = v;
  j["feature_points"] = points;
  j["head_pivot"] = vec3_json(model.head_pivot);
  json regions = json::array();
  for (const InfluenceRegion& r : model.regions) {
    json jr;
    jr["name"] = r.name;
    jr["function"] = kind_name(r.kind);
    json fps = json::array();
    for (FeaturePointId p : r.feature_points) fps.push_back(p.str());
    jr["feature_points"] = fps;
    if (!r.faps.empty()) jr["faps"] = r.faps;
    if (r.metric != Eigen::Vector3d::Ones()) jr["metric"] = vec3_json(r.metric);
    if (r.d_max > 0) jr["d_max"] = r.d_max;
    if (r.kind == InfluenceKind::Rigid) jr["gain"] = r.gain;
    jr["vertices"] = indices_json(r.vertices);
    if (!r.vertex_weights.empty()) {
      json w = json::array();
      // Three decimals are plenty for a fade and keep big heads' files small.
      for (double x : r.vertex_weights) w.push_back(std::round(x * 1000.0) / 1000.0);
      jr["weights"] = w;
    }
    if (!r.anchors.empty()) jr["anchors"] = indices_json(r.anchors);
    regions.push_back(jr);
  }
  j["regions"] = regions;
  json parts = json::object();
  for (const PartSlot& slot : kParts)
    if (!(model.parts.*slot.member).empty()) parts[slot.name] = part_json(model.parts.*slot.member);
  j["rigid_parts"] = parts;
  if (!model.turn_weights.empty()) {
    json w = json::array();
    for (double x : model.turn_weights.weights) w.push_back(std::round(x * 1000.0) / 1000.0);
    j["turn_weights"] = {{"vertices", indices_json(model.turn_weights.vertices)}, {"weights", w}};
  }

  AtomicFile file(dir / (stem + ".json"));
  file.write(j.dump(1));
  file.write("\n");
  file.commit();
}

}  // namespace rostro

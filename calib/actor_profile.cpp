#include "calib/actor_profile.hpp"

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

#include "facecore/atomic_file.hpp"
#include "facecore/error.hpp"

namespace rostro::calib {
namespace {

using nlohmann::json;

constexpr const char* kFormat = "rostro-actor-profile";
constexpr int kVersion = 1;

json fapu_json(const Fapu& f, const char* unit) {
  return {{"es0", f.es0}, {"ens0", f.ens0},     {"mns0", f.mns0},
          {"mw0", f.mw0}, {"irisd0", f.irisd0}, {"length_unit", unit}};
}

// Small readers that name the field that is wrong.
class Reader {
 public:
  explicit Reader(std::string context) : context_(std::move(context)) {}

  [[noreturn]] void fail(const std::string& field, const std::string& what) const {
    throw InputError(context_ + ": '" + field + "' " + what);
  }
  const json& member(const json& j, const std::string& key, const std::string& field) const {
    if (!j.is_object()) fail(field, "must be an object");
    auto it = j.find(key);
    if (it == j.end()) fail(field + key, "is missing");
    return *it;
  }
  double number(const json& j, const std::string& key, const std::string& field) const {
    const json& v = member(j, key, field);
    if (!v.is_number() || !std::isfinite(v.get<double>())) fail(field + key, "must be a number");
    return v.get<double>();
  }
  double positive(const json& j, const std::string& key, const std::string& field) const {
    double v = number(j, key, field);
    if (v <= 0) fail(field + key, "must be positive");
    return v;
  }
  std::string text(const json& j, const std::string& key, const std::string& field) const {
    const json& v = member(j, key, field);
    if (!v.is_string()) fail(field + key, "must be a string");
    return v.get<std::string>();
  }
  std::vector<double> numbers(const json& v, std::size_t n, const std::string& field) const {
    if (!v.is_array() || (n != 0 && v.size() != n))
      fail(field, n ? "must be an array of " + std::to_string(n) + " numbers"
                    : "must be an array of numbers");
    std::vector<double> out;
    for (const json& e : v) {
      if (!e.is_number() || !std::isfinite(e.get<double>())) fail(field, "must hold only numbers");
      out.push_back(e.get<double>());
    }
    return out;
  }
  Fapu fapu(const json& j, const std::string& field) const {
    Fapu f;
    f.es0 = positive(j, "es0", field);
    f.ens0 = positive(j, "ens0", field);
    f.mns0 = positive(j, "mns0", field);
    f.mw0 = positive(j, "mw0", field);
    f.irisd0 = positive(j, "irisd0", field);
    return f;
  }

 private:
  std::string context_;
};

}  // namespace

const NeutralMarker* ActorProfile::find_marker(const std::string& id) const {
  for (const NeutralMarker& m : markers)
    if (m.marker == id) return &m;
  return nullptr;
}

double ActorProfile::apply_gain(int id, double value) const {
  auto it = fap_gains.find(id);
  if (it == fap_gains.end()) return value;
  double v = value * it->second.gain;
  if (it->second.min && v < *it->second.min) v = *it->second.min;
  if (it->second.max && v > *it->second.max) v = *it->second.max;
  return v;
}

std::string actor_profile_to_json(const ActorProfile& p) {
  json j;
  j["format"] = kFormat;
  j["version"] = kVersion;
  j["name"] = p.name;
  j["fapu"] = fapu_json(p.fapu, "mm");
  j["fapu_image"] = fapu_json(p.fapu_image, "px");
  j["fapu_notes"] = p.fapu_notes;
  const CameraIntrinsics& k = p.camera;
  j["camera"] = {{"image_width", k.image_size.width},
                 {"image_height", k.image_size.height},
                 {"fx", k.fx},
                 {"fy", k.fy},
                 {"cx", k.cx},
                 {"cy", k.cy},
                 {"distortion", k.distortion},
                 {"reprojection_error", k.reprojection_error},
                 {"source", k.source}};
  if (p.neutral_pose) {
    const auto& r = p.neutral_pose->rotation;
    const auto& t = p.neutral_pose->translation;
    j["neutral_pose"] = {{"rotation", {r[0], r[1], r[2]}}, {"translation", {t[0], t[1], t[2]}}};
  }
  j["shape_source"] = p.shape_source;
  j["neutral_frames"] = p.neutral_frames;
  json markers = json::array();
  for (const NeutralMarker& m : p.markers) {
    json jm = {{"marker", m.marker},
               {"fp", is_feature_point(m.feature_point) ? m.feature_point.str() : ""},
               {"image", {m.image.x, m.image.y}},
               {"frames_seen", m.frames_seen},
               {"rigid", m.rigid}};
    if (m.position) jm["position"] = {m.position->x(), m.position->y(), m.position->z()};
    if (auto mo = p.marker_motion.find(m.marker); mo != p.marker_motion.end()) {
      json motion = json::object();
      for (const auto& [id, step] : mo->second)
        motion[std::to_string(id)] = {step.x(), step.y(), step.z()};
      jm["motion"] = std::move(motion);
    }
    markers.push_back(std::move(jm));
  }
  j["markers"] = std::move(markers);
  json gains = json::array();
  for (const auto& [id, g] : p.fap_gains) {
    json jg = {{"fap", std::string(fap_info(id).name)}, {"gain", g.gain}};
    if (g.min) jg["min"] = *g.min;
    if (g.max) jg["max"] = *g.max;
    gains.push_back(std::move(jg));
  }
  j["fap_gains"] = std::move(gains);
  return j.dump(2) + "\n";
}

ActorProfile actor_profile_from_json(const std::string& text, const std::string& context) {
  json j;
  try {
    j = json::parse(text);
  } catch (const json::exception& e) {  // parse_error, or out_of_range for a number
    throw InputError(context + ": not valid JSON (" + e.what() + ")");
  }
  const Reader r(context);
  if (!j.is_object()) throw InputError(context + ": expected a JSON object (an actor profile)");
  if (r.text(j, "format", "") != kFormat)
    r.fail("format", std::string("must be \"") + kFormat + "\"");
  if (r.number(j, "version", "") != kVersion)
    r.fail("version", "must be " + std::to_string(kVersion) + " (this rostro's profile version)");

  ActorProfile p;
  p.name = r.text(j, "name", "");
  p.fapu = r.fapu(r.member(j, "fapu", ""), "fapu.");
  p.fapu_image = r.fapu(r.member(j, "fapu_image", ""), "fapu_image.");
  if (j.contains("fapu_notes")) {
    const json& notes = j["fapu_notes"];
    if (!notes.is_object()) r.fail("fapu_notes", "must be an object of strings");
    for (const auto& [key, value] : notes.items()) {
      if (!value.is_string()) r.fail("fapu_notes." + key, "must be a string");
      p.fapu_notes[key] = value.get<std::string>();
    }
  }

  // A count stored in an int: a whole number in 0..max, so that the cast never wraps.
  const auto whole = [&](const json& o, const char* key, const std::string& field, double max) {
    const double v = r.number(o, key, field);
    if (!(v >= 0 && v <= max) || v != std::floor(v))
      r.fail(field + key, "must be a whole number in 0.." + std::to_string(static_cast<long>(max)));
    return static_cast<int>(v);
  };
  const json& cam = r.member(j, "camera", "");
  CameraIntrinsics& k = p.camera;
  k.image_size.width = whole(cam, "image_width", "camera.", 65536);
  k.image_size.height = whole(cam, "image_height", "camera.", 65536);
  if (k.image_size.width == 0 || k.image_size.height == 0)
    r.fail("camera.image_width", "and image_height must be positive");
  k.fx = r.positive(cam, "fx", "camera.");
  k.fy = r.positive(cam, "fy", "camera.");
  k.cx = r.number(cam, "cx", "camera.");
  k.cy = r.number(cam, "cy", "camera.");
  if (cam.contains("distortion"))
    k.distortion = r.numbers(cam["distortion"], 0, "camera.distortion");
  if (cam.contains("reprojection_error"))
    k.reprojection_error = r.number(cam, "reprojection_error", "camera.");
  if (cam.contains("source")) k.source = r.text(cam, "source", "camera.");

  if (j.contains("neutral_pose")) {
    const json& pose = j["neutral_pose"];
    auto rot = r.numbers(r.member(pose, "rotation", "neutral_pose."), 3, "neutral_pose.rotation");
    auto tr =
        r.numbers(r.member(pose, "translation", "neutral_pose."), 3, "neutral_pose.translation");
    p.neutral_pose = tracking::HeadPose{{rot[0], rot[1], rot[2]}, {tr[0], tr[1], tr[2]}};
  }
  if (j.contains("shape_source")) p.shape_source = r.text(j, "shape_source", "");
  if (j.contains("neutral_frames")) p.neutral_frames = whole(j, "neutral_frames", "", 1e9);

  const json& markers = r.member(j, "markers", "");
  if (!markers.is_array() || markers.empty()) r.fail("markers", "must be a non-empty array");
  for (std::size_t i = 0; i < markers.size(); ++i) {
    const std::string field = "markers[" + std::to_string(i) + "].";
    const json& jm = markers[i];
    NeutralMarker m;
    m.marker = r.text(jm, "marker", field);
    if (m.marker.empty()) r.fail(field + "marker", "must not be empty");
    if (p.find_marker(m.marker)) r.fail(field + "marker", "repeats '" + m.marker + "'");
    const std::string fp = r.text(jm, "fp", field);
    if (!fp.empty()) {  // empty: a marker on no feature point (a headband tag)
      auto parsed = parse_feature_point(fp);
      if (!parsed) r.fail(field + "fp", "'" + fp + "' is not an MPEG-4 feature point");
      m.feature_point = *parsed;
    }
    auto image = r.numbers(r.member(jm, "image", field), 2, field + "image");
    m.image = {image[0], image[1]};
    if (jm.contains("position")) {
      auto pos = r.numbers(jm["position"], 3, field + "position");
      m.position = Eigen::Vector3d(pos[0], pos[1], pos[2]);
    }
    if (jm.contains("frames_seen")) m.frames_seen = whole(jm, "frames_seen", field, 1e9);
    if (jm.contains("rigid")) {
      if (!jm["rigid"].is_boolean()) r.fail(field + "rigid", "must be true or false");
      m.rigid = jm["rigid"].get<bool>();
    }
    if (!is_feature_point(m.feature_point) && !m.rigid)
      r.fail(field + "fp", "is empty but the marker is not rigid");
    if (jm.contains("motion")) {
      const json& motion = jm["motion"];
      if (!motion.is_object()) r.fail(field + "motion", "must be an object of FAP id -> [x, y, z]");
      for (const auto& [key, step] : motion.items()) {
        int id = 0;
        try {
          std::size_t used = 0;
          id = std::stoi(key, &used);
          if (used != key.size()) id = 0;
        } catch (const std::exception&) {
          id = 0;
        }
        if (id < 3 || id > 68) r.fail(field + "motion." + key, "is not a low-level FAP id (3-68)");
        auto v = r.numbers(step, 3, field + "motion." + key);
        p.marker_motion[m.marker][id] = Eigen::Vector3d(v[0], v[1], v[2]);
      }
    }
    p.markers.push_back(std::move(m));
  }

  if (j.contains("fap_gains")) {
    const json& gains = j["fap_gains"];
    if (!gains.is_array()) r.fail("fap_gains", "must be an array");
    for (std::size_t i = 0; i < gains.size(); ++i) {
      const std::string field = "fap_gains[" + std::to_string(i) + "].";
      const json& jg = gains[i];
      const std::string name = r.text(jg, "fap", field);
      auto id = find_fap(name);
      if (!id) r.fail(field + "fap", "'" + name + "' is not an MPEG-4 FAP name");
      FapGain g;
      if (jg.contains("gain")) g.gain = r.number(jg, "gain", field);
      if (jg.contains("min")) g.min = r.number(jg, "min", field);
      if (jg.contains("max")) g.max = r.number(jg, "max", field);
      if (g.min && g.max && *g.min > *g.max) r.fail(field + "min", "is greater than max");
      p.fap_gains[*id] = g;
    }
  }
  return p;
}

ActorProfile read_actor_profile(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path.string() + ": cannot open the actor profile");
  std::stringstream text;
  text << in.rdbuf();
  return actor_profile_from_json(text.str(), path.string());
}

void write_actor_profile(const std::filesystem::path& path, const ActorProfile& profile) {
  const std::string text = actor_profile_to_json(profile);
  AtomicFile out(path);
  out.write(text);
  out.commit();
}

}  // namespace rostro::calib

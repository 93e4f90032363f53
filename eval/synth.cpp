#include "eval/synth.hpp"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <set>

#include "calib/actor_calibration.hpp"
#include "eval/draw_tag.hpp"
#include "facecore/error.hpp"
#include "render/camera.hpp"
#include "render/face_renderer.hpp"

namespace rostro::eval {
namespace {

constexpr double kPi = std::numbers::pi;

// A raised-cosine bump: 0 outside [start, start + length], 1 at its middle.
double bump(double t, double start, double length) {
  if (t < start || t > start + length) return 0;
  return 0.5 - 0.5 * std::cos(2 * kPi * (t - start) / length);
}

// The occluder: an ellipse crossing the image left to right over the middle of the clip.
struct Occluder {
  bool active = false;
  cv::Point2d centre;
  cv::Size2d axes;
  bool covers(const cv::Point2d& p) const {
    if (!active) return false;
    const double dx = (p.x - centre.x) / axes.width, dy = (p.y - centre.y) / axes.height;
    return dx * dx + dy * dy <= 1.0;
  }
};

// Area-weighted vertex normals of the neutral mesh.
std::vector<Eigen::Vector3f> neutral_normals(const FaceModel& model) {
  std::vector<Eigen::Vector3f> n(model.positions.size(), Eigen::Vector3f::Zero());
  for (const Eigen::Vector3i& t : model.triangles) {
    const auto a = static_cast<std::size_t>(t.x()), b = static_cast<std::size_t>(t.y()),
               c = static_cast<std::size_t>(t.z());
    const Eigen::Vector3f f =
        (model.positions[b] - model.positions[a]).cross(model.positions[c] - model.positions[a]);
    n[a] += f, n[b] += f, n[c] += f;
  }
  for (auto& v : n)
    if (v.norm() > 0) v.normalize();
  return n;
}

// The rigid motion (rotation, translation) taking the neutral anchors to their deformed
// places: Kabsch. The anchors lie in no FAP region, so only the head rotation moves them.
std::pair<Eigen::Matrix3f, Eigen::Vector3f> rigid_motion(
    const std::vector<int>& anchors, const std::vector<Eigen::Vector3f>& neutral,
    const std::vector<Eigen::Vector3f>& moved) {
  Eigen::Vector3f a = Eigen::Vector3f::Zero(), b = Eigen::Vector3f::Zero();
  for (int i : anchors) {
    a += neutral[static_cast<std::size_t>(i)];
    b += moved[static_cast<std::size_t>(i)];
  }
  a /= static_cast<float>(anchors.size());
  b /= static_cast<float>(anchors.size());
  Eigen::Matrix3f h = Eigen::Matrix3f::Zero();
  for (int i : anchors)
    h += (neutral[static_cast<std::size_t>(i)] - a) *
         (moved[static_cast<std::size_t>(i)] - b).transpose();
  Eigen::JacobiSVD<Eigen::Matrix3f> svd(h, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3f d = Eigen::Matrix3f::Identity();
  if ((svd.matrixV() * svd.matrixU().transpose()).determinant() < 0) d(2, 2) = -1;
  const Eigen::Matrix3f r = svd.matrixV() * d * svd.matrixU().transpose();
  return {r, b - r * a};
}

}  // namespace

std::vector<PaintedMarker> place_markers(const FaceModel& model,
                                         const tracking::MarkerLayout& layout) {
  std::vector<PaintedMarker> placed;
  for (const tracking::MarkerSpec& spec : layout.markers)
    if (!spec.is_tag() && model.has_feature_point(spec.feature_point)) {
      PaintedMarker pm;
      pm.spec = &spec;
      const int vertex = model.feature_points.at(spec.feature_point);
      pm.place = SurfacePoint::at_vertex(vertex);
      if (spec.beside_mm) {
        const Eigen::Vector3f& p = model.positions[static_cast<std::size_t>(vertex)];
        if (auto skin =
                front_skin_point(model, p.x() + spec.beside_mm->x, p.y() + spec.beside_mm->y))
          pm.place = *skin;
      }
      placed.push_back(std::move(pm));
    }
  if (layout.tag_count() == 0) return placed;

  // The layout's frame onto the head: the fit calibration uses for headband tags.
  std::vector<calib::NominalMarker> nominal;
  for (const tracking::MarkerSpec& m : layout.markers)
    nominal.push_back({m.id,
                       m.is_tag() ? std::nullopt : std::optional<FeaturePointId>(m.feature_point),
                       {m.position_mm.x, m.position_mm.y, m.position_mm.z}});
  std::map<std::string, Eigen::Vector3d> on_head;
  try {
    on_head = calib::place_nominal_markers(nominal, model.feature_point_positions());
  } catch (const InputError&) {
    return placed;  // too few dots on feature points: the tags cannot be placed
  }
  const std::vector<Eigen::Vector3f> normals = neutral_normals(model);
  // Vertices a FAP moves other than by turning the whole head.
  std::set<int> moving;
  for (const InfluenceRegion& r : model.regions)
    moving.insert(r.vertices.begin(), r.vertices.end());
  for (const RigidPart* p :
       {&model.parts.left_eyeball, &model.parts.right_eyeball, &model.parts.upper_teeth,
        &model.parts.lower_teeth, &model.parts.tongue, &model.parts.jaw})
    moving.insert(p->vertices.begin(), p->vertices.end());

  for (const tracking::MarkerSpec& spec : layout.markers) {
    if (!spec.is_tag()) continue;
    const Eigen::Vector3f wanted = on_head.at(spec.id).cast<float>();
    // Snapped to the nearest outward-facing skin vertex (the headband lies on the skin).
    int nearest = -1;
    float best = std::numeric_limits<float>::max();
    for (std::size_t i = 0; i < model.positions.size(); ++i) {
      const float d = (model.positions[i] - wanted).squaredNorm();
      if (d < best && normals[i].z() > 0) best = d, nearest = static_cast<int>(i);
    }
    if (nearest < 0) continue;
    PaintedMarker pm;
    pm.spec = &spec;
    pm.centre = model.positions[static_cast<std::size_t>(nearest)];
    pm.normal = normals[static_cast<std::size_t>(nearest)];
    // Read upright: right is the viewer's right (+x) and up is +y, in the tangent plane,
    // then the printed tag's own in-plane turn (counter-clockwise as seen).
    Eigen::Vector3f right = Eigen::Vector3f::UnitY().cross(pm.normal).normalized();
    Eigen::Vector3f up = pm.normal.cross(right);
    const float a = static_cast<float>(spec.rotation_deg * kPi / 180);
    pm.right = std::cos(a) * right + std::sin(a) * up;
    pm.up = -std::sin(a) * right + std::cos(a) * up;
    // Anchors: still vertices around the tag, the nearest first, widening until enough.
    for (float radius = 40; pm.anchors.size() < 12 && radius < 400; radius *= 1.5f) {
      pm.anchors.clear();
      for (std::size_t i = 0; i < model.positions.size(); ++i)
        if (!moving.count(static_cast<int>(i)) && (model.positions[i] - pm.centre).norm() < radius)
          pm.anchors.push_back(static_cast<int>(i));
    }
    if (pm.anchors.size() >= 3) placed.push_back(std::move(pm));
  }
  return placed;
}

FapStream range_of_motion(double fps) {
  // Amplitudes in each FAP's own unit, near the ends of a natural range.
  // The lip FAPs 4-13 are the inner lip; each moves with its outer-lip twin 51-60 (id + 47),
  // since the markers sit on the outer lip and the hierarchy derives the inner lip from it.
  const std::vector<std::vector<std::pair<int, double>>> poses = {
      {{3, 350}},              // open the jaw
      {{12, 180}, {13, 180}},  // raise the corners
      {{6, 150}, {7, 150}},    // stretch the corners
      {{4, -120}, {8, -100}, {9, -100}, {5, -160}, {10, -130}, {11, -130}, {3, 80}},  // part
      {{31, 160}, {32, 160}, {33, 180}, {34, 180}, {35, 150}, {36, 150}},             // brows up
      {{31, -80}, {32, -80}, {37, 60}, {38, 60}},    // brows down and squeezed
      {{19, 500}, {20, 500}, {21, 500}, {22, 500}},  // blink
      {{15, 120}, {16, 120}},                        // jaw sideways, lower lip pushed out
  };
  auto with_outer_lip = [](std::vector<std::pair<int, double>> pose) {
    const std::size_t n = pose.size();
    for (std::size_t i = 0; i < n; ++i)
      if (pose[i].first >= 4 && pose[i].first <= 13)
        pose.emplace_back(pose[i].first + 47, pose[i].second);
    return pose;
  };
  FapStream s;
  s.header.name = "rostro-range-of-motion";
  s.header.fps = fps;
  const double step = 1.0;  // seconds per pose
  const long frames = std::lround(step * static_cast<double>(poses.size()) * fps);
  for (long i = 0; i < frames; ++i) {
    FapFrame f;
    f.index = i;
    f.time_s = static_cast<double>(i) / fps;
    std::array<double, kFapCount> values{};
    for (std::size_t k = 0; k < poses.size(); ++k) {
      const double w = bump(f.time_s, step * static_cast<double>(k), step);
      for (const auto& [id, v] : with_outer_lip(poses[k]))
        values[static_cast<std::size_t>(id - 1)] += w * v;
    }
    for (const auto& pose : poses)
      for (const auto& [id, v] : with_outer_lip(pose))
        f.set(id, std::round(values[static_cast<std::size_t>(id - 1)]));
    s.frames.push_back(f);
  }
  s.header.frame_count = frames;
  return s;
}

SynthResult synthesize(const FaceModel& model, const ExpressionLibrary* library,
                       const std::vector<PaintedMarker>& markers, const FapStream& drive,
                       const SynthOptions& o, render::FrameSink& sink,
                       const std::function<void(long)>& progress) {
  if (o.width < 16 || o.height < 16) throw InputError("synth: the image must be at least 16x16");
  if (!(drive.header.fps > 0)) throw InputError("synth: the FAP stream has no frame rate");
  if (drive.frames.empty()) throw InputError("synth: the FAP stream has no frames");
  if (o.motion_blur < 0 || o.motion_blur > 1)
    throw InputError("synth: --motion-blur must be in 0..1");
  if (o.light_amp < 0 || o.light_amp > 1) throw InputError("synth: --light must be in 0..1");
  if (!(std::abs(o.elevation_deg) <= kMaxElevationDeg))
    throw InputError(
        fmt::format("synth: --elevation must be within -{0:g}..{0:g} degrees", kMaxElevationDeg));

  render::RenderOptions ro;
  ro.width = o.width;
  ro.height = o.height;
  render::FaceRenderer face(model, library, ro);
  const double aspect = static_cast<double>(o.width) / o.height;
  render::CameraPose base = render::CameraPose::front();
  base.fov_deg = o.fov_deg;
  base.pitch_deg = o.elevation_deg;
  const double base_distance =
      render::frame_camera(base, face.framing(), aspect).distance * o.distance_scale;

  cv::RNG rng(o.seed);
  // Seeded phases so two seeds give different motion, one seed always the same.
  const double phase_pitch = rng.uniform(0.0, 2 * kPi), phase_roll = rng.uniform(0.0, 2 * kPi);
  const double phase_light = rng.uniform(0.0, 2 * kPi), phase_dist = rng.uniform(0.0, 2 * kPi);
  const double occluder_y = rng.uniform(0.55, 0.75);
  const double fps = drive.header.fps;
  const double duration = static_cast<double>(drive.frames.size()) / fps;

  SynthResult result;
  {
    render::CameraPose pose = base;
    pose.distance = base_distance;
    const auto m = render::frame_camera(pose, face.framing(), aspect);
    auto& k = result.intrinsics;
    k.image_size = {o.width, o.height};
    k.fx = double(m.projection(0, 0)) * o.width / 2.0;
    k.fy = double(m.projection(1, 1)) * o.height / 2.0;
    k.cx = o.width / 2.0 - 0.5;
    k.cy = o.height / 2.0 - 0.5;
    k.source = "rostro synth (exact: the renderer's projection)";
  }

  cv::Mat image, noise, blurred;
  std::vector<Eigen::Vector3f> normals;
  cv::Point2d previous_centre(std::numeric_limits<double>::quiet_NaN(), 0);
  long done = 0;
  for (const FapFrame& frame : drive.frames) {
    const double t = static_cast<double>(done) / fps;
    const double w = 2 * kPi * t / o.motion_period_s;
    render::CameraPose pose = base;
    pose.yaw_deg = o.yaw_deg * std::sin(w);
    pose.pitch_deg = o.elevation_deg + o.pitch_deg * std::sin(0.73 * w + phase_pitch);
    pose.roll_deg = o.roll_deg * std::sin(0.57 * w + phase_roll);
    pose.distance = base_distance * (1.0 + o.distance_amp * std::sin(0.41 * w + phase_dist));

    face.render_into(frame, pose, image);
    const render::PixelProjector projector{render::frame_camera(pose, face.framing(), aspect),
                                           o.width, o.height};
    const auto& positions = face.positions();
    face.deformer().normals(positions, normals);

    Occluder occ;
    if (o.occluder && duration > 0) {
      // Crosses from off the left edge to off the right edge between 35 % and 65 % of the clip.
      const double s = (t / duration - 0.35) / 0.30;
      if (s >= 0 && s <= 1) {
        occ.active = true;
        occ.axes = {0.09 * o.width, 0.16 * o.height};  // about a hand at this framing
        occ.centre = {-occ.axes.width + s * (o.width + 2 * occ.axes.width), occluder_y * o.height};
      }
    }

    tracking::TrackedFrame truth;
    truth.frame = frame.index;
    truth.time_s = t;
    cv::Point2d centre_sum(0, 0);
    int centre_count = 0;
    std::vector<std::pair<const tracking::MarkerSpec*, std::array<cv::Point2d, 4>>> tags;
    for (const PaintedMarker& pm : markers) {
      if (pm.spec->is_tag()) {
        tracking::MarkerObservation obs;
        obs.marker = pm.spec->id;
        obs.quality = 1.0;
        const auto [r, tr] = rigid_motion(pm.anchors, model.positions, positions);
        const Eigen::Vector3f c = r * pm.centre + tr, right = r * pm.right, up = r * pm.up;
        const Eigen::Vector3f n = r * pm.normal;
        const float h = static_cast<float>(pm.spec->size_mm / 2);
        // libapriltag's order: bottom-left, bottom-right, top-right, top-left.
        const Eigen::Vector3f corner3[4] = {c - h * right - h * up, c + h * right - h * up,
                                            c + h * right + h * up, c - h * right + h * up};
        std::array<cv::Point2d, 4> corners;
        bool in_front = projector.project(c, obs.position);
        bool inside = true;
        for (int q = 0; q < 4; ++q) {
          in_front =
              projector.project(corner3[q], corners[static_cast<std::size_t>(q)]) && in_front;
          const cv::Point2d& p = corners[static_cast<std::size_t>(q)];
          inside = inside && p.x >= 0 && p.y >= 0 && p.x <= o.width - 1 && p.y <= o.height - 1;
        }
        const bool facing = n.dot((projector.m.eye - c).normalized()) > 0.2f;
        obs.valid = in_front && facing && inside && !occ.covers(obs.position);
        if (in_front && facing) tags.emplace_back(pm.spec, corners);
        truth.markers.push_back(std::move(obs));
        continue;
      }
      const Eigen::Vector3f at = pm.place.on(positions);
      const Eigen::Vector3f normal = pm.place.on(normals).normalized();
      tracking::MarkerObservation obs;
      obs.marker = pm.spec->id;
      obs.feature_point = pm.spec->feature_point;
      obs.quality = 1.0;
      const bool in_front = projector.project(at, obs.position);
      const Eigen::Vector3f to_eye = projector.m.eye - at;
      const bool facing = normal.dot(to_eye.normalized()) > 0.1f;
      const bool inside = obs.position.x >= 0 && obs.position.y >= 0 &&
                          obs.position.x <= o.width - 1 && obs.position.y <= o.height - 1;
      obs.valid = in_front && facing && inside && !occ.covers(obs.position);
      // Landmarks are places on the bare skin: truth, nothing painted.
      if (in_front && facing && inside && pm.spec->kind == tracking::MarkerKind::Dot) {
        // The disc on the skin: a circle in the tangent plane, projected.
        const Eigen::Vector3f& n = normal;
        Eigen::Vector3f u = n.cross(Eigen::Vector3f::UnitY());
        if (u.norm() < 1e-3f) u = n.cross(Eigen::Vector3f::UnitX());
        u.normalize();
        const Eigen::Vector3f w2 = n.cross(u);
        const auto r = static_cast<float>(o.dot_diameter_mm / 2.0);
        std::vector<cv::Point> outline;
        for (int k = 0; k < 24; ++k) {
          const float angle = static_cast<float>(2 * kPi * k / 24);
          cv::Point2d q;
          if (!projector.project(at + r * (std::cos(angle) * u + std::sin(angle) * w2), q))
            continue;
          outline.emplace_back(cvRound(q.x * 16), cvRound(q.y * 16));  // 4 fractional bits
        }
        const cv::Scalar ink = o.dark_dots ? cv::Scalar(25, 22, 22) : cv::Scalar(245, 245, 245);
        if (outline.size() >= 3) cv::fillConvexPoly(image, outline, ink, cv::LINE_AA, 4);
      }
      if (in_front) {
        centre_sum += obs.position;
        ++centre_count;
      }
      truth.markers.push_back(std::move(obs));
    }
    for (const auto& [spec, corners] : tags) draw_tag(image, *spec, corners);
    result.truth.push_back(std::move(truth));

    if (occ.active)
      cv::ellipse(image, cv::Point(cvRound(occ.centre.x), cvRound(occ.centre.y)),
                  cv::Size(cvRound(occ.axes.width), cvRound(occ.axes.height)), 15, 0, 360,
                  cv::Scalar(120, 150, 200), cv::FILLED, cv::LINE_AA);

    // Motion blur along the face's image motion since the last frame, centred on now.
    const cv::Point2d centre = centre_count ? centre_sum / centre_count : previous_centre;
    if (o.motion_blur > 0 && std::isfinite(previous_centre.x) && std::isfinite(centre.x)) {
      const cv::Point2d motion = (centre - previous_centre) * o.motion_blur;
      const int length = cvRound(cv::norm(motion));
      if (length >= 2) {
        const int size = 2 * (length / 2) + 1;
        cv::Mat kernel = cv::Mat::zeros(size, size, CV_32F);
        const cv::Point2d dir = motion / cv::norm(motion) * (size / 2.0);
        const cv::Point2d mid(size / 2, size / 2);
        cv::line(kernel, cv::Point(mid - dir), cv::Point(mid + dir), cv::Scalar(1.0), 1,
                 cv::LINE_AA);
        kernel /= cv::sum(kernel)[0];
        cv::filter2D(image, blurred, -1, kernel);
        std::swap(image, blurred);
      }
    }
    previous_centre = centre;

    const double gain =
        o.brightness *
        (1.0 - o.light_amp * (0.5 - 0.5 * std::cos(2 * kPi * t / 3.0 + phase_light)));
    if (gain != 1.0 || o.noise_sigma > 0) {
      image.convertTo(blurred, CV_32FC3, gain);
      if (o.noise_sigma > 0) {
        noise.create(image.size(), CV_32FC3);
        rng.fill(noise, cv::RNG::NORMAL, 0.0, o.noise_sigma);
        blurred += noise;
      }
      blurred.convertTo(image, CV_8UC3);  // saturates to 0..255
    }
    sink.write(image);
    ++done;
    if (progress) progress(done);
  }
  sink.finish();
  return result;
}

void prepend_neutral(FapStream& stream, double seconds) {
  const auto lead =
      static_cast<std::size_t>(std::lround(std::max(0.0, seconds) * stream.header.fps));
  std::vector<FapFrame> frames(lead);
  frames.insert(frames.end(), stream.frames.begin(), stream.frames.end());
  for (std::size_t i = 0; i < frames.size(); ++i) {
    frames[i].index = static_cast<long>(i);
    frames[i].time_s = static_cast<double>(i) / stream.header.fps;
  }
  stream.frames = std::move(frames);
  stream.header.frame_count = static_cast<long>(stream.frames.size());
}

}  // namespace rostro::eval

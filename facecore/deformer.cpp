#include "facecore/deformer.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <map>

#include "facecore/error.hpp"
#include "facecore/expression_library.hpp"
#include "facecore/influence.hpp"

namespace rostro {
namespace {

using Eigen::Vector3d;

constexpr int kOpenJaw = 3, kThrustJaw = 14, kShiftJaw = 15;
constexpr int kYawLeftEye = 23, kYawRightEye = 24, kPitchLeftEye = 25, kPitchRightEye = 26;
constexpr int kThrustLeftEye = 27, kThrustRightEye = 28;
constexpr int kDilateLeft = 29, kDilateRight = 30;
constexpr int kTongueRoll = 47;
constexpr int kHeadPitch = 48, kHeadYaw = 49, kHeadRoll = 50;

// The FAPs (3..68) that translate a given feature point along their axis.
std::vector<int> translating_faps(FeaturePointId point) {
  std::vector<int> out;
  for (const FapInfo& fap : fap_table()) {
    if (fap.id < 3 || fap.unit == FapUnit::AU) continue;
    const auto axis = fap_axis(fap);
    if (axis[0] == 0 && axis[1] == 0 && axis[2] == 0) continue;
    if (parse_feature_point(fap.feature_point) == point) out.push_back(fap.id);
  }
  return out;
}

// Rotation of a part looking along +z: yaw toward the face's left (+x) is about +y, pitch
// down is about +x, roll toward the face's right is about +z.
Eigen::Matrix3d rotation(double pitch, double yaw, double roll) {
  return (Eigen::AngleAxisd(yaw, Vector3d::UnitY()) * Eigen::AngleAxisd(pitch, Vector3d::UnitX()) *
          Eigen::AngleAxisd(roll, Vector3d::UnitZ()))
      .toRotationMatrix();
}

}  // namespace

Deformer::Deformer(const FaceModel& model, const ExpressionLibrary* library)
    : model_(model), library_(library) {
  const auto n_vertices = static_cast<Eigen::Index>(model.positions.size());

  // A channel is one feature point moved by a set of FAPs; most regions use every FAP on
  // their points, some (the jaw-following parts) only a subset.
  std::map<std::pair<FeaturePointId, std::vector<int>>, int> channel_ids;
  std::vector<std::vector<int>> channel_fap_lists;
  auto channel = [&](FeaturePointId point, std::vector<int> faps) {
    std::vector<int> all = translating_faps(point);
    if (!faps.empty()) {
      std::vector<int> kept;
      for (int f : all)
        if (std::find(faps.begin(), faps.end(), f) != faps.end()) kept.push_back(f);
      all = kept;
    }
    auto [it, added] =
        channel_ids.try_emplace({point, all}, static_cast<int>(channel_points_.size()));
    if (added) {
      channel_points_.push_back(point);
      channel_fap_lists.push_back(all);
    }
    return it->second;
  };

  std::vector<Eigen::Triplet<float>> weight_entries;
  for (const InfluenceRegion& region : model.regions) {
    const RegionWeights w = compile_region(model, region);
    for (std::size_t k = 0; k < region.feature_points.size(); ++k) {
      const int c = channel(region.feature_points[k], region.faps);
      for (std::size_t i = 0; i < w.vertices.size(); ++i) {
        const double value = w.weights(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(k));
        if (value != 0.0) weight_entries.emplace_back(w.vertices[i], c, static_cast<float>(value));
      }
    }
  }
  // Parts that follow the jaw move by a fraction of the displacement of 2.1.
  const FeaturePointId chin{2, 1};
  for (const RigidPart* part : {&model.parts.upper_teeth, &model.parts.lower_teeth,
                                &model.parts.tongue, &model.parts.jaw}) {
    if (part->jaw_gain == 0.0 || part->empty()) continue;
    if (!model.has_feature_point(chin))
      throw InputError("face model '" + model.name +
                       "': a part follows the jaw but 2.1 is missing");
    const int c = channel(chin, {kOpenJaw, kThrustJaw, kShiftJaw});
    for (int v : part->vertices)
      weight_entries.emplace_back(v, c, static_cast<float>(part->jaw_gain));
  }

  const auto n_channels = static_cast<Eigen::Index>(channel_points_.size());
  weights_.resize(n_vertices, n_channels);
  weights_.setFromTriplets(weight_entries.begin(), weight_entries.end());
  weights_.makeCompressed();

  channel_faps_ = Eigen::MatrixXd::Zero(3 * n_channels, kFapCount);
  for (Eigen::Index k = 0; k < n_channels; ++k)
    for (int f : channel_fap_lists[static_cast<std::size_t>(k)]) {
      const FapInfo& info = fap_info(f);
      const auto axis = fap_axis(info);
      const double unit = model.fapu.unit_size(info.unit);
      for (int a = 0; a < 3; ++a)
        channel_faps_(3 * k + a, f - 1) = unit * axis[static_cast<std::size_t>(a)];
    }

  // Direct per-vertex terms: pupil dilation, eyeball thrust, tongue roll.
  std::vector<Eigen::Triplet<float>> direct;
  auto add = [&](int v, int fap, const Vector3d& d) {
    for (int a = 0; a < 3; ++a)
      if (d[a] != 0.0) direct.emplace_back(3 * v + a, fap - 1, static_cast<float>(d[a]));
  };
  const double irisd = model.fapu.unit_size(FapUnit::IRISD);
  const double es = model.fapu.unit_size(FapUnit::ES);
  struct Eye {
    const RigidPart* part;
    FeaturePointId pupil;
    int dilate, thrust;
  };
  for (const Eye& eye : {Eye{&model.parts.left_eyeball, {3, 5}, kDilateLeft, kThrustLeftEye},
                         Eye{&model.parts.right_eyeball, {3, 6}, kDilateRight, kThrustRightEye}}) {
    for (int v : eye.part->vertices) add(v, eye.thrust, Vector3d(0, 0, es));
    if (!model.has_feature_point(eye.pupil) || eye.part->empty()) continue;
    // The neutral iris is IRISD0 across (eyelids tangent to it) and the pupil a third of
    // that. A positive value widens the pupil's diameter by value x IRISD; the iris stretches
    // between the pupil edge and its fixed rim.
    const Vector3d centre = model.feature_point(eye.pupil);
    const Vector3d axis = (centre - eye.part->pivot).normalized();
    const double iris_r = model.fapu.irisd0 / 2.0, pupil_r = iris_r / 3.0;
    for (int v : eye.part->vertices) {
      const Vector3d p = model.positions[static_cast<std::size_t>(v)].cast<double>();
      const Vector3d rel = p - eye.part->pivot;
      if (rel.dot(axis) <= 0) continue;
      const Vector3d lateral = rel - rel.dot(axis) * axis;
      const double rho = lateral.norm();
      if (rho < 1e-9 || rho >= iris_r * 1.0001) continue;
      const double gain = rho <= pupil_r ? rho / pupil_r : (iris_r - rho) / (iris_r - pupil_r);
      add(v, eye.dilate, lateral / rho * gain * irisd / 2.0);
    }
  }
  if (!model.parts.tongue.empty() && model.has_feature_point({6, 1})) {
    // Tongue roll (AU, concave upward): the sides rise by |x - tip.x| x angle (small-angle
    // rotation of each half about the tongue's mid-line).
    const double mid_x = model.feature_point({6, 1}).x();
    for (int v : model.parts.tongue.vertices) {
      const double dx = std::abs(model.positions[static_cast<std::size_t>(v)].x() - mid_x);
      add(v, kTongueRoll, Vector3d(0, dx * kAngleUnitRad, 0));
    }
  }
  direct_.resize(3 * n_vertices, kFapCount);
  direct_.setFromTriplets(direct.begin(), direct.end());
  direct_.makeCompressed();

  neutral_.resize(3, n_vertices);
  for (Eigen::Index v = 0; v < n_vertices; ++v)
    neutral_.col(v) = model.positions[static_cast<std::size_t>(v)];
}

void Deformer::deform(const FapFrame& frame, std::vector<Eigen::Vector3f>& positions) const {
  const bool high_level = frame.has(kVisemeFap) || frame.has(kExpressionFap);
  const FapFrame expanded = (library_ != nullptr && high_level) ? library_->expand(frame) : frame;
  Eigen::VectorXd faps = Eigen::VectorXd::Zero(kFapCount);
  for (int id = 3; id <= kFapCount; ++id) faps[id - 1] = expanded.get(id);
  deform_low_level(faps, positions);
}

void Deformer::deform(const Eigen::VectorXd& faps, std::vector<Eigen::Vector3f>& positions) const {
  if (faps.size() != kFapCount) throw std::invalid_argument("Deformer::deform needs 68 FAP values");
  Eigen::VectorXd low = faps;
  low[0] = low[1] = 0.0;
  deform_low_level(low, positions);
}

void Deformer::deform_low_level(const Eigen::VectorXd& faps,
                                std::vector<Eigen::Vector3f>& out) const {
  const auto n = static_cast<std::size_t>(neutral_.cols());
  out.resize(n);
  // The head rotation (about 7.1) is applied in the same pass as the sparse product.
  const double head_pitch = faps[kHeadPitch - 1] * kAngleUnitRad,
               head_yaw = faps[kHeadYaw - 1] * kAngleUnitRad,
               head_roll = faps[kHeadRoll - 1] * kAngleUnitRad;
  const bool turn = head_pitch != 0.0 || head_yaw != 0.0 || head_roll != 0.0;
  const Eigen::Matrix3f r = rotation(head_pitch, head_yaw, head_roll).cast<float>();
  const Eigen::Vector3f pivot = model_.head_pivot.cast<float>();

  // Displacement of every channel's feature point, then one sparse product over vertices.
  const Eigen::VectorXf d = (channel_faps_ * faps).cast<float>();
  const float* dp = d.data();
  const int* outer = weights_.outerIndexPtr();
  const int* inner = weights_.innerIndexPtr();
  const float* value = weights_.valuePtr();
  const float* neutral = neutral_.data();
  for (std::size_t v = 0; v < n; ++v) {
    float x = neutral[3 * v], y = neutral[3 * v + 1], z = neutral[3 * v + 2];
    for (int i = outer[v]; i < outer[v + 1]; ++i) {
      const float w = value[i];
      const float* c = dp + 3 * inner[i];
      x += w * c[0];
      y += w * c[1];
      z += w * c[2];
    }
    const Eigen::Vector3f p(x, y, z);
    out[v] = turn ? Eigen::Vector3f(pivot + r * (p - pivot)) : p;
  }
  for (int f = 0; f < kFapCount; ++f) {
    if (faps[f] == 0.0) continue;
    const auto scale = static_cast<float>(faps[f]);
    for (Eigen::SparseMatrix<float>::InnerIterator it(direct_, f); it; ++it) {
      const auto v = static_cast<std::size_t>(it.row() / 3);
      const auto axis = static_cast<Eigen::Index>(it.row() % 3);
      if (turn)
        out[v] += r.col(axis) * (scale * it.value());
      else
        out[v][axis] += scale * it.value();
    }
  }

  // Eyeballs rotate about their (possibly thrust) centres before the head turns: undo the
  // head rotation for their few vertices, rotate, and turn them again.
  struct Eye {
    const RigidPart* part;
    int yaw, pitch, thrust;
  };
  const double es = model_.fapu.unit_size(FapUnit::ES);
  for (const Eye& eye :
       {Eye{&model_.parts.left_eyeball, kYawLeftEye, kPitchLeftEye, kThrustLeftEye},
        Eye{&model_.parts.right_eyeball, kYawRightEye, kPitchRightEye, kThrustRightEye}}) {
    const double yaw = faps[eye.yaw - 1] * kAngleUnitRad,
                 pitch = faps[eye.pitch - 1] * kAngleUnitRad;
    if (yaw == 0.0 && pitch == 0.0) continue;
    const Eigen::Vector3f centre =
        (eye.part->pivot + Vector3d(0, 0, faps[eye.thrust - 1] * es)).cast<float>();
    const Eigen::Matrix3f re = rotation(pitch, yaw, 0.0).cast<float>();
    for (int v : eye.part->vertices) {
      Eigen::Vector3f& p = out[static_cast<std::size_t>(v)];
      if (turn) p = pivot + r.transpose() * (p - pivot);
      p = centre + re * (p - centre);
      if (turn) p = pivot + r * (p - pivot);
    }
  }
}

void Deformer::normals(const std::vector<Eigen::Vector3f>& positions,
                       std::vector<Eigen::Vector3f>& normals) const {
  normals.assign(positions.size(), Eigen::Vector3f::Zero());
  for (const Eigen::Vector3i& t : model_.triangles) {
    const auto a = static_cast<std::size_t>(t[0]), b = static_cast<std::size_t>(t[1]),
               c = static_cast<std::size_t>(t[2]);
    // The cross product's length is twice the area: larger triangles weigh more.
    const Eigen::Vector3f n = (positions[b] - positions[a]).cross(positions[c] - positions[a]);
    normals[a] += n;
    normals[b] += n;
    normals[c] += n;
  }
  for (Eigen::Vector3f& n : normals) {
    const float len = n.norm();
    n = len > 0 ? Eigen::Vector3f(n / len) : Eigen::Vector3f(0, 0, 1);
  }
}

Eigen::SparseMatrix<double> Deformer::linear_map() const {
  std::vector<Eigen::Triplet<double>> entries;
  for (Eigen::Index v = 0; v < weights_.outerSize(); ++v)
    for (Eigen::SparseMatrix<float, Eigen::RowMajor>::InnerIterator it(weights_, v); it; ++it)
      for (int a = 0; a < 3; ++a)
        for (int f = 0; f < kFapCount; ++f) {
          const double m = channel_faps_(3 * it.col() + a, f);
          if (m != 0.0)
            entries.emplace_back(static_cast<int>(3 * v + a), f,
                                 static_cast<double>(it.value()) * m);
        }
  for (int f = 0; f < kFapCount; ++f)
    for (Eigen::SparseMatrix<float>::InnerIterator it(direct_, f); it; ++it)
      entries.emplace_back(static_cast<int>(it.row()), f, static_cast<double>(it.value()));
  Eigen::SparseMatrix<double> m(3 * neutral_.cols(), kFapCount);
  m.setFromTriplets(entries.begin(), entries.end());
  return m;
}

}  // namespace rostro

#include "facecore/deformer.hpp"

#include <omp.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

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
constexpr int kRunMax = 2048;

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

// The head's turn p -> r p + t as plain scalars, so that the loops keep them in registers.
struct Turn {
  float r00, r01, r02, r10, r11, r12, r20, r21, r22, t0, t1, t2;
};

// Places the vertices [begin, end) of a run: neutral place plus the weighted displacements of
// the run's `count` channels (the weights packed per vertex), turned with the head. kCount >= 0
// fixes the count when compiling, so that the channels' displacements stay in registers and
// the rigid runs (count 0) vectorise; -1 takes it from `count`.
template <int kCount>
void place_run(int begin, int end, int count, const float* __restrict weights,
               const int* __restrict channels, const Eigen::Matrix4Xf& displacement,
               const float* __restrict neutral, const Turn m, float* __restrict o) {
  const int n = kCount >= 0 ? kCount : count;
  constexpr int kHeld = kCount > 0 ? kCount : 1;
  Eigen::Vector4f held[kHeld];
  for (int j = 0; j < kCount; ++j) held[j] = displacement.col(channels[j]);
  for (long v = 3L * begin; v < 3L * end; v += 3, weights += n) {
    Eigen::Vector4f sum = Eigen::Vector4f::Zero();
    if constexpr (kCount >= 0) {
      for (int j = 0; j < kCount; ++j) sum += weights[j] * held[j];
    } else {
      for (int j = 0; j < n; ++j) sum += weights[j] * displacement.col(channels[j]);
    }
    const float x = neutral[v] + sum[0], y = neutral[v + 1] + sum[1], z = neutral[v + 2] + sum[2];
    o[v] = m.r00 * x + m.r01 * y + m.r02 * z + m.t0;
    o[v + 1] = m.r10 * x + m.r11 * y + m.r12 * z + m.t1;
    o[v + 2] = m.r20 * x + m.r21 * y + m.r22 * z + m.t2;
  }
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
  Eigen::SparseMatrix<float, Eigen::RowMajor> vertex_weights(n_vertices, n_channels);
  vertex_weights.setFromTriplets(weight_entries.begin(), weight_entries.end());
  vertex_weights.makeCompressed();

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
  // (3V x 68, a row per vertex and axis: compacted below to the vertices that have any.)
  Eigen::SparseMatrix<float, Eigen::RowMajor> direct_terms(3 * n_vertices, kFapCount);
  direct_terms.setFromTriplets(direct.begin(), direct.end());

  neutral_.resize(3, n_vertices);
  for (Eigen::Index v = 0; v < n_vertices; ++v)
    neutral_.col(v) = model.positions[static_cast<std::size_t>(v)];

  // Runs of consecutive vertices weighted on the same channels (in a region, all of them),
  // cut at kRunMax vertices so that threads share them evenly.
  const int* channels_of = vertex_weights.innerIndexPtr();
  for (Eigen::Index v = 0; v < n_vertices; ++v) {
    const int first = vertex_weights.outerIndexPtr()[v],
              last = vertex_weights.outerIndexPtr()[v + 1];
    const int u = static_cast<int>(v);
    if (runs_.empty() || runs_.back().count != last - first ||
        runs_.back().end - runs_.back().begin >= kRunMax ||
        !std::equal(channels_of + first, channels_of + last,
                    run_channels_.begin() + runs_.back().channels)) {
      runs_.push_back({u, u, last - first, static_cast<int>(run_weights_.size()),
                       static_cast<int>(run_channels_.size())});
      run_channels_.insert(run_channels_.end(), channels_of + first, channels_of + last);
    }
    ++runs_.back().end;
    run_weights_.insert(run_weights_.end(), vertex_weights.valuePtr() + first,
                        vertex_weights.valuePtr() + last);
  }
  // The vertices with direct terms, each a row of its own.
  std::vector<Eigen::Triplet<float>> compact;
  for (Eigen::Index v = 0; v < n_vertices; ++v) {
    bool any = false;
    for (int a = 0; a < 3; ++a)
      for (Eigen::SparseMatrix<float, Eigen::RowMajor>::InnerIterator it(direct_terms, 3 * v + a);
           it; ++it) {
        compact.emplace_back(static_cast<int>(direct_vertices_.size()),
                             static_cast<int>(3 * it.col() + a), it.value());
        any = true;
      }
    if (any) direct_vertices_.push_back(static_cast<int>(v));
  }
  direct_.resize(static_cast<Eigen::Index>(direct_vertices_.size()), 3 * kFapCount);
  direct_.setFromTriplets(compact.begin(), compact.end());
  direct_.makeCompressed();
}

void Deformer::set_threads(int threads) {
  if (threads < 0) throw std::invalid_argument("Deformer::set_threads needs 0 or more threads");
  threads_ = threads;
}

int Deformer::threads() const {
  if (threads_ > 0) return threads_;
  if (static_cast<std::size_t>(neutral_.cols()) < kParallelVertices) return 1;
  return std::max(1, omp_get_num_procs());
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
  const auto n = static_cast<long>(neutral_.cols());
  out.resize(static_cast<std::size_t>(n));
  // The head turns about 7.1: p -> r p + (pivot - r pivot).
  const double head_pitch = faps[kHeadPitch - 1] * kAngleUnitRad,
               head_yaw = faps[kHeadYaw - 1] * kAngleUnitRad,
               head_roll = faps[kHeadRoll - 1] * kAngleUnitRad;
  const Eigen::Matrix3f r = rotation(head_pitch, head_yaw, head_roll).cast<float>();
  const Eigen::Vector3f pivot = model_.head_pivot.cast<float>();
  const Eigen::Vector3f shift = pivot - r * pivot;
  const Turn turn{r(0, 0), r(0, 1), r(0, 2), r(1, 0),  r(1, 1),  r(1, 2),
                  r(2, 0), r(2, 1), r(2, 2), shift[0], shift[1], shift[2]};

  // Displacement of every channel's feature point, padded to four floats so that one weight
  // is one vector multiply-add.
  const Eigen::VectorXd displacement = channel_faps_ * faps;
  Eigen::Matrix4Xf channels = Eigen::Matrix4Xf::Zero(4, displacement.size() / 3);
  for (Eigen::Index k = 0; k < channels.cols(); ++k)
    channels.col(k).head<3>() = displacement.segment<3>(3 * k).cast<float>();
  const Eigen::VectorXf fap_values = faps.cast<float>();
  const float* neutral = neutral_.data();
  float* o = out.data()->data();
  const auto n_runs = static_cast<long>(runs_.size());
  const auto n_direct = static_cast<long>(direct_vertices_.size());
  const int n_threads = threads();
  static_assert(sizeof(Eigen::Vector3f) == 3 * sizeof(float), "out is read as packed floats");

#pragma omp parallel num_threads(n_threads) if (n_threads > 1)
  {
#pragma omp for schedule(dynamic, 4)
    for (long i = 0; i < n_runs; ++i) {
      const VertexRun& run = runs_[static_cast<std::size_t>(i)];
      const float* w = run_weights_.data() + run.weights;
      const int* c = run_channels_.data() + run.channels;
      switch (run.count) {
        case 0:
          place_run<0>(run.begin, run.end, 0, w, c, channels, neutral, turn, o);
          break;
        case 1:
          place_run<1>(run.begin, run.end, 1, w, c, channels, neutral, turn, o);
          break;
        case 2:
          place_run<2>(run.begin, run.end, 2, w, c, channels, neutral, turn, o);
          break;
        case 3:
          place_run<3>(run.begin, run.end, 3, w, c, channels, neutral, turn, o);
          break;
        default:
          place_run<-1>(run.begin, run.end, run.count, w, c, channels, neutral, turn, o);
      }
    }
    // The direct terms, turned with the head (after the loop above has placed the vertex).
#pragma omp for schedule(static)
    for (long i = 0; i < n_direct; ++i) {
      Eigen::Vector3f d = Eigen::Vector3f::Zero();
      for (Eigen::SparseMatrix<float, Eigen::RowMajor>::InnerIterator it(direct_, i); it; ++it)
        d[it.col() % 3] += it.value() * fap_values[it.col() / 3];
      out[static_cast<std::size_t>(direct_vertices_[static_cast<std::size_t>(i)])] += r * d;
    }
  }

  // Eyeballs rotate about their (possibly thrust) centres before the head turns. For a vertex
  // already turned with the head (o = pivot + r (p - pivot)) that is one affine map,
  // o -> m (o - pivot) + q with m = r re r^T and q = pivot + (r - r re)(centre - pivot).
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
    const Eigen::Matrix3f m = r * re * r.transpose();
    const Eigen::Vector3f q = pivot + (r - r * re) * (centre - pivot);
    for (int v : eye.part->vertices) {
      Eigen::Vector3f& p = out[static_cast<std::size_t>(v)];
      p = m * (p - pivot) + q;
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
  for (const VertexRun& run : runs_)
    for (int v = run.begin; v < run.end; ++v)
      for (int j = 0; j < run.count; ++j) {
        const auto k = static_cast<std::size_t>(run.weights + (v - run.begin) * run.count + j);
        const int channel = run_channels_[static_cast<std::size_t>(run.channels + j)];
        for (int a = 0; a < 3; ++a)
          for (int f = 0; f < kFapCount; ++f) {
            const double m = channel_faps_(3 * channel + a, f);
            if (m != 0.0)
              entries.emplace_back(3 * v + a, f, static_cast<double>(run_weights_[k]) * m);
          }
      }
  for (Eigen::Index i = 0; i < direct_.rows(); ++i)
    for (Eigen::SparseMatrix<float, Eigen::RowMajor>::InnerIterator it(direct_, i); it; ++it)
      entries.emplace_back(
          3 * direct_vertices_[static_cast<std::size_t>(i)] + static_cast<int>(it.col() % 3),
          static_cast<int>(it.col() / 3), static_cast<double>(it.value()));
  Eigen::SparseMatrix<double> m(3 * neutral_.cols(), kFapCount);
  m.setFromTriplets(entries.begin(), entries.end());
  return m;
}

}  // namespace rostro

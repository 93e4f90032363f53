#include "facecore/deformer.hpp"

#include <omp.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <atomic>
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
constexpr int kHeldMax = 16;
constexpr int kHeldCount = -1, kGathered = -2;
std::atomic<std::uint64_t> compiled_deformers{0};

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

  Eigen::Matrix3f rotation() const {
    return (Eigen::Matrix3f() << r00, r01, r02, r10, r11, r12, r20, r21, r22).finished();
  }
  // The turn blended with staying put, p -> w (r p + t) + (1 - w) p: a neck vertex between the
  // turning head (w = 1) and the shoulders (w = 0). At w = 0.5 the blend shortens what lies
  // across the turn's axis by 1 - cos(angle / 2): 3 % for a 30-degree turn.
  Turn share(float w) const {
    const float s = 1.0f - w;
    return {w * r00 + s, w * r01, w * r02,     w * r10, w * r11 + s, w * r12,
            w * r20,     w * r21, w * r22 + s, w * t0,  w * t1,      w * t2};
  }
  Eigen::Matrix<float, 12, 1> values() const {
    return (Eigen::Matrix<float, 12, 1>() << r00, r01, r02, r10, r11, r12, r20, r21, r22, t0, t1,
            t2)
        .finished();
  }
};

// The head turns about 7.1 (`pivot`): p -> r p + (pivot - r pivot).
Turn head_turn(const Eigen::VectorXd& faps, const Vector3d& pivot) {
  const Eigen::Matrix3f r =
      rotation(faps[kHeadPitch - 1] * kAngleUnitRad, faps[kHeadYaw - 1] * kAngleUnitRad,
               faps[kHeadRoll - 1] * kAngleUnitRad)
          .cast<float>();
  const Eigen::Vector3f p = pivot.cast<float>();
  const Eigen::Vector3f shift = p - r * p;
  return {r(0, 0), r(0, 1), r(0, 2), r(1, 0),  r(1, 1),  r(1, 2),
          r(2, 0), r(2, 1), r(2, 2), shift[0], shift[1], shift[2]};
}

// On x86-64 the run loop is compiled twice, for AVX2 and for any x86-64, and the loader picks
// what the processor has: a frame takes about a third less time with AVX2 (docs/benchmarks.md).
// Not with FMA: a fused multiply-add rounds differently, so that a frame would depend on the
// processor (with FMA, one frame of a rendered test clip tracked differently).
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define ROSTRO_CLONED_FOR_AVX2 __attribute__((target_clones("avx2", "default")))
#else
#define ROSTRO_CLONED_FOR_AVX2
#endif

// Places the vertices [begin, end) of a run: neutral place plus the weighted displacements of
// the run's `count` channels (the weights packed per vertex), turned with the head. kCount >= 0
// fixes the count when compiling, so that the channels' displacements stay in registers and
// the rigid runs (count 0) vectorise; kHeldCount takes it from `count` (at most kHeldMax),
// kGathered too but reads each displacement where it is, for each vertex.
template <int kCount>
ROSTRO_CLONED_FOR_AVX2 void place_run(int begin, int end, int count,
                                      const float* __restrict weights,
                                      const int* __restrict channels,
                                      const Eigen::Matrix3Xf& displacement,
                                      const float* __restrict neutral, const Turn m,
                                      float* __restrict o) {
  const int n = kCount >= 0 ? kCount : count;
  constexpr int kHeld = kCount >= 0 ? std::max(kCount, 1) : kHeldMax;
  float hx[kHeld], hy[kHeld], hz[kHeld];
  if constexpr (kCount != kGathered)
    for (int j = 0; j < n; ++j) {
      hx[j] = displacement(0, channels[j]);
      hy[j] = displacement(1, channels[j]);
      hz[j] = displacement(2, channels[j]);
    }
  const long vertices = end - begin;
  neutral += 3L * begin;
  o += 3L * begin;
  for (long i = 0; i < vertices; ++i) {
    const long v = 3 * i;
    const float* w = weights + i * n;
    float sx = 0, sy = 0, sz = 0;
    if constexpr (kCount != kGathered) {
      for (int j = 0; j < n; ++j) {
        sx += w[j] * hx[j];
        sy += w[j] * hy[j];
        sz += w[j] * hz[j];
      }
    } else {
      for (int j = 0; j < n; ++j) {
        sx += w[j] * displacement(0, channels[j]);
        sy += w[j] * displacement(1, channels[j]);
        sz += w[j] * displacement(2, channels[j]);
      }
    }
    const float x = neutral[v] + sx, y = neutral[v + 1] + sy, z = neutral[v + 2] + sz;
    o[v] = m.r00 * x + m.r01 * y + m.r02 * z + m.t0;
    o[v + 1] = m.r10 * x + m.r11 * y + m.r12 * z + m.t1;
    o[v + 2] = m.r20 * x + m.r21 * y + m.r22 * z + m.t2;
  }
}

}  // namespace

Deformer::Deformer(const FaceModel& model, const ExpressionLibrary* library)
    : model_(model), library_(library), id_(++compiled_deformers) {
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
      // A point none of the region's FAPs moves holds the region's shape but carries nothing.
      if (channel_fap_lists[static_cast<std::size_t>(c)].empty()) continue;
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
  std::vector<std::vector<DirectTerm>> direct(kFapCount + 1);  // by FAP id
  auto add = [&](int v, int fap, const Vector3d& d) {
    if (d.isZero()) return;
    const Eigen::Vector3f term = d.cast<float>();
    direct[static_cast<std::size_t>(fap)].push_back({v, term.x(), term.y(), term.z()});
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
  for (int fap = 1; fap <= kFapCount; ++fap) {
    auto& terms = direct[static_cast<std::size_t>(fap)];
    if (terms.empty()) continue;
    // One term per vertex (summed), so that the frame can split a FAP's terms over threads.
    std::stable_sort(terms.begin(), terms.end(),
                     [](const DirectTerm& a, const DirectTerm& b) { return a.vertex < b.vertex; });
    const auto begin = static_cast<int>(direct_terms_.size());
    for (const DirectTerm& term : terms) {
      if (static_cast<int>(direct_terms_.size()) > begin &&
          direct_terms_.back().vertex == term.vertex) {
        direct_terms_.back().x += term.x;
        direct_terms_.back().y += term.y;
        direct_terms_.back().z += term.z;
      } else {
        direct_terms_.push_back(term);
      }
    }
    direct_faps_.push_back({fap, begin, static_cast<int>(direct_terms_.size())});
  }

  neutral_.resize(3, n_vertices);
  for (Eigen::Index v = 0; v < n_vertices; ++v)
    neutral_.col(v) = model.positions[static_cast<std::size_t>(v)];

  // The vertices moved after the run loop: direct terms and the eyeballs' gaze.
  std::vector<bool> moved_after(static_cast<std::size_t>(n_vertices), false);
  for (const DirectTerm& term : direct_terms_)
    moved_after[static_cast<std::size_t>(term.vertex)] = true;
  for (const RigidPart* eye : {&model.parts.left_eyeball, &model.parts.right_eyeball})
    for (int v : eye->vertices) moved_after[static_cast<std::size_t>(v)] = true;

  std::vector<float> turn_share(static_cast<std::size_t>(n_vertices), 1.0f);
  for (std::size_t i = 0; i < model.turn_weights.vertices.size(); ++i)
    turn_share[static_cast<std::size_t>(model.turn_weights.vertices[i])] =
        static_cast<float>(model.turn_weights.weights[i]);

  // Runs of consecutive vertices weighted on the same channels (in a region, all of them),
  // cut at kRunMax vertices so that threads share them evenly, and where stillness or the
  // share of the head's turn changes.
  const int* channels_of = vertex_weights.innerIndexPtr();
  for (Eigen::Index v = 0; v < n_vertices; ++v) {
    const int first = vertex_weights.outerIndexPtr()[v],
              last = vertex_weights.outerIndexPtr()[v + 1];
    const int u = static_cast<int>(v);
    const bool still = first == last && !moved_after[static_cast<std::size_t>(v)];
    const float share = turn_share[static_cast<std::size_t>(v)];
    if (runs_.empty() || runs_.back().count != last - first || runs_.back().still != still ||
        runs_.back().turn_share != share || runs_.back().end - runs_.back().begin >= kRunMax ||
        !std::equal(channels_of + first, channels_of + last,
                    run_channels_.begin() + runs_.back().channels)) {
      runs_.push_back({u, u, last - first, static_cast<int>(run_weights_.size()),
                       static_cast<int>(run_channels_.size()), still, share});
      run_channels_.insert(run_channels_.end(), channels_of + first, channels_of + last);
    }
    ++runs_.back().end;
    run_weights_.insert(run_weights_.end(), vertex_weights.valuePtr() + first,
                        vertex_weights.valuePtr() + last);
  }
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

Eigen::VectorXd Deformer::low_level(const FapFrame& frame) const {
  const bool high_level = frame.has(kVisemeFap) || frame.has(kExpressionFap);
  const FapFrame expanded = (library_ != nullptr && high_level) ? library_->expand(frame) : frame;
  Eigen::VectorXd faps = Eigen::VectorXd::Zero(kFapCount);
  for (int id = 3; id <= kFapCount; ++id) faps[id - 1] = expanded.get(id);
  return faps;
}

Eigen::VectorXd Deformer::low_level(const Eigen::VectorXd& faps) {
  if (faps.size() != kFapCount) throw std::invalid_argument("Deformer::deform needs 68 FAP values");
  Eigen::VectorXd low = faps;
  low[0] = low[1] = 0.0;
  return low;
}

void Deformer::deform(const FapFrame& frame, std::vector<Eigen::Vector3f>& positions) const {
  deform_low_level(low_level(frame), false, positions);
}

void Deformer::deform(const Eigen::VectorXd& faps, std::vector<Eigen::Vector3f>& positions) const {
  deform_low_level(low_level(faps), false, positions);
}

void Deformer::deform(const FapFrame& frame, DeformedMesh& mesh) const {
  deform_low_level(low_level(frame), mesh);
}

void Deformer::deform(const Eigen::VectorXd& faps, DeformedMesh& mesh) const {
  deform_low_level(low_level(faps), mesh);
}

void Deformer::deform_low_level(const Eigen::VectorXd& faps, DeformedMesh& mesh) const {
  const Turn turn = head_turn(faps, model_.head_pivot);
  const bool same_turn = mesh.deformer_ == id_ &&
                         mesh.positions_.size() == static_cast<std::size_t>(neutral_.cols()) &&
                         mesh.turn_ == turn.values();
  mesh.deformer_ = 0;  // (if deforming throws, nothing is known of what the mesh holds)
  deform_low_level(faps, same_turn, mesh.positions_);
  mesh.deformer_ = id_;
  mesh.turn_ = turn.values();
}

void Deformer::deform_low_level(const Eigen::VectorXd& faps, bool keep_still,
                                std::vector<Eigen::Vector3f>& out) const {
  const auto n = static_cast<long>(neutral_.cols());
  out.resize(static_cast<std::size_t>(n));
  const Turn head = head_turn(faps, model_.head_pivot);
  const Eigen::Matrix3f r = head.rotation();
  const Eigen::Vector3f pivot = model_.head_pivot.cast<float>();

  // Displacement of every channel's feature point (a column each).
  const Eigen::VectorXd displacement = channel_faps_ * faps;
  const Eigen::Matrix3Xf channels =
      Eigen::Map<const Eigen::Matrix3Xd>(displacement.data(), 3, displacement.size() / 3)
          .cast<float>();
  const Eigen::VectorXf fap_values = faps.cast<float>();
  const float* neutral = neutral_.data();
  float* o = out.data()->data();
  const auto n_runs = static_cast<long>(runs_.size());
  const int n_threads = threads();
  static_assert(sizeof(Eigen::Vector3f) == 3 * sizeof(float), "out is read as packed floats");

#pragma omp parallel num_threads(n_threads) if (n_threads > 1)
  {
#pragma omp for schedule(dynamic, 4)
    for (long i = 0; i < n_runs; ++i) {
      const VertexRun& run = runs_[static_cast<std::size_t>(i)];
      if (keep_still && run.still) continue;
      const Turn turn = run.turn_share == 1.0f ? head : head.share(run.turn_share);
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
          if (run.count <= kHeldMax)
            place_run<kHeldCount>(run.begin, run.end, run.count, w, c, channels, neutral, turn, o);
          else
            place_run<kGathered>(run.begin, run.end, run.count, w, c, channels, neutral, turn, o);
      }
    }
    // The direct terms, turned with the head (after the loop above has placed the vertex).
    for (const DirectFap& fap : direct_faps_) {
      const float value = fap_values[fap.fap - 1];
      if (value == 0.0f) continue;
      const Eigen::Matrix3f turned = value * r;
#pragma omp for schedule(static)
      for (int i = fap.begin; i < fap.end; ++i) {
        const DirectTerm& term = direct_terms_[static_cast<std::size_t>(i)];
        out[static_cast<std::size_t>(term.vertex)] +=
            turned * Eigen::Vector3f(term.x, term.y, term.z);
      }
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
  for (const DirectFap& fap : direct_faps_)
    for (int i = fap.begin; i < fap.end; ++i) {
      const DirectTerm& term = direct_terms_[static_cast<std::size_t>(i)];
      const float d[3] = {term.x, term.y, term.z};
      for (int a = 0; a < 3; ++a)
        if (d[a] != 0.0f)
          entries.emplace_back(3 * term.vertex + a, fap.fap - 1, static_cast<double>(d[a]));
    }
  Eigen::SparseMatrix<double> m(3 * neutral_.cols(), kFapCount);
  m.setFromTriplets(entries.begin(), entries.end());
  return m;
}

}  // namespace rostro

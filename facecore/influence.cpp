#include "facecore/influence.hpp"

#include <Eigen/LU>
#include <cmath>
#include <numbers>

#include "facecore/error.hpp"

namespace rostro {
namespace {

using Eigen::MatrixXd;
using Eigen::Vector3d;

Vector3d vertex(const FaceModel& model, int v) {
  return model.positions[static_cast<std::size_t>(v)].cast<double>();
}

double scaled_distance(const Vector3d& a, const Vector3d& b, const Vector3d& metric) {
  return (a - b).cwiseProduct(metric).norm();
}

std::vector<Vector3d> centres(const FaceModel& model, const InfluenceRegion& region) {
  std::vector<Vector3d> out;
  for (FeaturePointId p : region.feature_points) out.push_back(model.feature_point(p));
  return out;
}

// The reach of a cosine centred at `c`: the region's d_max, else its farthest vertex.
double reach(const FaceModel& model, const InfluenceRegion& region, const Vector3d& c) {
  if (region.d_max > 0) return region.d_max;
  double d_max = 0;
  for (int v : region.vertices)
    d_max = std::max(d_max, scaled_distance(vertex(model, v), c, region.metric));
  // A cosine of zero reach would divide by zero; the point then moves alone.
  return d_max > 0 ? d_max : 1.0;
}

[[noreturn]] void fail(const InfluenceRegion& region, const std::string& what) {
  throw InputError("region '" + region.name + "': " + what);
}

// RBF interpolation of displacements: centres are the feature points (moving) and the
// anchors (held still). W = H^-1 T gives the coefficients; a vertex receives K H^-1 T, so its
// weight for feature point j is (K H^-1)(:, j). At a centre K's row equals H's row, so
// feature points move exactly by their displacement and zero FAPs move nothing.
MatrixXd rbf_weights(const FaceModel& model, const InfluenceRegion& region) {
  std::vector<Vector3d> c = centres(model, region);
  const auto moving = static_cast<Eigen::Index>(c.size());
  for (int a : region.anchors) c.push_back(vertex(model, a));
  const auto n = static_cast<Eigen::Index>(c.size());
  Eigen::VectorXd stiffness(n);  // s_j: distance to the nearest other centre (Eck)
  for (Eigen::Index j = 0; j < n; ++j) {
    double nearest = std::numeric_limits<double>::infinity();
    for (Eigen::Index i = 0; i < n; ++i)
      if (i != j)
        nearest = std::min(
            nearest, (c[static_cast<std::size_t>(i)] - c[static_cast<std::size_t>(j)]).norm());
    if (n == 1) nearest = 1.0;
    if (nearest < 1e-9)
      fail(region, "two RBF centres (feature points or anchors) are at the same position");
    stiffness[j] = nearest;
  }
  MatrixXd h(n, n);
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = 0; j < n; ++j)
      h(i, j) = multiquadric(
          (c[static_cast<std::size_t>(i)] - c[static_cast<std::size_t>(j)]).norm(), stiffness[j]);
  Eigen::FullPivLU<MatrixXd> lu(h);
  if (!lu.isInvertible()) fail(region, "the RBF system is singular");
  const MatrixXd h_inv = lu.inverse();
  const auto m = static_cast<Eigen::Index>(region.vertices.size());
  MatrixXd k(m, n);
  for (Eigen::Index r = 0; r < m; ++r) {
    const Vector3d p = vertex(model, region.vertices[static_cast<std::size_t>(r)]);
    for (Eigen::Index j = 0; j < n; ++j)
      k(r, j) = multiquadric((p - c[static_cast<std::size_t>(j)]).norm(), stiffness[j]);
  }
  return k * h_inv.leftCols(moving);
}

// The average of per-point raised cosines R (M x K). Averaging alone would move a feature
// point by less than its displacement wherever cosines overlap, so the per-point amplitudes
// are solved (G a = displacement, G_jk = R_k(point j)) to make each point exact.
MatrixXd averaged_cosine_weights(const FaceModel& model, const InfluenceRegion& region) {
  const std::vector<Vector3d> c = centres(model, region);
  const auto n = static_cast<Eigen::Index>(c.size());
  std::vector<double> reaches;
  for (const Vector3d& p : c) reaches.push_back(reach(model, region, p));
  auto cosine = [&](const Vector3d& p, Eigen::Index k) {
    const auto ks = static_cast<std::size_t>(k);
    return raised_cosine(scaled_distance(p, c[ks], region.metric), reaches[ks]) /
           static_cast<double>(n);
  };
  MatrixXd g(n, n);
  for (Eigen::Index j = 0; j < n; ++j)
    for (Eigen::Index k = 0; k < n; ++k) g(j, k) = cosine(c[static_cast<std::size_t>(j)], k);
  Eigen::FullPivLU<MatrixXd> lu(g);
  if (!lu.isInvertible())
    fail(region, "the averaged cosines cannot be solved (feature points at the same place?)");
  const auto m = static_cast<Eigen::Index>(region.vertices.size());
  MatrixXd r(m, n);
  for (Eigen::Index i = 0; i < m; ++i) {
    const Vector3d p = vertex(model, region.vertices[static_cast<std::size_t>(i)]);
    for (Eigen::Index k = 0; k < n; ++k) r(i, k) = cosine(p, k);
  }
  return r * lu.inverse();
}

}  // namespace

double raised_cosine(double d, double d_max) {
  if (d >= d_max) return 0.0;
  return 0.5 * (1.0 + std::cos(std::numbers::pi * d / d_max));
}

double multiquadric(double r, double s) {
  return std::sqrt(r * r + s * s);
}

RegionWeights compile_region(const FaceModel& model, const InfluenceRegion& region) {
  RegionWeights out;
  out.vertices = region.vertices;
  const auto m = static_cast<Eigen::Index>(region.vertices.size());
  const auto n = static_cast<Eigen::Index>(region.feature_points.size());
  switch (region.kind) {
    case InfluenceKind::RaisedCosine: {
      const Vector3d c = model.feature_point(region.feature_points.at(0));
      const double d_max = reach(model, region, c);
      out.weights.resize(m, 1);
      for (Eigen::Index i = 0; i < m; ++i)
        out.weights(i, 0) = raised_cosine(
            scaled_distance(vertex(model, region.vertices[static_cast<std::size_t>(i)]), c,
                            region.metric),
            d_max);
      break;
    }
    case InfluenceKind::Rbf:
      out.weights = rbf_weights(model, region);
      break;
    case InfluenceKind::AveragedCosine:
      out.weights = averaged_cosine_weights(model, region);
      break;
    case InfluenceKind::Rigid:
      out.weights = MatrixXd::Constant(m, n, region.gain);
      break;
  }
  // A feature point's own vertex moves exactly with it: remove round-off of the solves.
  for (Eigen::Index i = 0; i < m; ++i)
    for (Eigen::Index k = 0; k < n; ++k) {
      const auto fp = model.feature_points.find(region.feature_points[static_cast<std::size_t>(k)]);
      if (region.kind != InfluenceKind::Rigid &&
          fp->second == region.vertices[static_cast<std::size_t>(i)]) {
        out.weights.row(i).setZero();
        out.weights(i, k) = 1.0;
      }
    }
  if (!region.vertex_weights.empty())
    for (Eigen::Index i = 0; i < m; ++i)
      out.weights.row(i) *= region.vertex_weights[static_cast<std::size_t>(i)];
  return out;
}

}  // namespace rostro

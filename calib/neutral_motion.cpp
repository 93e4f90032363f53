#include "calib/neutral_motion.hpp"

#include <fmt/format.h>

#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <map>

namespace rostro::calib {
namespace {

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

double percentile90(std::vector<double> v) {
  const auto k = static_cast<long>(std::floor(0.9 * static_cast<double>(v.size() - 1)));
  std::nth_element(v.begin(), v.begin() + k, v.end());
  return v[static_cast<std::size_t>(k)];
}

}  // namespace

std::optional<NeutralMotion> measure_neutral_motion(
    const std::vector<tracking::TrackedFrame>& frames) {
  // The median shape: each marker valid in at least half the frames, at its median position.
  std::map<std::string, std::vector<cv::Point2d>> seen;
  for (const auto& f : frames)
    for (const auto& m : f.markers)
      if (m.valid) seen[m.marker].push_back(m.position);
  std::map<std::string, Eigen::Vector2d> shape;
  for (const auto& [id, points] : seen) {
    if (2 * points.size() < frames.size()) continue;
    std::vector<double> xs, ys;
    for (const auto& p : points) xs.push_back(p.x), ys.push_back(p.y);
    shape[id] = {median(xs), median(ys)};
  }
  if (shape.size() < 3) return std::nullopt;
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  for (const auto& [id, p] : shape) centroid += p;
  centroid /= static_cast<double>(shape.size());
  double size_sq = 0;
  for (const auto& [id, p] : shape) size_sq += (p - centroid).squaredNorm();
  const double face_size = std::sqrt(size_sq / static_cast<double>(shape.size()));

  std::map<std::string, std::vector<double>> displacement;
  long compared = 0;
  for (const auto& f : frames) {
    std::vector<std::string> ids;
    std::vector<Eigen::Vector2d> from, to;
    for (const auto& m : f.markers) {
      const auto it = shape.find(m.marker);
      if (!m.valid || it == shape.end()) continue;
      ids.push_back(m.marker);
      from.emplace_back(m.position.x, m.position.y);
      to.push_back(it->second);
    }
    if (ids.size() < 4) continue;  // an affine map fits any three
    // The affine map from this frame's markers to the median shape, by least squares.
    const auto n = static_cast<Eigen::Index>(ids.size());
    Eigen::MatrixXd x(n, 3), y(n, 2);
    for (Eigen::Index i = 0; i < n; ++i) {
      x.row(i) << from[static_cast<std::size_t>(i)].transpose(), 1.0;
      y.row(i) = to[static_cast<std::size_t>(i)].transpose();
    }
    const Eigen::MatrixXd map = x.colPivHouseholderQr().solve(y);  // 3 x 2
    const Eigen::MatrixXd aligned = x * map;
    for (Eigen::Index i = 0; i < n; ++i)
      displacement[ids[static_cast<std::size_t>(i)]].push_back((aligned.row(i) - y.row(i)).norm());
    ++compared;
  }
  if (compared < 2) return std::nullopt;
  NeutralMotion worst;
  worst.face_size_px = face_size;
  for (const auto& [id, d] : displacement) {
    const double p90 = percentile90(d);
    if (p90 > worst.displacement_px || worst.marker.empty()) {
      worst.marker = id;
      worst.displacement_px = p90;
    }
  }
  return worst;
}

std::string neutral_motion_warning(const std::optional<NeutralMotion>& motion) {
  if (!motion || motion->share() <= kMaxNeutralMotionShare) return {};
  return fmt::format(
      "the calibration frames do not hold a still face: '{}' moves {:.1f} px ({:.1f} % of "
      "the face's size) against the rest of the face; the calibration takes their median as "
      "the neutral face, so that motion reads wrongly for the whole take. "
      "Give an --actor profile made from a still neutral take, or start the take with a "
      "second of neutral face",
      motion->marker, motion->displacement_px, 100 * motion->share());
}

}  // namespace rostro::calib

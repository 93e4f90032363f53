#include "calib/fapu_estimation.hpp"

#include <cmath>
#include <optional>
#include <vector>

#include "facecore/error.hpp"

namespace rostro::calib {
namespace {

using V = Eigen::Vector3d;

class Estimator {
 public:
  Estimator(const FeaturePointPositions& marked, const FeaturePointPositions& prior)
      : marked_(marked), prior_(prior), points_(marked) {
    // Scale and centroids on the x/y plane over the points both sets know.
    std::vector<std::pair<V, V>> common;
    for (const auto& [id, m] : marked)
      if (auto it = prior.find(id); it != prior.end()) common.emplace_back(m, it->second);
    if (common.size() < 2)
      throw InputError("FAPU: need at least two marked feature points the face prior knows, got " +
                       std::to_string(common.size()));
    V mc = V::Zero(), pc = V::Zero();
    for (const auto& [m, p] : common) mc += m, pc += p;
    mc /= static_cast<double>(common.size());
    pc /= static_cast<double>(common.size());
    double sm = 0, sp = 0;
    for (const auto& [m, p] : common) {
      sm += (m - mc).head<2>().squaredNorm();
      sp += (p - pc).head<2>().squaredNorm();
    }
    if (sp <= 0 || sm <= 0) throw InputError("FAPU: the marked feature points all coincide");
    scale_ = std::sqrt(sm / sp);
    marked_centroid_ = mc;
    prior_centroid_ = pc;
  }

  bool marked(FeaturePointId id) const { return marked_.count(id) != 0; }
  double scale() const { return scale_; }
  const V& prior(FeaturePointId id) const { return prior_.at(id); }

  // target = mean of anchors + scale * (prior target - prior mean of anchors).
  bool from_anchors(FeaturePointId target, std::vector<FeaturePointId> anchors,
                    const std::string& how) {
    if (marked(target)) return true;
    for (auto a : anchors)
      if (!marked(a) || !prior_.count(a)) return false;
    V m = V::Zero(), p = V::Zero();
    for (auto a : anchors) m += marked_.at(a), p += prior_.at(a);
    m /= static_cast<double>(anchors.size());
    p /= static_cast<double>(anchors.size());
    points_[target] = m + scale_ * (prior_.at(target) - p);
    notes_[target.str()] = how + " (plus the face prior's offset, scaled to the actor)";
    return true;
  }

  void from_prior(FeaturePointId target) {
    if (marked(target) || points_.count(target)) return;
    points_[target] = marked_centroid_ + scale_ * (prior_.at(target) - prior_centroid_);
    notes_[target.str()] = "no marker nearby: the face prior aligned to the markers";
  }

  FeaturePointPositions& points() { return points_; }
  std::map<std::string, std::string>& notes() { return notes_; }

 private:
  const FeaturePointPositions& marked_;
  const FeaturePointPositions& prior_;
  FeaturePointPositions points_;
  std::map<std::string, std::string> notes_;
  double scale_ = 1;
  V marked_centroid_, prior_centroid_;
};

}  // namespace

FapuEstimate estimate_fapu(const FeaturePointPositions& marked, const FeaturePointPositions& prior,
                           bool lids_on_margin) {
  Estimator e(marked, prior);
  const FeaturePointId p35{3, 5}, p36{3, 6}, p915{9, 15}, p22{2, 2}, p83{8, 3}, p84{8, 4},
      p31{3, 1}, p33{3, 3}, p32{3, 2}, p34{3, 4};

  e.from_anchors(p35, {{3, 7}, {3, 11}}, "midpoint of the left eye corners 3.7 and 3.11") ||
      e.from_anchors(p35, {p31, p33}, "midpoint of the left eyelids 3.1 and 3.3") ||
      (e.from_prior(p35), true);
  e.from_anchors(p36, {{3, 12}, {3, 8}}, "midpoint of the right eye corners 3.12 and 3.8") ||
      e.from_anchors(p36, {p32, p34}, "midpoint of the right eyelids 3.2 and 3.4") ||
      (e.from_prior(p36), true);
  e.from_anchors(p915, {{9, 1}, {9, 2}}, "midpoint of the nose wings 9.1 and 9.2") ||
      e.from_anchors(p915, {{9, 5}, {9, 4}}, "midpoint of the nose base edges 9.5 and 9.4") ||
      e.from_anchors(p915, {{9, 3}}, "the nose tip 9.3") || (e.from_prior(p915), true);
  e.from_anchors(p22, {{8, 1}}, "the outer upper-lip marker 8.1") ||
      e.from_anchors(p22, {{2, 3}}, "the inner lower-lip marker 2.3") || (e.from_prior(p22), true);
  e.from_prior(p83);
  e.from_prior(p84);

  FapuEstimate out;
  const auto& pts = e.points();
  auto y = [&](FeaturePointId id) { return pts.at(id).y(); };
  auto x = [&](FeaturePointId id) { return pts.at(id).x(); };
  out.fapu.es0 = std::abs(x(p35) - x(p36));
  out.fapu.ens0 = std::abs(y(p35) - y(p915));
  out.fapu.mns0 = std::abs(y(p915) - y(p22));
  out.fapu.mw0 = std::abs(x(p83) - x(p84));
  if (lids_on_margin && e.marked(p31) && e.marked(p33)) {
    out.fapu.irisd0 = std::abs(y(p31) - y(p33));
  } else if (lids_on_margin && e.marked(p32) && e.marked(p34)) {
    out.fapu.irisd0 = std::abs(y(p32) - y(p34));
    e.notes()["IRISD0"] = "from the right eyelids 3.2 and 3.4 (the left ones carry no markers)";
  } else {
    const double ratio = std::abs(e.prior(p31).y() - e.prior(p33).y()) /
                         std::abs(e.prior(p35).x() - e.prior(p36).x());
    out.fapu.irisd0 = out.fapu.es0 * ratio;
    char buf[160];
    std::snprintf(buf, sizeof buf, "%s: ES0 x %.4f (the face prior's IRISD0/ES0)",
                  lids_on_margin ? "no eyelid markers" : "the eyelid dots sit beside the margins",
                  ratio);
    e.notes()["IRISD0"] = buf;
  }
  out.notes = e.notes();
  out.scale_to_prior = e.scale();
  return out;
}

}  // namespace rostro::calib

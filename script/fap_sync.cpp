#include "script/fap_sync.hpp"

#include <numbers>

namespace rostro::script {
namespace {

constexpr double kAuPerDegree = std::numbers::pi / 180.0 * 1e5;  // FAP angle unit: 1e-5 rad
constexpr double kEyeWeight = 0.25;  // eye behaviour against expression (seed004 6.6 rule 2)

}  // namespace

FapSynchronizer::FapSynchronizer(const speech::BehaviourSettings& behaviour,
                                 const std::vector<int>& closure_faps)
    : behaviour_(behaviour) {
  for (int id : closure_faps) closure_[static_cast<std::size_t>(id)] = true;
}

bool FapSynchronizer::is_mouth(int id) {
  return (id >= 3 && id <= 18) || (id >= 43 && id <= 47) || (id >= 51 && id <= 60);
}

FapVector FapSynchronizer::merge(const FrameLayers& l) const {
  using speech::fap;
  const double ew = behaviour_.expression_weight;
  const FapVector zero{};
  const FapVector& s = l.speech ? *l.speech : zero;
  FapVector out{};
  // 1, 2: speech against expression.
  for (int id = 3; id <= kFapCount; ++id) {
    const double e = fap(l.expression, id), ae = fap(l.expression_activity, id);
    double x = fap(s, id) + e;
    if (is_mouth(id)) {
      x = mix(e, ae, ew, fap(s, id), l.speech_activity);
      if (closure_[static_cast<std::size_t>(id)] && ae > 0.0 && l.closing > 0.0 && l.viseme)
        x = (1.0 - l.closing) * x + l.closing * fap(*l.viseme, id);
    }
    fap(out, id) = x;
  }
  // 3: eyelids.
  const EyeFrame& eye = l.eyes;
  for (int id : {19, 20})
    fap(out, id) = mix(fap(out, id), fap(l.expression_activity, id), 1.0 - kEyeWeight,
                       eye.lid_irisd, eye.lid_activity);
  const double c = eye.closure;
  for (int id : {19, 20}) fap(out, id) += c * (behaviour_.blink.closed_top_irisd - fap(out, id));
  for (int id : {21, 22}) fap(out, id) += c * (behaviour_.blink.closed_bottom_irisd - fap(out, id));
  // 4: eyeballs.
  for (int id : {23, 24}) fap(out, id) += eye.yaw_deg * kAuPerDegree;
  for (int id : {25, 26}) fap(out, id) += eye.pitch_deg * kAuPerDegree;
  // 5: head.
  const HeadFrame& h = l.head;
  const double gaze_head[3] = {eye.head_pitch_deg, eye.head_yaw_deg, 0.0};
  const double action[3] = {h.action.pitch_deg, h.action.yaw_deg, h.action.roll_deg};
  const double noise[3] = {h.noise.pitch_deg, h.noise.yaw_deg, h.noise.roll_deg};
  const double quiet = 1.0 - std::max(h.activity, eye.head_activity);
  for (int i = 0; i < 3; ++i) {
    const int id = 48 + i;
    double x = mix(fap(out, id), fap(l.expression_activity, id), 1.0 - kEyeWeight,
                   gaze_head[i] * kAuPerDegree, eye.head_activity);
    x += action[i] * kAuPerDegree;
    x += noise[i] * kAuPerDegree * quiet;
    fap(out, id) = x;
  }
  return out;
}

}  // namespace rostro::script

// Finding lost markers again: where their neighbours put them (the lids, the upper lip and the
// mouth's corners carried from where they were last seen, the lower lip with the jaw), each found
// only where it looks like itself.
#include "tracking/marker_tracker_impl.hpp"

namespace rostro::tracking {

void MarkerTracker::Impl::reacquire_lost(const Flow& f) {
  remember_last_seen(f.was_valid, f.before, f.owner);
  predict_lost();
  // With LowerLipOptions::with_the_jaw the jaw's dots last, once the dots they are placed by
  // (and the upper lip the lower lip's search stands on) are back.
  bool lower_lip_searched = false;
  auto one_by_one = [&](bool before_the_lower_lip) {
    for (size_t i = 0; i < states.size(); ++i)
      if (!states[i].valid && has_prediction[i] &&
          (options.lower_lip.with_the_jaw && !on_jaw(i)) == before_the_lower_lip &&
          !(lower_lip_searched && searched_with_lower_lip(i)))
        reacquire(i);
  };
  one_by_one(true);
  lower_lip_searched = options.lower_lip.together && reacquire_lower_lip();
  one_by_one(false);
}

bool MarkerTracker::Impl::keeps_shape(const std::array<cv::Point2d, 4>& was,
                                      const std::array<cv::Point2d, 4>& now) {
  for (int k = 0; k < 4; ++k) {
    const double a = cv::norm(was[k] - was[(k + 1) % 4]), b = cv::norm(now[k] - now[(k + 1) % 4]);
    if (std::abs(a - b) > 0.1 * a + 0.5) return false;
  }
  return true;
}

cv::Point2d MarkerTracker::Impl::diagonal_crossing(const std::array<cv::Point2d, 4>& c) {
  const cv::Point2d d1 = c[2] - c[0], d2 = c[3] - c[1], r = c[1] - c[0];
  const double den = d1.x * d2.y - d1.y * d2.x;
  if (std::abs(den) < 1e-9) return mean_of(c);
  const double t = (r.x * d2.y - r.y * d2.x) / den;
  return c[0] + t * d1;
}

bool MarkerTracker::Impl::find_tag(size_t i, const std::array<cv::Point2d, 4>& guess) {
  MarkerState& s = states[i];
  const double side = cv::norm(guess[0] - guess[1]);
  const cv::Rect roi = box_around(guess, options.tag_margin * side + 4);
  if (s.valid) s.lost_reason = LostReason::TagLost;  // unless found below
  s.valid = false;
  // Large tags are found as well at half resolution, for a quarter of the cost; the
  // corners are refined on the full image either way.
  const float decimation = side > options.tag_decimate_above_px ? 2.0f : 1.0f;
  ensure_gray(roi);
  for (const TagDetection& t : window_detector.detect(gray, roi, decimation)) {
    if (t.marker_id() != s.spec->id) continue;
    if (cv::norm(t.center - mean_of(guess)) > side) continue;
    s.valid = true;
    s.corners = t.corners;
    s.position = t.center;
    s.quality = std::clamp(t.decision_margin / 100.0, 0.0, 1.0);
    if (options.align_tags) align_tag(i, s.corners);  // keeps the detection's if it fails
    return true;
  }
  return false;
}

void MarkerTracker::Impl::predict_lost() {
  const size_t n = states.size();
  prediction_fit.assign(n, {});
  has_prediction.assign(n, false);
  face_fit.reset();
  predicted.assign(n, {});
  std::vector<cv::Point2d> from, to;
  for (size_t j = 0; j < n; ++j)
    if (states[j].valid) from.push_back(reference[j]), to.push_back(states[j].position);
  if (from.size() < 3) return;
  cv::Mat global_fit = cv::estimateAffine2D(from, to, cv::noArray(), cv::RANSAC, 3.0);
  if (global_fit.empty()) return;
  const cv::Matx23d global(global_fit);
  face_fit = global;
  const double global_scale = scale_of(global);
  face_scale = global_scale;
  for (size_t i = 0; i < n; ++i) {
    if (states[i].valid) continue;
    const bool by_jaw = placed_by_jaw(i);
    cv::Matx23d fit = by_jaw ? moved_with_jaw(global, i) : global;
    std::vector<std::pair<double, size_t>> near;
    for (size_t j = 0; j < n && !by_jaw; ++j)
      if (states[j].valid) near.push_back({cv::norm(reference[j] - reference[i]), j});
    std::sort(near.begin(), near.end());
    if (near.size() > 6) near.resize(6);
    if (near.size() >= 4) {
      std::vector<cv::Point2d> f, t;
      for (const auto& [d, j] : near) f.push_back(reference[j]), t.push_back(states[j].position);
      cv::Mat local = cv::estimateAffine2D(f, t, cv::noArray(), cv::LMEDS);
      if (!local.empty()) {
        const cv::Matx23d l(local);
        double worst = 0;
        for (size_t k = 0; k < f.size(); ++k)
          worst = std::max(worst, cv::norm(apply(l, f[k]) - t[k]));
        const double ratio = scale_of(l) / global_scale;
        // A local fit that bends more than a face does is ignored.
        if (worst < std::max(2.0, 0.15 * spacing[i] * global_scale) && ratio > 0.7 && ratio < 1.4)
          fit = l;
      }
    }
    prediction_fit[i] = fit;
    const std::optional<cv::Point2d> carry = carried(i);
    predicted[i] = carry.value_or(apply(fit, reference[i]));
    has_prediction[i] = true;
  }
}

cv::Matx23d MarkerTracker::Impl::moved_with_jaw(const cv::Matx23d& global, size_t i) const {
  std::optional<size_t> nearest;  // the followed jaw dot nearest i at the start (i aside)
  for (size_t j = 0; j < states.size(); ++j)
    if (j != i && states[j].valid && on_jaw(j) &&
        (!nearest ||
         cv::norm(reference[j] - reference[i]) < cv::norm(reference[*nearest] - reference[i])))
      nearest = j;
  if (!nearest) return global;
  const size_t j = *nearest;
  const cv::Point2d miss = states[j].position - apply(global, reference[j]);
  cv::Matx23d moved = global;
  moved(0, 2) += miss.x, moved(1, 2) += miss.y;
  return moved;
}

void MarkerTracker::Impl::remember_last_seen(const std::vector<bool>& was_valid,
                                             const std::vector<cv::Point2f>& before,
                                             const std::vector<size_t>& owner) {
  const size_t n = states.size();
  last_seen.resize(n);
  std::vector<cv::Point2d> then(n);
  for (size_t k = 0; k < before.size(); ++k) then[owner[k]] = cv::Point2d(before[k]);
  for (size_t i = 0; i < n; ++i) {
    if (states[i].valid) {
      last_seen[i].known = false;
      continue;
    }
    if (!was_valid[i] || states[i].spec->is_tag()) continue;
    LastSeen& l = last_seen[i];
    l.known = true;
    l.position = then[i];
    l.anchors.clear();
    std::vector<std::pair<double, size_t>> near;
    for (size_t j = 0; j < n; ++j)
      if (j != i && was_valid[j] && !states[j].spec->is_tag())
        near.push_back({cv::norm(reference[j] - reference[i]), j});
    std::sort(near.begin(), near.end());
    for (const auto& [d, j] : near) l.anchors.push_back({j, then[j]});
  }
}

std::optional<cv::Point2d> MarkerTracker::Impl::carried(size_t i) const {
  if (i >= last_seen.size() || !last_seen[i].known) return std::nullopt;
  if (!carried_while_lost(i) && states[i].lost_frames > 0) return std::nullopt;
  const LastSeen& l = last_seen[i];
  std::vector<cv::Point2d> from, to;
  for (const auto& [j, at] : l.anchors) {
    if (!states[j].valid) continue;
    from.push_back(at), to.push_back(states[j].position);
    if (from.size() == 6) break;
  }
  if (from.empty()) return std::nullopt;
  if (from.size() >= 3) {
    cv::Mat m = cv::estimateAffinePartial2D(from, to, cv::noArray(), cv::LMEDS);
    if (!m.empty()) return apply(cv::Matx23d(m), l.position);
  }
  cv::Point2d shift(0, 0);
  for (size_t k = 0; k < from.size(); ++k) shift += to[k] - from[k];
  return l.position + shift * (1.0 / static_cast<double>(from.size()));
}

void MarkerTracker::Impl::reacquire(size_t i) {
  MarkerState& s = states[i];
  const cv::Matx23d& m = prediction_fit[i];
  const double scale = scale_of(m);
  if (s.spec->is_tag()) {
    std::array<cv::Point2d, 4> guess;
    for (int k = 0; k < 4; ++k) guess[k] = apply(m, reference_corners[i][k]);
    find_tag(i, guess);
    return;
  }
  const cv::Point2d expected = predicted_at(i);
  const double radius = options.search_fraction * spacing[i] * scale;
  ensure_gray_around(expected, radius);
  // Every dot near the expected place, nearest first: the strongest one there may be a dark
  // feature that is no marker (the pupil beside a lid dot) and fail the checks.
  // (Peaks too faint to pass dot_passes() are not even measured.)
  const double least = options.min_contrast_ratio * reference_contrast[i];
  for (const Dot& d : dots_near(gray, expected, radius, dot_options(i), 4, least)) {
    if (cv::norm(d.center - expected) > radius || !dot_passes(i, d, false)) continue;
    if (!belongs_to(i, d.center, scale)) continue;
    // Last: it measures the blob again.
    if (!looks_like_itself(i, d)) continue;
    found_on(i, d);
    return;
  }
}

bool MarkerTracker::Impl::looks_like_itself(size_t i, const Dot& d) const {
  if (options.found_look_allowance < 0) return true;
  const std::optional<Dot> as_followed = refine_dot(gray, d.center, max_snap(), dot_options(i));
  const bool same_blob =
      as_followed && cv::norm(as_followed->center - d.center) <= 0.5 * d.diameter;
  return unlike_a_dot(same_blob ? *as_followed : d) <= usual_look[i] + options.found_look_allowance;
}

void MarkerTracker::Impl::found_on(size_t i, const Dot& d) {
  MarkerState& s = states[i];
  // Found by a search, not carried by LK: reported from the next frame after a loss.
  const int hold_after = options.hold_found_after_lost;
  s.held = hold_after > 0 && s.lost_frames >= hold_after;
  s.valid = true, s.position = d.center, s.lost_reason = LostReason::None;
  recent_diameter[i] = last_diameter[i] = d.diameter, recent_elongation[i] = d.elongation;
  s.quality = 0.9 * std::clamp(d.contrast / reference_contrast[i], 0.0, 1.0);
}

bool MarkerTracker::Impl::apart_from_lower_lip(size_t i, size_t j) const {
  if (at_lower_lip(i)) return options.lower_lip.with_the_jaw && !on_jaw(j);
  return options.lower_lip.together && at_lower_lip(j);
}

bool MarkerTracker::Impl::reacquire_lower_lip() {
  LowerLipScene scene;
  for (size_t i = 0; i < states.size(); ++i) {
    const MarkerState& s = states[i];
    if (s.spec->is_tag()) continue;
    if (searched_with_lower_lip(i))
      scene.lower_lip.push_back(
          {i, reference[i], spacing[i], s.valid, s.position, !s.valid && has_prediction[i]});
    else if (!s.valid && has_prediction[i])
      scene.expected.push_back({i, predicted_at(i), spacing[i]});
    if (!s.valid) continue;
    if (at_upper_lip_or_corner(s.spec->feature_point))
      scene.upper_start.push_back(reference[i]), scene.upper_now.push_back(s.position);
    scene.followed.push_back({i, s.position, spacing[i]});
  }
  LowerLipSearch search;
  search.options = options.lower_lip;
  search.dots_near = [this](size_t k, cv::Point2d centre, double radius) {
    ensure_gray_around(centre, radius);
    const double least = options.min_contrast_ratio * reference_contrast[k];
    return dots_near(gray, centre, radius, dot_options(k), 4, least);
  };
  // Not asked the look (found_look_allowance): found together they are held to the lip's
  // shape already, and asked, the lower lip's dots beside the open mouth were left lost (the
  // closed loops, docs/accuracy.md).
  search.passes = [this](size_t k, const Dot& d) { return dot_passes(k, d, false); };
  const std::optional<std::vector<LowerLipFound>> found = find_lower_lip(scene, search);
  if (!found) return false;
  for (const LowerLipFound& f : *found) found_on(f.marker, f.dot);
  return true;
}

bool MarkerTracker::Impl::followed_dot_at(cv::Point2d at, double scale) const {
  for (size_t j = 0; j < states.size(); ++j)
    if (states[j].valid && !states[j].spec->is_tag() &&
        cv::norm(states[j].position - at) < 0.5 * spacing[j] * scale)
      return true;
  return false;
}

bool MarkerTracker::Impl::belongs_to(size_t i, cv::Point2d at, double scale) const {
  const IdentificationOptions& naming = options.identification;
  const double own = cv::norm(at - predicted_at(i));
  if (followed_dot_at(at, scale)) return false;
  for (size_t j = 0; j < states.size(); ++j) {
    if (j == i || states[j].spec->is_tag()) continue;
    if (!states[j].valid && has_prediction[j] &&
        cv::norm(predicted_at(j) - at) < naming.unnamed_rival * own &&
        own > naming.sure_within * spacing[i] * scale)
      return false;
  }
  return true;
}

}  // namespace rostro::tracking

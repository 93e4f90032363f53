// Following the markers from one frame to the next: LK's round trip, each dot snapped to its
// measured centre, the tags aligned, and the dots that jumped or coincide dropped.
#include <algorithm>
#include <array>
#include <span>

#include "tracking/marker_tracker_impl.hpp"
#include "tracking/order_statistic.hpp"

namespace rostro::tracking {

bool MarkerTracker::Impl::failed_round_trip(const Flow& f, size_t k) const {
  return !f.status[k] || !f.status_back[k] || cv::norm(f.back[k] - f.before[k]) > max_fb_error();
}

void MarkerTracker::Impl::follow(long frame) {
  Flow flow = timed("lk_round_trip", [&] { return lk_round_trip(); });
  const TagGuesses tags = timed("tag_corner_guesses", [&] { return tag_corner_guesses(flow); });
  timed("snap_dots", [&] { snap_dots(flow); });
  timed("follow_tags", [&] { follow_tags(flow, tags); });
  timed("drop_jumped", [&] { drop_jumped(flow); });
  timed("drop_coincident", [&] { drop_coincident(); });
  timed("reacquire_lost", [&] { reacquire_lost(flow); });
  if (options.swap_back_pairs) timed("swap_back_pairs", [&] { swap_back_pairs(frame); });
}

MarkerTracker::Impl::Flow MarkerTracker::Impl::lk_round_trip() {
  Flow f;
  f.was_valid.resize(states.size());
  for (size_t i = 0; i < states.size(); ++i) {
    const MarkerState& s = states[i];
    f.was_valid[i] = s.valid;
    if (!s.valid) continue;
    if (s.spec->is_tag()) {
      for (const auto& c : s.corners) f.before.emplace_back(c), f.owner.push_back(i);
    } else {
      f.before.emplace_back(s.position), f.owner.push_back(i);
    }
  }
  if (f.before.empty()) return f;
  // (No error measure asked of LK: nothing reads it, and it costs a window's interpolation
  // per point.)
  const cv::Size window(lk_window(), lk_window());
  const cv::TermCriteria stop(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 20, 0.03);
  // Each pyramid has its own region: points go to its coordinates and back.
  const cv::Point2f from_tl(previous_region.tl()), to_tl(region.tl());
  std::vector<cv::Point2f> local_before(f.before.size());
  f.after.resize(f.before.size());
  for (size_t k = 0; k < f.before.size(); ++k)
    local_before[k] = f.before[k] - from_tl, f.after[k] = f.before[k] - to_tl;
  // Derivatives only where LK reads them: around the points it follows from each pyramid.
  previous_pyramid.derivatives(local_before);
  cv::calcOpticalFlowPyrLK(previous_pyramid.as_lk_input(), pyramid.as_lk_input(), local_before,
                           f.after, f.status, cv::noArray(), window, options.lk_levels, stop,
                           cv::OPTFLOW_USE_INITIAL_FLOW);
  f.back = local_before;
  f.status_back.assign(f.before.size(), 1);
  // The way back only for the dots when the tags are aligned to their patterns: a tag's
  // alignment checks it (follow_tags), and its corners are a quarter of LK's points.
  std::vector<size_t> back;  // the points LK takes back
  for (size_t k = 0; k < f.before.size(); ++k)
    if (!options.align_tags || !states[f.owner[k]].spec->is_tag()) back.push_back(k);
  std::vector<cv::Point2f> back_from(back.size()), back_to(back.size());
  for (size_t j = 0; j < back.size(); ++j)
    back_from[j] = f.after[back[j]], back_to[j] = local_before[back[j]];
  std::vector<uchar> back_status;
  pyramid.derivatives(back_from);
  cv::calcOpticalFlowPyrLK(pyramid.as_lk_input(), previous_pyramid.as_lk_input(), back_from,
                           back_to, back_status, cv::noArray(), window, options.lk_levels, stop,
                           cv::OPTFLOW_USE_INITIAL_FLOW);
  for (size_t j = 0; j < back.size(); ++j)
    f.back[back[j]] = back_to[j], f.status_back[back[j]] = back_status[j];
  for (size_t k = 0; k < f.before.size(); ++k) f.after[k] += to_tl, f.back[k] += from_tl;
  return f;
}

MarkerTracker::Impl::TagGuesses MarkerTracker::Impl::tag_corner_guesses(const Flow& f) const {
  TagGuesses g{std::vector<std::array<cv::Point2d, 4>>(states.size()),
               std::vector<bool>(states.size(), true)};
  std::vector<int> count(states.size(), 0);
  for (size_t k = 0; k < f.before.size(); ++k) {
    const size_t i = f.owner[k];
    const MarkerState& s = states[i];
    if (!s.spec->is_tag()) continue;
    int& c = count[i];
    g.corners[i][c] = f.status[k] ? cv::Point2d(f.after[k]) : s.corners[c];
    if (failed_round_trip(f, k)) g.held[i] = false;
    ++c;
  }
  return g;
}

void MarkerTracker::Impl::snap_dots(const Flow& f) {
  // The dots that made LK's round trip are measured apart from one another (each reads only
  // the grey image around it) on TrackerOptions::threads threads, then judged and applied
  // in their order: the result does not depend on the thread count. Their grey windows are
  // filled first, serially, as the conversion writes to the one grey image.
  std::vector<size_t> to_measure;  // point indices
  for (size_t k = 0; k < f.before.size(); ++k) {
    MarkerState& s = states[f.owner[k]];
    if (s.spec->is_tag()) continue;
    s.valid = false;
    if (failed_round_trip(f, k)) {
      s.lost_reason = LostReason::RoundTrip;
      continue;
    }
    ensure_gray_around(cv::Point2d(f.after[k]), max_snap());
    to_measure.push_back(k);
  }
  std::vector<std::optional<Dot>> measured(f.before.size());
  for_each_in_parallel(to_measure.size(), [&](size_t m) {
    const size_t k = to_measure[m];
    measured[k] = refine_dot(gray, cv::Point2d(f.after[k]), max_snap(), dot_options(f.owner[k]));
  });
  for (const size_t k : to_measure) {
    const size_t i = f.owner[k];
    MarkerState& s = states[i];
    const double fb = cv::norm(f.back[k] - f.before[k]);
    const std::optional<Dot>& d = measured[k];
    if (!d) {
      s.lost_reason = LostReason::NoDot;
      continue;
    }
    const cv::Point2d lk(f.after[k]);
    const double snap = cv::norm(d->center - lk);
    s.lost_reason = snap > max_snap() ? LostReason::Snap : dot_check(i, *d, true);
    if (s.lost_reason != LostReason::None) continue;
    s.valid = true;
    s.position = d->center;
    recent_diameter[i] = 0.7 * recent_diameter[i] + 0.3 * d->diameter;
    recent_elongation[i] = d->elongation, last_diameter[i] = d->diameter;
    usual_look[i] = 0.8 * usual_look[i] + 0.2 * unlike_a_dot(*d);
    s.quality =
        std::clamp(d->contrast / reference_contrast[i], 0.0, 1.0) * (1 - 0.5 * fb / max_fb_error());
  }
}

void MarkerTracker::Impl::follow_tags(const Flow& f, const TagGuesses& g) {
  if (options.align_tags) {
    for (size_t i = 0; i < states.size(); ++i) {
      if (!states[i].spec->is_tag() || !f.was_valid[i]) continue;
      if (!align_tag(i, g.corners[i])) find_tag(i, g.corners[i]);
    }
    return;
  }
  const bool detect_tags = ++frames_since_tag_detection >= options.tag_redetect_every;
  if (detect_tags) frames_since_tag_detection = 0;
  for (size_t i = 0; i < states.size(); ++i) {
    if (!states[i].spec->is_tag() || !f.was_valid[i]) continue;
    if (!detect_tags && g.held[i] && keeps_shape(states[i].corners, g.corners[i])) {
      states[i].corners = g.corners[i];
      states[i].position = diagonal_crossing(g.corners[i]);
      continue;
    }
    find_tag(i, g.corners[i]);
  }
}

bool MarkerTracker::Impl::align_tag(size_t i, const std::array<cv::Point2d, 4>& start) {
  MarkerState& s = states[i];
  ensure_gray(box_around(start, 0.2 * cv::norm(start[0] - start[1]) + 2));
  const auto c = aligners[i]->align(gray, start);
  if (!c) return false;
  s.valid = true;
  s.corners = *c;
  s.position = diagonal_crossing(*c);
  return true;
}

void MarkerTracker::Impl::drop_jumped(const Flow& f) {
  // Kept from frame to frame: this runs for every dot on every frame.
  thread_local std::vector<cv::Point2d> moved;
  thread_local std::vector<std::pair<double, size_t>> near;
  thread_local std::vector<size_t> jumped;
  moved.assign(states.size(), {});
  jumped.clear();
  for (size_t k = 0; k < f.before.size(); ++k)
    if (!states[f.owner[k]].spec->is_tag())
      moved[f.owner[k]] = states[f.owner[k]].position - cv::Point2d(f.before[k]);
  constexpr size_t kMostNeighbours = 6;
  for (size_t i = 0; i < states.size(); ++i) {
    if (!states[i].valid || states[i].spec->is_tag() || !f.was_valid[i]) continue;
    // The lower lip by the jaw's dots while three of them were followed, else by any.
    for (const bool apart : {true, false}) {
      near.clear();
      for (size_t j = 0; j < states.size(); ++j)
        if (j != i && states[j].valid && f.was_valid[j] && !states[j].spec->is_tag() &&
            !(apart && apart_from_lower_lip(i, j)))
          near.push_back({cv::norm(reference[j] - reference[i]), j});
      if (near.size() >= 3 || !at_lower_lip(i)) break;
    }
    if (near.size() < 3) continue;
    const size_t n = std::min(near.size(), kMostNeighbours);
    std::partial_sort(near.begin(), near.begin() + static_cast<std::ptrdiff_t>(n), near.end());
    std::array<double, kMostNeighbours> xs, ys;
    for (size_t k = 0; k < n; ++k) xs[k] = moved[near[k].second].x, ys[k] = moved[near[k].second].y;
    const cv::Point2d typical(median_in_place(std::span(xs.data(), n)),
                              median_in_place(std::span(ys.data(), n)));
    if (cv::norm(moved[i] - typical) >
        std::max(options.max_relative_motion_px * px, options.max_relative_motion * spacing[i]))
      jumped.push_back(i);
  }
  for (size_t i : jumped) states[i].valid = false, states[i].lost_reason = LostReason::Jump;
}

void MarkerTracker::Impl::drop_coincident() {
  for (size_t i = 0; i < states.size(); ++i)
    for (size_t j = i + 1; j < states.size(); ++j) {
      MarkerState &a = states[i], &b = states[j];
      if (!a.valid || !b.valid || a.spec->is_tag() || b.spec->is_tag()) continue;
      if (cv::norm(a.position - b.position) < 0.5 * std::max(reference_diameter[i], 2.0)) {
        a.valid = b.valid = false;
        a.lost_reason = b.lost_reason = LostReason::Coincident;
      }
    }
}

}  // namespace rostro::tracking

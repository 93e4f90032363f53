#include "eval/track_metrics.hpp"

#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <unordered_map>

#include "facecore/error.hpp"
#include "facecore/feature_point.hpp"

namespace rostro::eval {
namespace {

using tracking::MarkerObservation;
using tracking::TrackedFrame;

constexpr double kInf = std::numeric_limits<double>::infinity();

std::string match_key(const MarkerObservation& m, MatchBy match) {
  return match == MatchBy::Marker ? m.marker : m.feature_point.str();
}

// Markers with no feature point (a headband's tags) cannot be matched by one: left out.
bool matchable(const MarkerObservation& m, MatchBy match) {
  return match == MatchBy::Marker || is_feature_point(m.feature_point);
}

// The observations of one frame by match key; repeated keys are an input error.
std::unordered_map<std::string, const MarkerObservation*> index_frame(const TrackedFrame& f,
                                                                      MatchBy match,
                                                                      const char* side) {
  std::unordered_map<std::string, const MarkerObservation*> index;
  for (const MarkerObservation& m : f.markers) {
    if (!matchable(m, match)) continue;
    auto [it, added] = index.emplace(match_key(m, match), &m);
    if (!added)
      throw InputError(std::string(side) + " frame " + std::to_string(f.frame) + ": " +
                       (match == MatchBy::Marker ? "marker '" : "feature point '") + it->first +
                       "' appears twice" +
                       (match == MatchBy::FeaturePoint ? " (match by marker id instead)" : ""));
  }
  return index;
}

// The truth observation a normalising name refers to: a feature point or a marker id.
const MarkerObservation* find_norm_point(const TrackedFrame& f, const std::string& name) {
  const auto fp = parse_feature_point(name);
  for (const MarkerObservation& m : f.markers) {
    if (fp ? m.feature_point == *fp : m.marker == name) return &m;
  }
  return nullptr;
}

std::optional<double> frame_norm_distance(const TrackedFrame& f, const TrackEvalOptions& o) {
  const MarkerObservation* a = find_norm_point(f, o.norm_a);
  const MarkerObservation* b = find_norm_point(f, o.norm_b);
  if (!a || !b || !a->valid || !b->valid) return std::nullopt;
  const double d = cv::norm(a->position - b->position);
  if (!(d > 0) || !std::isfinite(d)) return std::nullopt;
  return d;
}

std::set<std::string> match_keys(std::span<const TrackedFrame> frames, MatchBy match) {
  std::set<std::string> keys;
  for (const TrackedFrame& f : frames)
    for (const MarkerObservation& m : f.markers)
      if (matchable(m, match)) keys.insert(match_key(m, match));
  return keys;
}

// Two files that share no marker would score as all lost: an error naming a few of each
// side's markers instead, so the user sees why.
void require_common_markers(std::span<const TrackedFrame> truth,
                            std::span<const TrackedFrame> estimate, MatchBy match) {
  const auto truth_keys = match_keys(truth, match);
  const auto estimate_keys = match_keys(estimate, match);
  for (const std::string& k : estimate_keys)
    if (truth_keys.contains(k)) return;
  auto some = [](const std::set<std::string>& keys) {
    std::string list;
    int shown = 0;
    for (const std::string& k : keys) {
      if (shown++ == 4) return list + ", ...";
      list += (list.empty() ? "'" : ", '") + k + "'";
    }
    return list.empty() ? std::string("none") : list;
  };
  const bool by_marker = match == MatchBy::Marker;
  throw InputError(
      std::string("the estimate and the truth share no ") +
      (by_marker ? "marker id" : "feature point") + " (truth: " + some(truth_keys) +
      "; estimate: " + some(estimate_keys) + "); " +
      (by_marker ? "--match fp matches by feature point" : "--match marker matches by marker id"));
}

struct MarkerAccumulator {
  std::size_t order = 0;
  FeaturePointId feature_point;
  std::vector<double> errors_px;
  std::vector<double> errors_nme;
  long lost = 0;
  long swap_frames = 0;
  long swap_events = 0;
  long astray_frames = 0;
  bool swapped_last_frame = false;
};

}  // namespace

TrackEvalResult evaluate_tracks(std::span<const TrackedFrame> truth,
                                std::span<const TrackedFrame> estimate,
                                const TrackEvalOptions& options) {
  TrackEvalResult r;
  r.options = options;
  if (!estimate.empty()) require_common_markers(truth, estimate, options.match);
  r.truth_frames = static_cast<long>(truth.size());
  r.estimate_frames = static_cast<long>(estimate.size());

  std::map<long, const TrackedFrame*> estimate_by_frame;
  for (const TrackedFrame& f : estimate)
    if (!estimate_by_frame.emplace(f.frame, &f).second)
      throw InputError("estimate: frame " + std::to_string(f.frame) + " appears twice");
  std::map<long, const TrackedFrame*> truth_by_frame;
  for (const TrackedFrame& f : truth)
    if (!truth_by_frame.emplace(f.frame, &f).second)
      throw InputError("truth: frame " + std::to_string(f.frame) + " appears twice");
  for (const auto& [frame, f] : estimate_by_frame)
    if (!truth_by_frame.contains(frame)) ++r.extra_frames;

  // The normalising distance: per frame where the pair is visible, else their median.
  std::vector<std::optional<double>> norm(truth.size());
  std::vector<double> visible_norms;
  for (std::size_t i = 0; i < truth.size(); ++i) {
    norm[i] = frame_norm_distance(truth[i], options);
    if (norm[i]) visible_norms.push_back(*norm[i]);
  }
  if (visible_norms.empty())
    throw InputError("truth: the normalising points '" + options.norm_a + "' and '" +
                     options.norm_b +
                     "' are never both visible; name another pair (--norm A,B: feature points "
                     "or marker ids)");
  r.norm_distance_median = quantile(visible_norms, 0.5);

  std::map<std::string, MarkerAccumulator> per_marker;
  std::vector<double> all_errors_px;

  for (std::size_t i = 0; i < truth.size(); ++i) {
    const TrackedFrame& t = truth[i];
    const auto truth_index = index_frame(t, options.match, "truth");
    std::vector<const MarkerObservation*> visible;
    for (const MarkerObservation& m : t.markers) {
      if (!matchable(m, options.match)) continue;
      auto& acc = per_marker[match_key(m, options.match)];
      if (acc.errors_px.empty() && acc.lost == 0 && acc.order == 0) {
        acc.order = per_marker.size();
        acc.feature_point = m.feature_point;
      }
      if (m.valid) visible.push_back(&m);
    }
    if (visible.empty()) continue;

    FrameResult fr;
    fr.frame = t.frame;
    fr.norm_fallback = !norm[i].has_value();
    fr.norm_distance = norm[i].value_or(r.norm_distance_median);
    if (fr.norm_fallback) ++r.norm_fallback_frames;

    const auto est_it = estimate_by_frame.find(t.frame);
    const TrackedFrame* e = est_it == estimate_by_frame.end() ? nullptr : est_it->second;
    if (!e) ++r.missing_frames;
    std::unordered_map<std::string, const MarkerObservation*> est_index;
    if (e) est_index = index_frame(*e, options.match, "estimate");

    double nme_sum = 0;
    for (const MarkerObservation* own : visible) {
      const std::string key = match_key(*own, options.match);
      MarkerAccumulator& acc = per_marker[key];
      const auto found = est_index.find(key);
      const MarkerObservation* est = found == est_index.end() ? nullptr : found->second;
      if (!est || !est->valid) {
        ++fr.lost;
        ++acc.lost;
        acc.swapped_last_frame = false;
        continue;
      }
      const double err = cv::norm(est->position - own->position);
      ++fr.scored;
      nme_sum += err / fr.norm_distance;
      acc.errors_px.push_back(err);
      acc.errors_nme.push_back(err / fr.norm_distance);
      all_errors_px.push_back(err);

      // Identity swap: nearer some other visible marker's truth than its own, by enough;
      // astray: as far off, near no other.
      bool swapped = false;
      if (err > options.swap_threshold * fr.norm_distance) {
        for (const MarkerObservation* other : visible) {
          if (other == own) continue;
          if (cv::norm(est->position - other->position) < err) {
            swapped = true;
            break;
          }
        }
        if (!swapped) ++fr.astray, ++acc.astray_frames;
      }
      if (swapped) {
        ++fr.swaps;
        ++acc.swap_frames;
        if (!acc.swapped_last_frame) ++acc.swap_events;
      }
      acc.swapped_last_frame = swapped;
    }
    fr.nme = fr.scored > 0 ? nme_sum / fr.scored : kInf;
    if (options.lost_is_failure && fr.lost > 0) fr.nme = kInf;

    r.scored_observations += fr.scored;
    r.lost_observations += fr.lost;
    if (fr.lost > 0) ++r.lost_frames;
    r.swap_observations += fr.swaps;
    r.astray_observations += fr.astray;
    r.frames.push_back(fr);
    r.frame_nme.push_back(fr.nme);
  }

  r.scored_frames = static_cast<long>(r.frames.size());
  r.nme = summarize(r.frame_nme);
  r.error_px = summarize(all_errors_px);
  r.auc = auc_at(r.frame_nme, options.threshold);
  r.failure_rate = failure_rate(r.frame_nme, options.threshold);

  std::vector<std::pair<std::size_t, MarkerResult>> ordered;
  for (auto& [key, acc] : per_marker) {
    MarkerResult m;
    m.marker = key;
    m.feature_point = acc.feature_point;
    m.error_px = summarize(acc.errors_px);
    m.nme = summarize(acc.errors_nme);
    m.scored = static_cast<long>(acc.errors_px.size());
    m.lost = acc.lost;
    m.swap_frames = acc.swap_frames;
    m.swap_events = acc.swap_events;
    m.astray_frames = acc.astray_frames;
    r.swap_events += acc.swap_events;
    ordered.emplace_back(acc.order, std::move(m));
  }
  std::sort(ordered.begin(), ordered.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  for (auto& [order, m] : ordered) r.markers.push_back(std::move(m));
  return r;
}

}  // namespace rostro::eval

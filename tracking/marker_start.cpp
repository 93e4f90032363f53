// Naming the markers at the start of a take: the whole frame's tags and dots named
// (identify.hpp), or the positions given; the reference looks and spacings measured there.
#include "tracking/marker_tracker_impl.hpp"
#include "tracking/order_statistic.hpp"

namespace rostro::tracking {

std::vector<TagDetection> MarkerTracker::Impl::detect_all_tags() {
  return layout.tag_count() > 0 ? full_detector.detect(gray) : std::vector<TagDetection>{};
}

void MarkerTracker::Impl::start() {
  ensure_gray({0, 0, gray.cols, gray.rows});
  const std::vector<TagDetection> tags = timed("detect_tags", [&] { return detect_all_tags(); });
  const std::vector<std::pair<cv::Point2d, cv::Point2d>> known = timed("identify", [&] {
    return start_positions.empty() ? adopt(name_frame(tags)) : find_at_start_positions(tags);
  });
  const bool doubtful = start_positions.empty() && !identification.confident;
  if (doubtful || !begin(known))
    for (MarkerState& s : states) s.valid = false, s.lost_reason = LostReason::Unidentified;
}

bool MarkerTracker::Impl::enough(size_t placed) const {
  return static_cast<int>(placed) >= std::max(3, options.min_identified);
}

bool MarkerTracker::Impl::begin(const std::vector<std::pair<cv::Point2d, cv::Point2d>>& known) {
  if (!enough(known.size())) return false;
  place_unseen(known);
  unconfirmed.clear(), called_otherwise.clear();
  for (size_t i = 0; i < states.size(); ++i)
    if (states[i].valid && !states[i].spec->is_tag()) unconfirmed.insert(i);
  if (options.align_tags)
    timed("align_tags", [&] {
      for (size_t i = 0; i < states.size(); ++i)
        if (states[i].valid && aligners[i]) align_tag(i, states[i].corners);
    });
  scale_to_dots(measure_seen());
  measure_spacing();
  started = true;
  return true;
}

std::vector<std::pair<cv::Point2d, cv::Point2d>> MarkerTracker::Impl::find_at_start_positions(
    const std::vector<TagDetection>& tags) {
  std::vector<std::pair<cv::Point2d, cv::Point2d>> known;
  expected_start.clear();
  for (MarkerState& s : states) {
    s.valid = false;
    auto it = start_positions.find(s.spec->id);
    if (it == start_positions.end()) continue;
    if (s.spec->is_tag()) {
      for (const TagDetection& t : tags)
        if (t.marker_id() == s.spec->id && cv::norm(t.center - it->second) < 20)
          s.valid = true, s.corners = t.corners, s.position = t.center;
    } else if (auto d = refine_dot(gray, it->second, 3,
                                   dot_options(static_cast<size_t>(&s - states.data())))) {
      s.valid = true, s.position = d->center;
    }
    if (s.valid) known.push_back({s.spec->frontal(), s.position});
  }
  return known;
}

Identification MarkerTracker::Impl::name_frame(const std::vector<TagDetection>& tags) {
  const auto expected = expected_places(tags);
  Identification id = identify_markers(layout, detect_dots(gray, centroid_dots), tags,
                                       options.identification, expected);
  if (face_prior.available() && !id.confidence.face_model && id.confidence.confident) {
    id.confidence.confident = false;
    id.confidence.doubt = expected.empty() ? "the landmark model found no face"
                                           : "the face's landmarks disagree with the tags";
  }
  return id;
}

std::vector<std::pair<cv::Point2d, cv::Point2d>> MarkerTracker::Impl::adopt(
    const Identification& id) {
  std::vector<std::pair<cv::Point2d, cv::Point2d>> known;
  identification = id.confidence;
  expected_start = id.places;
  for (MarkerState& s : states) {
    s.valid = false;
    if (s.spec->is_tag()) {
      auto it = id.tags.find(s.spec->id);
      if (it != id.tags.end())
        s.valid = true, s.corners = it->second.corners, s.position = it->second.center;
    } else {
      auto it = id.dots.find(s.spec->id);
      if (it != id.dots.end()) s.valid = true, s.position = it->second.center;
    }
    if (s.valid) known.push_back({s.spec->frontal(), s.position});
  }
  return known;
}

std::map<std::string, cv::Point2d> MarkerTracker::Impl::expected_places(
    const std::vector<TagDetection>& tags) {
  return face_prior.expected(gray, layout, layout_to_image(tags));
}

std::optional<cv::Matx23d> MarkerTracker::Impl::layout_to_image(
    const std::vector<TagDetection>& tags) const {
  std::vector<cv::Point2d> from, to;
  for (const MarkerSpec& m : layout.markers)
    for (const TagDetection& t : tags)
      if (m.is_tag() && t.family == m.family && t.id == m.tag_id) {
        const auto corners = m.tag_corners_frontal();
        for (int k = 0; k < 4; ++k) from.push_back(corners[k]), to.push_back(t.corners[k]);
      }
  if (from.empty()) return std::nullopt;
  const cv::Mat s = cv::estimateAffinePartial2D(from, to, cv::noArray(), cv::LMEDS);
  if (s.empty()) return std::nullopt;
  return cv::Matx23d(s);
}

void MarkerTracker::Impl::place_unseen(
    const std::vector<std::pair<cv::Point2d, cv::Point2d>>& known) {
  std::vector<cv::Point2d> from, to;
  for (const auto& [f, t] : known) from.push_back(f), to.push_back(t);
  cv::Matx23d mapping(cv::estimateAffine2D(from, to, cv::noArray(), cv::LMEDS));
  const size_t n = states.size();
  reference.assign(n, {});
  reference_seen.assign(n, false);
  reference_corners.assign(n, {});
  for (size_t i = 0; i < n; ++i) {
    MarkerState& s = states[i];
    if (s.valid) continue;
    // The identification's place for an unseen dot follows this face's shape; the mapping
    // the layout's average one.
    const auto place = expected_start.find(s.spec->id);
    reference[i] =
        place != expected_start.end() ? place->second : apply(mapping, s.spec->frontal());
    if (s.spec->is_tag()) {
      auto c = s.spec->tag_corners_frontal();
      for (int k = 0; k < 4; ++k) reference_corners[i][k] = apply(mapping, c[k]);
    }
  }
}

std::pair<std::vector<double>, std::vector<double>> MarkerTracker::Impl::measure_seen() {
  const size_t n = states.size();
  std::vector<double> contrasts, diameters;
  reference_contrast.assign(n, 0);
  reference_diameter.assign(n, 0);
  usual_look.assign(n, 0);
  for (size_t i = 0; i < n; ++i) {
    MarkerState& s = states[i];
    s.quality = s.valid ? 1 : 0;
    s.lost_frames = s.valid ? 0 : 1;
    s.lost_reason = s.valid ? LostReason::None : LostReason::Unidentified;
    if (!s.valid) continue;
    reference[i] = s.position;
    reference_seen[i] = true;
    reference_corners[i] = s.corners;
    if (s.spec->is_tag()) continue;
    // An eye dot is identified by its centroid alone, beside the slit's corner line
    // even on a weak blob between the two (1280x720: 2.9 px off): measured again, as it
    // will be followed, from the strongest point within a few pixels.
    if (at_eye(i))
      if (auto d = refine_dot(gray, s.position, 3, dot_options(i)))
        reference[i] = s.position = d->center;
    if (auto d = refine_dot(gray, s.position, 1.5, dot_options(i))) {
      reference_contrast[i] = d->contrast, reference_diameter[i] = d->diameter;
      usual_look[i] = unlike_a_dot(*d);
      contrasts.push_back(d->contrast), diameters.push_back(d->diameter);
    }
  }
  return {contrasts, diameters};
}

void MarkerTracker::Impl::scale_to_dots(
    const std::pair<std::vector<double>, std::vector<double>>& measured) {
  const auto& [contrasts, diameters] = measured;
  const double typical_contrast = median(contrasts), typical_diameter = median(diameters);
  std::vector<double> seen_looks;
  for (size_t i = 0; i < states.size(); ++i)
    if (reference_contrast[i] > 0) seen_looks.push_back(usual_look[i]);
  const double typical_look = median(seen_looks);
  px = std::max(1.0, typical_diameter / options.reference_dot_px);
  large_dots = typical_diameter >= options.reference_dot_px;
  for (size_t i = 0; i < states.size(); ++i)
    if (!states[i].spec->is_tag() && reference_contrast[i] <= 0)
      reference_contrast[i] = typical_contrast, reference_diameter[i] = typical_diameter,
      usual_look[i] = typical_look;
  recent_diameter = last_diameter = reference_diameter;
  recent_elongation.assign(states.size(), 1);
  face_scale = 1;
}

void MarkerTracker::Impl::measure_spacing() {
  const size_t n = states.size();
  spacing.assign(n, std::numeric_limits<double>::max());
  for (size_t i = 0; i < n; ++i)
    for (size_t j = 0; j < n; ++j)
      if (i != j) spacing[i] = std::min(spacing[i], cv::norm(reference[i] - reference[j]));
}

}  // namespace rostro::tracking

#include "tracking/marker_tracker_impl.hpp"

namespace rostro::tracking {

MarkerTracker::Impl::Impl(MarkerLayout l, TrackerOptions o)
    : layout(std::move(l)),
      options(validated(o)),
      full_detector(with_layout_families(options.tags)),
      window_detector(window_options(with_layout_families(options.tags))),
      threads(options.threads > 0 ? options.threads : std::max(1, cv::getNumberOfCPUs())) {
  for (const MarkerSpec& m : layout.markers) {
    MarkerState s;
    s.spec = &m;
    states.push_back(s);
    aligners.push_back(m.is_tag()
                           ? std::make_optional<TagAligner>(apriltag_image(m.family, m.tag_id),
                                                            apriltag_black_width(m.family))
                           : std::nullopt);
  }
  std::vector<FeaturePointId> points;
  for (const MarkerState& s : states) points.push_back(s.spec->feature_point);
  for (const FeaturePointId& fp : points) roles.push_back(role_of(fp));
  options.dots.polarity = layout.polarity;
  centroid_dots = options.dots;
  centroid_dots.edge_fit = false;
  lower_face_dots = options.dots;
  lower_face_centroid_dots = centroid_dots;
  if (options.surround_test_upper_face_only)
    lower_face_dots.max_surround = lower_face_centroid_dots.max_surround = kNoSurroundTest;
  inner_corner_dots = options.dots;
  inner_corner_dots.raise_share_for_roundness |= options.eyes.inner_corners_raise_share;
  // The inner corners' centre from the raised share's blob (its centroid, then the symmetric
  // centre, EyeOptions::inner_corners_symmetric_centre), not the edge fit: the edge fit's
  // rays there run along the slit's corner line and the lashes, and its centre moved with
  // the expression (Xface fear at 1280x720: 0.32-0.41 px frame-to-frame spread in x against
  // 0.14-0.18 for the centroid, which went into the head pose: pitch 5.8 -> 2.7 % of range).
  inner_corner_dots.edge_fit = false;
  inner_corner_dots.symmetric_centre = options.eyes.inner_corners_symmetric_centre;
  inner_corner_dots_large = inner_corner_dots;
  inner_corner_dots_large.max_elongation =
      std::max(options.dots.max_elongation, options.eyes.inner_corner_max_elongation_large);
  for (size_t i = 0; i < states.size(); ++i) {
    const DotRole r = roles[i];
    const bool edge_fit =
        tracking::at_eye(r) ||
        (r == DotRole::MidBrow ? options.brows.edge_fit_mid_brows : options.edge_fit_elsewhere);
    const bool upper_face = by_dark_features(points[i]);
    const DotOptions* plain = edge_fit ? (upper_face ? &options.dots : &lower_face_dots)
                                       : (upper_face ? &centroid_dots : &lower_face_centroid_dots);
    const bool inner_corner = r == DotRole::InnerEyeCorner;
    measured_with[0].push_back(inner_corner ? &inner_corner_dots : plain);
    measured_with[1].push_back(inner_corner ? &inner_corner_dots_large : plain);
  }
}

AprilTagOptions MarkerTracker::Impl::with_layout_families(AprilTagOptions o) const {
  auto families = layout.tag_families();
  if (!families.empty()) o.families = families;
  return o;
}

AprilTagOptions MarkerTracker::Impl::window_options(AprilTagOptions o) {
  o.decimation = 1;
  o.refine_edges = true;
  o.threads = 1;
  return o;
}

void MarkerTracker::Impl::to_gray(const cv::Mat& image) {
  converted.clear();
  if (image.channels() == 3 || image.channels() == 4) {
    colour = &image;
    gray_storage.create(image.size(), CV_8UC1);
    gray = gray_storage;
  } else {
    // Only read during this call: the pyramid copies what it keeps (no reuse of the input).
    colour = nullptr;
    gray = image;
  }
}

void MarkerTracker::Impl::ensure_gray(cv::Rect r) {
  if (!colour) return;
  r &= cv::Rect(0, 0, gray.cols, gray.rows);
  if (r.empty()) return;
  for (const cv::Rect& c : converted)
    if ((r & c) == r) return;
  cv::Mat out = gray(r);
  cv::cvtColor((*colour)(r), out,
               colour->channels() == 3 ? cv::COLOR_BGR2GRAY : cv::COLOR_BGRA2GRAY);
  converted.push_back(r);
}

void MarkerTracker::Impl::ensure_gray_around(cv::Point2d p, double radius) {
  if (!colour) return;
  const int half = static_cast<int>(std::ceil(radius + options.dots.max_diameter_px / 2 + 3));
  ensure_gray({static_cast<int>(std::lround(p.x)) - half, static_cast<int>(std::lround(p.y)) - half,
               2 * half + 1, 2 * half + 1});
}

cv::Rect MarkerTracker::Impl::needed_region() const {
  double x0 = 1e18, y0 = 1e18, x1 = -1e18, y1 = -1e18;
  auto add = [&](cv::Point2d p) {
    x0 = std::min(x0, p.x), y0 = std::min(y0, p.y), x1 = std::max(x1, p.x), y1 = std::max(y1, p.y);
  };
  for (size_t i = 0; i < states.size(); ++i) {
    const MarkerState& s = states[i];
    if (s.spec->is_tag())
      for (const auto& c : s.valid ? s.corners : reference_corners[i]) add(c);
    else
      add(s.valid ? s.position : reference[i]);
  }
  const double margin = options.region_margin_px * px +
                        0.5 * lk_window() * static_cast<double>(1 << options.lk_levels);
  const cv::Rect r(cv::Point(static_cast<int>(std::floor(x0 - margin)),
                             static_cast<int>(std::floor(y0 - margin))),
                   cv::Point(static_cast<int>(std::ceil(x1 + margin)),
                             static_cast<int>(std::ceil(y1 + margin))));
  return r & cv::Rect(0, 0, gray.cols, gray.rows);
}

cv::Rect MarkerTracker::Impl::placed(cv::Size size, const cv::Rect& want) const {
  size.width = std::min(size.width, gray.cols), size.height = std::min(size.height, gray.rows);
  const int cx = want.x + want.width / 2, cy = want.y + want.height / 2;
  const int x = std::clamp(cx - size.width / 2, 0, gray.cols - size.width);
  const int y = std::clamp(cy - size.height / 2, 0, gray.rows - size.height);
  return {x, y, size.width, size.height};
}

cv::Size MarkerTracker::Impl::grown(const cv::Rect& need) const {
  return {std::min(gray.cols, need.width + need.width / 5 + 16),
          std::min(gray.rows, need.height + need.height / 5 + 16)};
}

bool MarkerTracker::Impl::fits(cv::Size size, const cv::Rect& need) const {
  const bool holds = (size.width >= need.width || size.width == gray.cols) &&
                     (size.height >= need.height || size.height == gray.rows);
  const cv::Size ideal = grown(need);
  const bool not_too_big = static_cast<double>(size.area()) <= 1.5 * ideal.area();
  return holds && not_too_big;
}

void MarkerTracker::Impl::build_pyramid(const cv::Rect& r, LkPyramid& out) const {
  out.build(gray(r), {lk_window(), lk_window()}, options.lk_levels);
}

int MarkerTracker::Impl::lk_window() const {
  return static_cast<int>(std::lround(options.lk_window * std::sqrt(px))) | 1;
}

LostReason MarkerTracker::Impl::dot_check(size_t i, const Dot& d, bool followed) const {
  if (is_lid(i) && d.elongation > options.eyes.max_lid_elongation) return LostReason::LidElongation;
  if (!(d.contrast >= options.min_contrast_ratio * reference_contrast[i]))
    return LostReason::Contrast;
  if (!(d.diameter >= 0.5 * reference_diameter[i])) return LostReason::Shrunk;
  if ((followed || !reference_seen[i]) &&
      !(d.diameter >= options.min_recent_size * last_diameter[i]))
    return LostReason::Shrunk;
  if (!(d.diameter <= (at_eye(i) && !followed ? largest_found(i) : 2.0 * reference_diameter[i])))
    return LostReason::Growth;
  return LostReason::None;
}

double MarkerTracker::Impl::largest_found(size_t i) const {
  const double was = recent_diameter[i] > 0 ? recent_diameter[i] : reference_diameter[i];
  // (EyeOptions::eye_size_memory_frames: an eye dot last seen edge-on and lost a short
  // while keeps its own size.)
  const bool edge_on_lately = states[i].lost_frames < options.eyes.eye_size_memory_frames &&
                              recent_elongation[i] >= options.eyes.edge_on_elongation;
  const double grown_from =
      edge_on_lately ? was : std::max(was, reference_diameter[i] * face_scale);
  return options.eyes.max_dot_growth_found * grown_from;
}

bool MarkerTracker::Impl::dot_passes(size_t i, const Dot& d, bool followed) const {
  return dot_check(i, d, followed) == LostReason::None;
}

MarkerTracker::MarkerTracker(MarkerLayout layout, TrackerOptions options)
    : impl_(std::make_unique<Impl>(std::move(layout), std::move(options))) {}

MarkerTracker::~MarkerTracker() = default;

std::unique_ptr<FaceTracker> MarkerTracker::started_from(const TrackedFrame& start) const {
  auto tracker = std::make_unique<MarkerTracker>(impl_->layout, impl_->options);
  std::map<std::string, cv::Point2d> at;
  for (const MarkerObservation& o : start.markers)
    if (o.valid) at[o.marker] = o.position;
  tracker->set_start_positions(at);
  return tracker;
}

void MarkerTracker::set_start_positions(const std::map<std::string, cv::Point2d>& positions) {
  impl_->start_positions = positions;
  impl_->started = false;
}

TrackedFrame MarkerTracker::track(const cv::Mat& image, long frame, double time_s) {
  Impl& m = *impl_;
  m.step_times.clear();
  for (MarkerState& s : m.states) s.held = false;
  m.to_gray(image);
  if (m.started) {
    // LK needs this frame's pyramid the size of the previous one: it moves with the markers.
    m.timed("pyramid", [&] {
      const cv::Rect need = m.needed_region();
      m.region = m.placed(m.previous_region.size(), need);
      m.ensure_gray(m.region);
      m.build_pyramid(m.region, m.pyramid);
    });
    m.follow(frame);
    const long followed = frame - m.started_at;
    if (m.options.second_look_after > 0 && followed > 0 &&
        followed % m.options.second_look_after == 0 && m.start_positions.empty() &&
        m.looks < m.options.second_look_tries) {
      ++m.looks;
      if (m.timed("second_look", [&] { return m.second_look(frame); }))
        m.looks = m.options.second_look_tries;
    }
    // (Not on a frame the second look has just named afresh.)
    if (m.options.identity_check_every > 0 && followed % m.options.identity_check_every == 0 &&
        m.start_positions.empty() && m.started_at != frame)
      m.timed("check_identities", [&] { m.check_identities(); });
    // A frame that kept fewer markers than a start needs lost the face (a motion past LK's
    // reach, most of the face covered): its few are checked against nothing, and one that
    // slid onto a neighbour's dot looks as sure as one that followed its own. Everything is
    // lost and identified again from scratch.
    const auto kept = static_cast<size_t>(std::count_if(
        m.states.begin(), m.states.end(), [](const MarkerState& s) { return s.valid; }));
    if (!m.enough(kept)) {
      for (MarkerState& s : m.states)
        if (s.valid) s.valid = false, s.lost_reason = LostReason::TooFew;
      m.started = false;
    } else {
      const cv::Rect now = m.needed_region();
      if (!m.fits(m.region.size(), now)) {
        m.region = m.placed(m.grown(now), now);
        m.ensure_gray(m.region);
        m.build_pyramid(m.region, m.pyramid);
      }
    }
  } else {
    m.start();
    if (m.started) {
      m.started_at = frame;
      m.looks = 0;
      m.moved_before.clear();
      m.note = m.start_positions.empty() ? "identified, " + describe(m.identification)
                                         : "started from the starting positions";
      const cv::Rect need = m.needed_region();
      m.region = m.placed(m.grown(need), need);
      m.build_pyramid(m.region, m.pyramid);
    }
  }
  std::swap(m.previous_pyramid, m.pyramid);
  m.previous_region = m.region;

  TrackedFrame out;
  out.frame = frame;
  out.time_s = time_s;
  out.identification = std::move(m.note);
  m.note.clear();
  out.corrections = std::move(m.corrections);
  out.corrected_since = out.corrections.empty() ? -1 : m.corrected_since;
  m.corrections.clear();
  for (MarkerState& s : m.states) {
    if (s.valid) s.lost_reason = LostReason::None;
    // Found again after being lost: its name was chosen by re-acquisition, not carried by LK.
    if (s.valid && s.lost_frames > 0 && m.started_at != frame)
      m.unconfirmed.insert(static_cast<size_t>(&s - m.states.data()));
    s.held = s.held && s.valid;  // found again this frame (Impl::found_on)
    if (s.held) s.lost_reason = LostReason::FoundAgain;
    s.lost_frames = s.valid ? 0 : s.lost_frames + 1;
    if (!s.valid) s.quality = 0;
    MarkerObservation o;
    o.marker = s.spec->id;
    o.feature_point = s.spec->feature_point;
    o.valid = s.valid && !s.held;
    o.position = s.valid ? s.position : cv::Point2d(std::nan(""), std::nan(""));
    o.quality = s.quality;
    out.markers.push_back(o);
  }
  return out;
}

void TrackerOptions::validate() const {
  dots.validate();
  identification.validate();
  eyes.validate();
  lower_lip.validate();
  OptionCheck("TrackerOptions")
      .positive("reference_dot_px", reference_dot_px)
      .positive("lk_window", lk_window)
      .not_negative("lk_levels", lk_levels)
      .not_negative("region_margin_px", region_margin_px)
      .positive("max_fb_error", max_fb_error)
      .positive("max_snap", max_snap)
      .not_negative("min_contrast_ratio", min_contrast_ratio)
      .not_negative("min_recent_size", min_recent_size)
      .not_negative("tag_margin", tag_margin)
      .not_negative("tag_decimate_above_px", tag_decimate_above_px)
      .positive("tag_redetect_every", tag_redetect_every)
      .positive("search_fraction", search_fraction)
      .not_negative("max_relative_motion", max_relative_motion)
      .not_negative("max_relative_motion_px", max_relative_motion_px)
      .not_negative("hold_found_after_lost", hold_found_after_lost)
      .not_negative("min_identified", min_identified)
      .not_negative("identity_check_every", identity_check_every)
      .not_negative("second_look_after", second_look_after)
      .at_least("second_look_tries", second_look_tries, 1)
      .not_negative("threads", threads);
}

void set_tracker_option(TrackerOptions& options, const std::string& assignment) {
  using O = TrackerOptions;
  static const std::vector<NamedOption<O>> table = {
      ROSTRO_NAMED_OPTION(O, dots.min_diameter_px),
      ROSTRO_NAMED_OPTION(O, dots.max_diameter_px),
      ROSTRO_NAMED_OPTION(O, dots.min_contrast),
      ROSTRO_NAMED_OPTION(O, dots.min_roundness),
      ROSTRO_NAMED_OPTION(O, dots.min_roundness_merged),
      ROSTRO_NAMED_OPTION(O, dots.max_elongation),
      ROSTRO_NAMED_OPTION(O, dots.max_surround),
      ROSTRO_NAMED_OPTION(O, dots.edge_fit),
      ROSTRO_NAMED_OPTION(O, dots.raise_share_for_roundness),
      ROSTRO_NAMED_OPTION(O, dots.symmetric_centre),
      ROSTRO_NAMED_OPTION(O, reference_dot_px),
      ROSTRO_NAMED_OPTION(O, edge_fit_elsewhere),
      ROSTRO_NAMED_OPTION(O, surround_test_upper_face_only),
      ROSTRO_NAMED_OPTION(O, brows.edge_fit_mid_brows),
      ROSTRO_NAMED_OPTION(O, eyes.inner_corners_raise_share),
      ROSTRO_NAMED_OPTION(O, eyes.inner_corners_symmetric_centre),
      ROSTRO_NAMED_OPTION(O, eyes.inner_corner_max_elongation_large),
      ROSTRO_NAMED_OPTION(O, lk_window),
      ROSTRO_NAMED_OPTION(O, lk_levels),
      ROSTRO_NAMED_OPTION(O, region_margin_px),
      ROSTRO_NAMED_OPTION(O, max_fb_error),
      ROSTRO_NAMED_OPTION(O, max_snap),
      ROSTRO_NAMED_OPTION(O, min_contrast_ratio),
      ROSTRO_NAMED_OPTION(O, min_recent_size),
      ROSTRO_NAMED_OPTION(O, tag_margin),
      ROSTRO_NAMED_OPTION(O, tag_decimate_above_px),
      ROSTRO_NAMED_OPTION(O, tag_redetect_every),
      ROSTRO_NAMED_OPTION(O, align_tags),
      ROSTRO_NAMED_OPTION(O, search_fraction),
      ROSTRO_NAMED_OPTION(O, found_look_allowance),
      ROSTRO_NAMED_OPTION(O, max_relative_motion),
      ROSTRO_NAMED_OPTION(O, max_relative_motion_px),
      ROSTRO_NAMED_OPTION(O, lower_lip.together),
      ROSTRO_NAMED_OPTION(O, lower_lip.with_the_jaw),
      ROSTRO_NAMED_OPTION(O, swap_back_pairs),
      ROSTRO_NAMED_OPTION(O, hold_found_after_lost),
      ROSTRO_NAMED_OPTION(O, lower_lip.up),
      ROSTRO_NAMED_OPTION(O, lower_lip.down),
      ROSTRO_NAMED_OPTION(O, lower_lip.sideways),
      ROSTRO_NAMED_OPTION(O, lower_lip.shape),
      ROSTRO_NAMED_OPTION(O, eyes.max_dot_growth_found),
      ROSTRO_NAMED_OPTION(O, eyes.eye_size_memory_frames),
      ROSTRO_NAMED_OPTION(O, eyes.edge_on_elongation),
      ROSTRO_NAMED_OPTION(O, eyes.max_lid_elongation),
      ROSTRO_NAMED_OPTION(O, min_identified),
      ROSTRO_NAMED_OPTION(O, identification.gate),
      ROSTRO_NAMED_OPTION(O, identification.size_factor),
      ROSTRO_NAMED_OPTION(O, identification.shape_factor),
      ROSTRO_NAMED_OPTION(O, identification.alone_share),
      ROSTRO_NAMED_OPTION(O, identification.ink_weight),
      ROSTRO_NAMED_OPTION(O, identification.lower_lip_apart),
      ROSTRO_NAMED_OPTION(O, identification.dots_beside_points),
      ROSTRO_NAMED_OPTION(O, identification.unnamed_rival),
      ROSTRO_NAMED_OPTION(O, identification.sure_within),
      ROSTRO_NAMED_OPTION(O, identification.min_explained),
      ROSTRO_NAMED_OPTION(O, identification.max_residual),
      ROSTRO_NAMED_OPTION(O, identification.min_margin),
      ROSTRO_NAMED_OPTION(O, identification.min_tags),
      ROSTRO_NAMED_OPTION(O, identification.max_tag_error),
      ROSTRO_NAMED_OPTION(O, identification.max_elongation),
      ROSTRO_NAMED_OPTION(O, identity_check_every),
      ROSTRO_NAMED_OPTION(O, second_look_after),
      ROSTRO_NAMED_OPTION(O, second_look_tries),
      ROSTRO_NAMED_OPTION(O, threads),
  };
  set_named_option(options, table, "TrackerOptions", assignment);
}

const char* to_string(LostReason r) {
  switch (r) {
    case LostReason::None:
      return "none";
    case LostReason::Unidentified:
      return "unidentified";
    case LostReason::RoundTrip:
      return "round trip";
    case LostReason::NoDot:
      return "no dot";
    case LostReason::Snap:
      return "snap";
    case LostReason::LidElongation:
      return "lid elongation";
    case LostReason::Contrast:
      return "contrast";
    case LostReason::Shrunk:
      return "shrunk";
    case LostReason::Growth:
      return "growth";
    case LostReason::Jump:
      return "jump";
    case LostReason::Coincident:
      return "coincident";
    case LostReason::Identity:
      return "identity";
    case LostReason::TagLost:
      return "tag lost";
    case LostReason::TooFew:
      return "too few";
    case LostReason::FoundAgain:
      return "found again";
  }
  return "?";
}

long MarkerTracker::correction_horizon() const {
  const TrackerOptions& o = impl_->options;
  const long second_look =
      impl_->start_positions.empty() ? o.second_look_after * o.second_look_tries : 0;
  return o.swap_back_pairs ? std::max(second_look, Impl::kSwapBackReach) : second_look;
}

bool MarkerTracker::started() const {
  return impl_->started;
}
const IdentificationConfidence& MarkerTracker::identification() const {
  return impl_->identification;
}
long MarkerTracker::started_at() const {
  return impl_->started_at;
}
const std::vector<MarkerState>& MarkerTracker::states() const {
  return impl_->states;
}
const MarkerLayout& MarkerTracker::layout() const {
  return impl_->layout;
}
const std::vector<StepTime>& MarkerTracker::step_times() const {
  return impl_->step_times;
}
void MarkerTracker::draw(cv::Mat& image, long frame) const {
  draw_overlay(image, impl_->states, frame);
}

}  // namespace rostro::tracking

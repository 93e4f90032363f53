#include "tracking/landmark_tracker.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <string>

#include "facecore/error.hpp"
#include "tracking/overlay.hpp"

namespace rostro::tracking {
namespace {

constexpr int kLandmarks = LandmarkModel::kLandmarks;

// iBUG 0-based indices of the outer eye corners: the eye distance is the stabiliser's unit.
constexpr int kRightEyeOuter = 36, kLeftEyeOuter = 45;

double eye_distance(const std::vector<cv::Point2d>& landmarks) {
  return cv::norm(landmarks[kRightEyeOuter] - landmarks[kLeftEyeOuter]);
}

cv::Point2d centre(const cv::Rect2d& r) {
  return {r.x + r.width / 2, r.y + r.height / 2};
}

// iBUG 0-based indices of the nose (27-35) and the eye corners: the part of the face that
// expressions do not move. The box is placed by these alone: placed by all 68, an opened jaw
// moved it down, and a jaw closed again within the box's deadband left it there; placed with
// the lids, a blink moved it.
constexpr std::array<int, 13> kRigid = {27, 28, 29, 30, 31, 32, 33, 34, 35, 36, 39, 42, 45};

cv::Rect2d rigid_box(const std::vector<cv::Point2d>& points) {
  double x0 = points[27].x, y0 = points[27].y, x1 = x0, y1 = y0;
  for (int i : kRigid) {
    const cv::Point2d& p = points[static_cast<std::size_t>(i)];
    x0 = std::min(x0, p.x), y0 = std::min(y0, p.y);
    x1 = std::max(x1, p.x), y1 = std::max(y1, p.y);
  }
  return {x0, y0, x1 - x0, y1 - y0};
}

// Where the detector's box lies against the rigid points' bounding box, in units of that box:
// kept from the detection that found the face, so that the boxes later made from landmarks
// are boxes like those the shape predictor was trained on (the detector's), without the
// detector's own jitter (its boxes step by its 8-pixel cells).
struct BoxRelation {
  double dx = 0, dy = 0, sw = 1, sh = 1;  // centre offset, size ratio

  static BoxRelation between(const cv::Rect2d& detection, const cv::Rect2d& landmarks) {
    const cv::Point2d d = centre(detection) - centre(landmarks);
    return {d.x / landmarks.width, d.y / landmarks.height, detection.width / landmarks.width,
            detection.height / landmarks.height};
  }
  cv::Rect2d apply(const cv::Rect2d& landmarks) const {
    const double w = sw * landmarks.width, h = sh * landmarks.height;
    const cv::Point2d c =
        centre(landmarks) + cv::Point2d(dx * landmarks.width, dy * landmarks.height);
    return {c.x - w / 2, c.y - h / 2, w, h};
  }
};

// 1/(1 + e^-2s): the detector's score as a share (0 at the threshold is 0.5).
double quality_of(double confidence) {
  return 1.0 / (1.0 + std::exp(-2.0 * confidence));
}

}  // namespace

void LandmarkTrackerOptions::validate() const {
  if (face_rank < 1)
    throw InputError("--face: faces are ranked from 1 (the largest), not " +
                     std::to_string(face_rank));
  if (!(min_face_px >= 20) || !std::isfinite(min_face_px))
    throw InputError("landmark tracker: the smallest face must be at least 20 px wide, not " +
                     std::to_string(min_face_px));
  if (!(box_anchor > box_deadband && box_anchor < 1))
    throw InputError(
        "landmark tracker: the box anchor is a share above the deadband, below 1, "
        "not " +
        std::to_string(box_anchor));
  if (!(box_deadband >= 0 && box_deadband < 1))
    throw InputError("landmark tracker: the box deadband is a share of the face in [0, 1), not " +
                     std::to_string(box_deadband));
  if (check_every < 1)
    throw InputError("landmark tracker: the detector looks again every 1 or more frames, not " +
                     std::to_string(check_every));
  if (!(min_flow_agreement >= 0 && min_flow_agreement <= 1))
    throw InputError("landmark tracker: the flow agreement is a share in [0, 1], not " +
                     std::to_string(min_flow_agreement));
  if (!(look_window >= 1 && look_window <= 4))
    throw InputError("landmark tracker: the detector's window is 1 to 4 times the face, not " +
                     std::to_string(look_window));
  if (!std::isfinite(follow_threshold))
    throw InputError("landmark tracker: the detector threshold must be finite");
  stabiliser.validate();
}

struct LandmarkTracker::Impl {
  IbugMapping mapping;
  MarkerLayout layout;
  LandmarkTrackerOptions options;
  LandmarkModel model;

  bool started = false;
  bool following = false;
  std::optional<cv::Rect2d> box;  // the box the followed face's landmarks are fitted in
  BoxRelation relation;
  double confidence = 0;  // the detector's score when the face was last found or checked
  int since_check = 0;    // frames since the detector last looked
  long searches = 0;
  std::vector<cv::Point2d> raw, smoothed;
  LandmarkStabiliser stabiliser{options.stabiliser};
  std::vector<MarkerState> states;
  cv::Mat gray;

  Impl(const IbugMapping& m, const FeaturePointPositions& neutral, LandmarkTrackerOptions o)
      : mapping(m),
        layout(landmark_layout(m, neutral)),
        options(validated(std::move(o))),
        model(options.model.empty() ? default_landmark_model() : options.model) {
    for (const IbugMarker& marker : mapping.markers)
      for (int i : marker.points)
        if (i >= kLandmarks)
          throw InputError("landmark mapping: marker " + marker.marker + " names iBUG point " +
                           std::to_string(i + 1) + ", beyond the model's 68");
    for (const MarkerSpec& spec : layout.markers) {
      MarkerState state;
      state.spec = &spec;
      states.push_back(state);
    }
  }

  static LandmarkTrackerOptions validated(LandmarkTrackerOptions o) {
    o.validate();
    return o;
  }

  // Step 1: the whole image, the face_rank-th largest face.
  std::optional<FaceDetection> search() {
    ++searches;
    auto faces = model.detect(gray, cv::Rect(0, 0, gray.cols, gray.rows), options.min_face_px, 0.0);
    if (static_cast<int>(faces.size()) < options.face_rank) return std::nullopt;
    std::sort(faces.begin(), faces.end(), [](const FaceDetection& a, const FaceDetection& b) {
      return a.box.area() > b.box.area();
    });
    return faces[static_cast<std::size_t>(options.face_rank - 1)];
  }

  // Step 2: the followed face again, near where it was and about its size, in a window
  // look_window times its size around it.
  std::optional<FaceDetection> find_again(const cv::Rect2d& last) {
    const double k = options.look_window;
    const cv::Rect window =
        cv::Rect(cv::Point(static_cast<int>(last.x - last.width * (k - 1) / 2),
                           static_cast<int>(last.y - last.height * (k - 1) / 2)),
                 cv::Size(static_cast<int>(last.width * k), static_cast<int>(last.height * k))) &
        cv::Rect(0, 0, gray.cols, gray.rows);
    if (window.width < 8 || window.height < 8) return std::nullopt;
    std::optional<FaceDetection> best;
    // The face at 0.8 of its last size meets the detector's smallest window: it may shrink by
    // a fifth in a frame, or grow (the detector's pyramid covers larger faces).
    for (const FaceDetection& d :
         model.detect(gray, window, 0.8 * last.width, options.follow_threshold)) {
      const double size = d.box.width / last.width;
      if (cv::norm(centre(d.box) - centre(last)) > 0.5 * last.width || size < 0.7 || size > 1.4)
        continue;
      if (!best || d.confidence > best->confidence) best = d;
    }
    return best;
  }

  // Step 3: the box the landmarks are fitted in follows last frame's landmarks only once they
  // have moved it by more than box_deadband of its width (or grown it by that share): a still
  // face keeps one box, and the fit's noise is not fed back into the next frame's box. Fit
  // and box can carry each other away (the fit leans toward its box); where the box parts
  // from the detector's by more than box_anchor, the detector's is taken instead.
  void move_box(const cv::Rect2d& from_landmarks, const std::optional<cv::Rect2d>& detected) {
    const auto apart = [](const cv::Rect2d& a, const cv::Rect2d& b) {
      return std::max(cv::norm(centre(a) - centre(b)) / b.width,
                      std::abs(std::log(a.width / b.width)));
    };
    if (detected && apart(from_landmarks, *detected) > options.box_anchor)
      box = *detected;
    else if (apart(from_landmarks, *box) > options.box_deadband)
      box = from_landmarks;
  }

  void fit(const cv::Rect2d& around) { raw = model.fit(gray, around); }

  void lose() {
    following = false;
    box.reset();
    raw.clear(), smoothed.clear();
    stabiliser.reset();
  }

  // Steps 1-3 for this frame: whether a face is there, and its box.
  bool find_face() {
    if (following) {
      // The flow tells, every frame and nearly for free, whether the face moved as one; the
      // detector looks again every check_every frames, and at once when the flow disagrees.
      const double moved_as_one = stabiliser.predict(gray, eye_distance(smoothed));
      if (++since_check < options.check_every && moved_as_one >= options.min_flow_agreement) {
        move_box(relation.apply(rigid_box(smoothed)), std::nullopt);
        return true;
      }
      since_check = 0;
      if (const auto again = find_again(*box)) {
        confidence = again->confidence;
        move_box(relation.apply(rigid_box(smoothed)), again->box);
        return true;
      }
      lose();
    }
    const auto found = search();
    if (!found) return false;
    confidence = found->confidence;
    following = started = true;
    since_check = 0;
    box = found->box;
    fit(*box);
    relation = BoxRelation::between(*box, rigid_box(raw));
    return true;
  }

  TrackedFrame track(const cv::Mat& image, long frame, double time_s) {
    if (image.channels() == 3)
      cv::cvtColor(image, gray, cv::COLOR_BGR2GRAY);
    else if (image.channels() == 4)
      cv::cvtColor(image, gray, cv::COLOR_BGRA2GRAY);
    else
      gray = image;
    if (gray.depth() != CV_8U) throw InputError("landmark tracker: frames must be 8-bit images");

    TrackedFrame out;
    out.frame = frame;
    out.time_s = time_s;
    const bool face = find_face();
    if (face) {
      fit(*box);
      stabilise();
    }
    const cv::Rect2d inside(0, 0, gray.cols, gray.rows);
    for (std::size_t k = 0; k < mapping.markers.size(); ++k) {
      MarkerObservation o;
      o.marker = layout.markers[k].id;
      o.feature_point = layout.markers[k].feature_point;
      MarkerState& state = states[k];
      if (face) {
        o.position = mapped_position(mapping.markers[k], smoothed);
        o.valid = inside.contains(o.position);
        o.quality = o.valid ? quality_of(confidence) : 0.0;
      }
      state.valid = o.valid;
      state.quality = o.quality;
      if (o.valid) state.position = o.position;
      state.lost_frames = o.valid ? 0 : state.lost_frames + 1;
      out.markers.push_back(std::move(o));
    }
    return out;
  }

  // Step 4: optical flow blended with the fit.
  void stabilise() {
    const std::vector<cv::Point2d> blended = stabiliser.blend(gray, raw, eye_distance(raw));
    smoothed = options.stabilise ? blended : raw;
  }
};

LandmarkTracker::LandmarkTracker(const IbugMapping& mapping, const FeaturePointPositions& neutral,
                                 LandmarkTrackerOptions options)
    : impl_(std::make_unique<Impl>(mapping, neutral, std::move(options))) {}

LandmarkTracker::~LandmarkTracker() = default;

TrackedFrame LandmarkTracker::track(const cv::Mat& image, long frame, double time_s) {
  return impl_->track(image, frame, time_s);
}

bool LandmarkTracker::started() const {
  return impl_->started;
}
const MarkerLayout& LandmarkTracker::layout() const {
  return impl_->layout;
}
const std::vector<cv::Point2d>& LandmarkTracker::raw_landmarks() const {
  return impl_->raw;
}
const std::vector<cv::Point2d>& LandmarkTracker::landmarks() const {
  return impl_->smoothed;
}
long LandmarkTracker::searches() const {
  return impl_->searches;
}

void LandmarkTracker::draw(cv::Mat& image, long frame) const {
  if (image.channels() == 1) cv::cvtColor(image, image, cv::COLOR_GRAY2BGR);
  for (const cv::Point2d& p : impl_->smoothed)
    cv::circle(image, p, 2, {0, 200, 255}, -1, cv::LINE_AA);
  draw_overlay(image, impl_->states, frame);
}

}  // namespace rostro::tracking

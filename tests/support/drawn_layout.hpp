#pragma once
// For the tracking tests that draw the layout's dots on a flat image: sub-pixel drawing and
// starting the tracker on the drawn places.

#include <map>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <string>
#include <vector>

#include "tracking/layout.hpp"
#include "tracking/marker_tracker.hpp"

namespace rostro::tracking::testing {

constexpr int kDrawShift = 4;  // sub-pixel bits for OpenCV's drawing calls

// `p` in OpenCV's fixed-point drawing coordinates (kDrawShift bits).
inline cv::Point fixed_point(cv::Point2d p) {
  return {cvRound(p.x * (1 << kDrawShift)), cvRound(p.y * (1 << kDrawShift))};
}

// A filled, anti-aliased disc of `grey` centred to 1/16 px.
inline void draw_disc(cv::Mat& img, cv::Point2d centre, double radius_px, int grey) {
  cv::circle(img, fixed_point(centre), cvRound(radius_px * (1 << kDrawShift)), cv::Scalar(grey),
             cv::FILLED, cv::LINE_AA, kDrawShift);
}

// Frontal layout millimetres (x right, y down) to pixels, `scale` pixels a millimetre: the
// face centred as the layout's origin is at 640x480 with 2.4 px a millimetre, the image grown
// with the scale.
inline cv::Point2d frontal_to_image(cv::Point2d mm, double scale) {
  return cv::Point2d(320, 230) * (scale / 2.4) + mm * scale;
}

// Starts `tracker` with every dot where `place(marker)` draws it: a flat drawing is no face
// for automatic identification.
template <typename Place>
void start_on_drawing(MarkerTracker& tracker, const MarkerLayout& layout, Place place) {
  std::map<std::string, cv::Point2d> start;
  for (const MarkerSpec& m : layout.markers)
    if (!m.is_tag()) start[m.id] = place(m);
  tracker.set_start_positions(start);
}

// Per frame k < frames: `marker`'s distance in pixels from its true place, or -1 while it is
// reported lost, as `tracker` follows the frames `render(k, img)` draws (returning that place),
// blurred by `blur_sigma` as a lens would.
template <typename Render>
std::vector<double> follow_marker(MarkerTracker& tracker, const std::string& marker, int frames,
                                  double blur_sigma, Render render) {
  std::vector<double> errors;
  for (int k = 0; k < frames; ++k) {
    cv::Mat img;
    const cv::Point2d truth = render(k, img);
    cv::GaussianBlur(img, img, {0, 0}, blur_sigma);
    double error = -1;
    for (const MarkerObservation& o : tracker.track(img, k, k / 25.0).markers)
      if (o.marker == marker && o.valid) error = cv::norm(o.position - truth);
    errors.push_back(error);
  }
  return errors;
}

// A drawn take as tracked: per frame, where each dot was drawn and where each valid marker
// was seen.
struct DrawnRun {
  std::vector<std::map<std::string, cv::Point2d>> truth;
  std::vector<std::map<std::string, cv::Point2d>> seen;
};

// Frame k: draws on `img` (the background) every dot `place(marker)` puts somewhere (an
// optional point in pixels: none while hidden), blurs it a little as a lens would, tracks it and
// adds the frame to `run`.
template <typename Place>
void draw_and_track(MarkerTracker& tracker, const MarkerLayout& layout, cv::Mat img, int k,
                    double dot_radius_px, Place place, DrawnRun& run) {
  std::map<std::string, cv::Point2d> truth;
  for (const MarkerSpec& m : layout.markers) {
    if (m.is_tag()) continue;
    const std::optional<cv::Point2d> c = place(m);
    if (!c) continue;
    truth[m.id] = *c;
    draw_disc(img, *c, dot_radius_px, 25);
  }
  cv::GaussianBlur(img, img, {0, 0}, 0.7);
  std::map<std::string, cv::Point2d> seen;
  for (const MarkerObservation& o : tracker.track(img, k, k / 25.0).markers)
    if (o.valid) seen[o.marker] = o.position;
  run.truth.push_back(std::move(truth));
  run.seen.push_back(std::move(seen));
}

}  // namespace rostro::tracking::testing

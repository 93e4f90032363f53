#pragma once
// Follows a bare face through a take with dlib's 68-point shape predictor (the iBUG 300-W
// landmarks), giving the same TrackedFrame as the marker tracker: each landmark named by its
// MPEG-4 feature point through an IbugMapping (tracking/ibug_mapping.hpp).
//
// Per frame:
//  1. find the face: while none is followed, dlib's HOG frontal face detector searches the
//     whole image (scaled so that a face of min_face_px is the detector's 80 px window); with
//     several faces the face_rank-th largest is taken;
//  2. check it is still there: while a face is followed, optical flow carries its last
//     landmarks into the frame, and the share of them that move as one face (a similarity)
//     is the check on every frame; every check_every frames, and on any frame where too few
//     move as one, the detector looks again in a window around it (look_window times the
//     face's size), at its scale. No face there ends the following and the whole image is searched
//     on the same frame. A frame so costs the flow and one shape fit, not an image search;
//  3. place the box: it follows the last frame's landmarks (in the relation the detector's box
//     had to them when the face was found) once they have moved it by a twentieth of the face
//     (box_deadband), so a still face keeps one box; and it is the detector's box whenever
//     it parts from that by more than box_anchor;
//  4. fit the 68 landmarks in the box to sub-pixel precision, and steady them by blending
//     them with the flow's carried points (tracking/landmark_stabiliser.hpp).
// A frame with no face has every observation invalid: nothing is guessed, and the take goes
// on until the face is found again.

#include <filesystem>
#include <memory>
#include <opencv2/core.hpp>
#include <vector>

#include "facecore/fapu.hpp"
#include "tracking/face_tracker.hpp"
#include "tracking/ibug_mapping.hpp"
#include "tracking/landmark_model.hpp"
#include "tracking/landmark_stabiliser.hpp"

namespace rostro::tracking {

struct LandmarkTrackerOptions {
  // dlib shape predictor file (68 points, iBUG order). Empty: default_landmark_model().
  std::filesystem::path model;
  int face_rank = 1;         // with several faces in view: 1 the largest, 2 the next, ...
  double min_face_px = 100;  // smallest face width (pixels) the whole-image search finds
  // Detector score (dlib's adjust_threshold) a followed face must reach when the detector
  // looks again; below 0 accepts weaker faces than a first detection needs (a turned or
  // expressive face).
  double follow_threshold = -0.5;
  // The detector looks again every this many frames while the optical flow says the face
  // moves as one, and on any frame where less than min_flow_agreement of its points do (a
  // face covered, turned away or gone).
  int check_every = 10;
  double min_flow_agreement = 0.6;
  // The window the detector looks again in, as a multiple of the face's box around it. The box
  // follows the landmarks every frame, so the face is found near it; the detector's cost
  // grows with the window's area, and it is the costliest step of the frames it runs on
  // (docs/benchmarks.md, "Landmark tracking"): 1.5 costs about half of 2.
  double look_window = 1.5;
  // The box a followed face is fitted in moves with its landmarks only once they have moved
  // it by this share of its width (or grown it by this share): a still face keeps one box.
  double box_deadband = 0.05;
  // ... and is the detector's box when it lies further than this share from that.
  double box_anchor = 0.15;
  bool stabilise = true;  // optical flow blended with the fit (false: the raw fit)
  StabiliserOptions stabiliser;
  void validate() const;  // throws InputError naming the option
};

class LandmarkTracker : public FaceTracker {
 public:
  // `neutral`: a neutral face's feature points (mm), which place the layout's landmarks for
  // calibration (landmark_layout()). Throws InputError when the model file is missing (naming
  // the path and the Debian package) or unreadable.
  LandmarkTracker(const IbugMapping& mapping, const FeaturePointPositions& neutral,
                  LandmarkTrackerOptions options = {});
  ~LandmarkTracker() override;

  TrackedFrame track(const cv::Mat& image, long frame, double time_s) override;
  bool started() const override;
  const MarkerLayout& layout() const override;
  void draw(cv::Mat& image, long frame) const override;

  // The last frame's 68 landmarks (pixels), as fitted and as reported (stabilised); empty
  // when the last frame had no face.
  const std::vector<cv::Point2d>& raw_landmarks() const;
  const std::vector<cv::Point2d>& landmarks() const;
  // Whole-image searches run so far (the first detection and every re-acquisition attempt).
  long searches() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rostro::tracking

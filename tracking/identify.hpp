#pragma once
// Naming the markers at the start of a take, with no clicks: the AprilTags found fix where
// the layout's frontal arrangement lies in the image (a similarity from their corners), the
// detected dots are matched to the layout's dots by proximity, and the mapping is refitted
// as an affine transform from the matches, a few rounds. Without tags the first guesses come
// from the dot cloud's centre and spread (face upright and frontal) at a range of rolls.
//
// A real face carries many dark blobs beside the dots (pupils, nostrils, lip corners, hair),
// and a blurred frame may show no tag: an arrangement shifted by a row can then explain the
// blobs nearly as well as the right one. So every identification says how sure it is
// (IdentificationConfidence): how many of the layout's dots the fitted arrangement explains
// and how closely, by how much it beats the next-best distinct assignment, and whether the
// tags were read and agree with it. The tracker starts only on a confident frame.
#include <map>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "tracking/apriltag_detector.hpp"
#include "tracking/dot_detector.hpp"
#include "tracking/landmark_model.hpp"
#include "tracking/layout.hpp"

namespace rostro::tracking {

struct IdentificationOptions {
  // The fraction of a dot's distance to its nearest layout neighbour within which a detection
  // may be given to it.
  double gate = 0.45;
  // The layout's dots share one size: a detection more than this factor larger or smaller
  // than the matched detections' median diameter (a pupil, a nostril, a clump of hair) is
  // given to no dot.
  double size_factor = 1.5;
  // And one shape: a painted dot is round, so its image is about as long for its width as the
  // other dots' (motion blur smears them all alike, a turn foreshortens its neighbours alike),
  // where a lip corner, a gap between teeth or the eye's slit is a blob twice as long as wide
  // that stood apart from the darker feature it runs into only when measured high up its
  // contrast (Dot::share). A detection more than `shape_factor` times as elongated as the
  // matched detections' median and measured above `alone_share` is given to no dot. A dot on
  // skin that turns away from the camera (the chin's, seen from the front) is long too, but
  // stands alone: it is measured low.
  double shape_factor = 1.5;
  double alone_share = 0.6;
  // And one ink: in the final naming a detection fainter than the named detections' median
  // contrast costs as much more as if it lay farther, ink_weight x (its spacing x ln(median /
  // its contrast))^2 farther squared, so that of two detections near a dot's place the one
  // as dark as the other dots takes the name (the dot above the eye, not the shadow in it);
  // a faint dot alone near its place (in a corner's shadow, on skin turning away) is still
  // named (tests/tracking/dark_features_test.cpp). 0: position alone. Measured 0.15-0.5 on the
  // photo scenes (docs/accuracy.md, "A faint blob weighs twice as much").
  double ink_weight = 0.3;
  // The lower lip's dots (MPEG-4 8.2, 8.7, 8.8) are neighbours only of each other where the
  // naming moves a dot's place by its neighbours' offsets (the face model's, then the named
  // detections'): the lower lip drops and spreads away from the upper lip and the corners, so
  // in an open mouth their offsets pulled its places back toward the lip line by up to a
  // spacing, where a lower-lip dot took its neighbour's detection or none (the photo scenes:
  // the hand's, a blur's). The tracker treats it apart likewise (LowerLipOptions::together).
  // false: every dot a neighbour of every other.
  bool lower_lip_apart = true;
  // A name in doubt is left out: a dot that lies farther than sure_within of its spacing from
  // its place, with the place of a dot left unnamed within unnamed_rival x that distance of
  // it, could be either (the mid-brow dot unseen in the brow hair, the upper-lid dot below it
  // nearer the mid-brow's place than the lid's); naming it one of them is a coin toss that LK
  // then follows to the end. MarkerTracker's re-acquisition leaves such a dot to the other
  // lost marker likewise. 0: never left out.
  double unnamed_rival = 1.5;
  double sure_within = 0.25;
  // A confident identification meets all of these.
  double min_explained = 0.8;  // share of the layout's dots given a detection
  double max_residual = 0.3;   // IdentificationConfidence::residual
  double min_margin = 0.2;     // IdentificationConfidence::margin
  int min_tags = 2;            // tags read, of a layout with tags (all of them when fewer)
  // A tag agrees when its centre lies within this many tag sides of where the fitted
  // arrangement puts it; arrangements that more than half the tags read disagree with are not
  // considered at all.
  double max_tag_error = 0.5;
  // The named dots' median elongation (long over short axis) above this is motion blur: a
  // smeared dot's centre, and so its name, is unsure.
  double max_elongation = 1.5;
  // The face model's places are its feature points; each dot is looked for `beside` its point
  // as the layout says it is worn (and farther out by how much larger than the layout's the
  // dots are). false: at the point itself.
  bool dots_beside_points = true;
  // Name the dots near where dlib's landmarks put them on this face (face_prior.hpp); empty:
  // by the layout's arrangement alone. MarkerTracker reads it; identify_markers() takes the
  // places themselves.
  std::filesystem::path face_model = default_landmark_model();

  // Throws InputError naming the first option out of range.
  void validate() const;
};

struct IdentificationConfidence {
  int dots = 0;     // the layout's dots
  int matched = 0;  // given a detection
  // Median distance of the named dots from where their named neighbours put them, in spacings.
  double residual = 0;
  // How much farther than its own detection the next one lies from a named dot's place, in
  // half spacings (1: half a spacing or more), the lowest quartile over the named dots;
  // without tags read, no more than 1 - (the best rival arrangement's score / this one's).
  double margin = 0;
  int tags = 0;       // the layout's tags
  int tags_seen = 0;  // read in the image
  int tags_agreeing = 0;
  bool face_model = false;  // the dots were named near a face model's places (face_prior.hpp)
  double elongation = 1;    // the named dots' median elongation (motion blur smears them)
  bool confident = false;
  std::string doubt;  // why not confident, in words ("1 of 3 tags read"); empty when confident
};

// "29/31 dots, residual 0.06, margin 0.71, tags 3/3 read, 3 agree"
std::string describe(const IdentificationConfidence& confidence);

struct Identification {
  std::map<std::string, Dot> dots;           // layout id -> the detection it was given
  std::map<std::string, TagDetection> tags;  // layout id -> detection
  cv::Matx23d layout_to_image;               // frontal millimetres -> pixels
  bool mapped = false;                       // false when nothing could be placed
  IdentificationConfidence confidence;
  // Where the naming expects every layout dot, named or not (layout id -> pixels): the face's
  // own shape where a model of it was used, the layout's arrangement otherwise.
  std::map<std::string, cv::Point2d> places;

  cv::Point2d project(cv::Point2d frontal_mm) const;
};

// `expected`: where a model of this face puts some of the layout's dots (layout id -> pixels,
// face_prior.hpp), or nothing. With it the dots are named near those places (and the layout's
// arrangement mapped onto them for the rest) wherever the tags read agree with them.
Identification identify_markers(const MarkerLayout& layout, const std::vector<Dot>& dots,
                                const std::vector<TagDetection>& tags,
                                const IdentificationOptions& options = {},
                                const std::map<std::string, cv::Point2d>& expected = {});

// Starting positions from a file instead: the first frame of a tracks CSV (valid rows only).
std::map<std::string, cv::Point2d> read_start_positions(const std::filesystem::path& path,
                                                        const MarkerLayout& layout);

}  // namespace rostro::tracking

#pragma once
// Test scenes that are not rostro's rendered head (issue 21): a real photograph of a face with
// a marker layout's dots painted on the skin and its AprilTags on a light headband across the
// forehead, moved by a smooth warp, with exact truth.
//
// Placement: dlib's 68 landmarks are fitted to the chosen face (tracking::LandmarkModel). A
// layout dot whose feature point has an iBUG counterpart (data/eval/ibug68_to_mpeg4.json)
// starts from that landmark; every other dot goes through a smooth map from the layout's
// frontal millimetres (MarkerSpec::frontal()) to the photo: an affine fitted to the mapped
// dots plus their residuals spread by normalised Gaussian weights. Then the dots are nudged onto
// skin as a make-up artist would: brow dots above the brow hair, upper-lid dots above the lid line
// and lower-lid dots below it, eye-corner and mouth-corner dots just outside the corner, the
// chin dot (iBUG 9 is the jaw's silhouette) 15 % of the way up toward the lower lip; a dot left
// near a pupil or a nostril is pushed away from it, every dot is moved a little at random
// (placement_jitter), and dots nearer each other than 1.8 diameters are pushed apart. Tags (and
// the headband) go through the map's affine part only, so they are flat and rigid.
//
// Rendering: the photo is resampled (INTER_CUBIC, its own surroundings reflected past its
// edges) onto a canvas twice as fine as the output, scaled so that the face
// (jaw width, iBUG 1 to 17) is `face_px` output pixels wide, and the markers are painted on it:
// dots as anti-aliased discs of `dot_px` with a one-pixel soft edge, dark (a quarter of the
// skin's colour around them), tags with their white quiet zone. Frame t is the canvas moved by
//   F_t(p) = G_t(p + D_t(p))
// (p in the output frame's pixels at rest): D_t are expression displacements (Gaussian bumps:
// jaw and lower lip down, mouth corners out and up, brows up; small on the forehead, so the
// tags stay nearly rigid) and G_t a global affine (roll, scale, a horizontal squeeze standing
// in for yaw, translation). Each output pixel y samples the canvas at F_t^-1(y) (the affine
// inverted, then p + D_t(p) = z solved by Newton's method, at every other row and column, the
// pixels between interpolated, within 0.01 px) with INTER_LINEAR. Then
// the optional hand, lighting, first-frame motion blur and noise.
//
// Truth: every layout marker in layout order, at F_t of its painted position, exactly (a tag:
// its centre, plus its four corners in PhotoSceneResult::tag_corners). A dot is visible when
// its centre lies inside the frame and no part of it is under the hand; a tag when its four
// corners lie inside the frame and none of them (nor its centre) is under the hand.

#include <array>
#include <filesystem>
#include <functional>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "tracking/layout.hpp"
#include "tracking/tracked_frame.hpp"

namespace rostro::eval {

struct PhotoSceneOptions {
  std::filesystem::path photo;
  int face = 0;  // which face in the photo, largest first
  cv::Size size{1280, 720};
  double face_px = 300;  // the face's width (jaw, iBUG 1 to 17) in output pixels at rest
  double dot_px = 8;     // painted dot diameter, output pixels at rest
  // Each dot painted up to this many eye widths (about 30 mm) off its place, at random (seeded
  // by `seed`): the landmarks place the dots, and the tracker looks for them near landmarks
  // too; real dots are not where a landmark model would put them.
  double placement_jitter = 0.12;
  double fps = 25, seconds = 6;
  // "still"; "turns": roll +-8 degrees, a horizontal squeeze 0.85..1 (yaw-like), scale and
  // translation; "mouth": the jaw and lips opening at 2.5 Hz, mouth corners and brows moving;
  // "talk": both at once, the mouth at half the amplitude.
  std::string motion = "turns";
  // Horizontal motion blur of this length (pixels) on frame 0, fading to none by frame 5,
  // while the face moves horizontally by the same amount each frame.
  double first_blur_px = 0;
  // A late start: the face slides in from beyond the right edge over this long (seconds).
  double enter_seconds = 0;
  double brightness = 1;  // gain
  double gradient = 0;    // light falls off left to right by this share (0..1)
  double noise = 2;       // Gaussian noise sigma, grey levels
  bool hand = false;      // a skin-coloured hand passes across the lower face mid-take
  unsigned seed = 1;      // the noise
};

// The tag's corners (libapriltag's order: bottom-left, bottom-right, top-right, top-left).
struct TagCorners {
  std::string marker;
  std::array<cv::Point2d, 4> corners;
};

struct PhotoSceneResult {
  std::vector<tracking::TrackedFrame> truth;         // one per frame, every layout marker
  std::vector<std::vector<TagCorners>> tag_corners;  // per frame, per tag of the layout
  // Each layout marker's painted position in the output frame at rest (F = identity), in
  // layout order: a dot's centre, a tag's centre.
  std::vector<cv::Point2d> painted;
  cv::Rect2d face_box;  // the face the landmarks were fitted to, photo pixels
};

using PhotoFrameSink = std::function<void(const cv::Mat& bgr)>;

// Renders every frame into `sink` (8-bit BGR, options.size) and returns the truth. `progress`
// gets the number of frames done. Throws InputError for a photo that is missing or unreadable
// (naming it), a photo with no face or too few faces for `options.face`, an unknown motion or
// options out of range.
PhotoSceneResult render_photo_scene(const PhotoSceneOptions& options,
                                    const tracking::MarkerLayout& layout,
                                    const PhotoFrameSink& sink,
                                    const std::function<void(long)>& progress = {});

}  // namespace rostro::eval

#pragma once
// AprilTag detection through libapriltag: a thin owner of the C detector that takes OpenCV
// images and returns corners in libapriltag's order (counter-clockwise as seen in the image;
// on an upright tag: bottom-left, bottom-right, top-right, top-left).

#include <array>
#include <memory>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace rostro::tracking {

// Coordinates: a pixel's centre is at integer coordinates (OpenCV's convention, and that of
// the dot detector). libapriltag's own output has centres at +0.5; detect() subtracts this.
inline constexpr double kApriltagPixelOffset = 0.5;

struct AprilTagOptions {
  std::vector<std::string> families = {"tag36h11"};
  float decimation = 2.0f;  // quad detection on a decimated image: faster, coarser
  float blur_sigma = 0.0f;  // Gaussian blur before quad detection (helps noisy images)
  int threads = 1;
  bool refine_edges = true;  // snaps the corners to the image gradient (sub-pixel)
  int max_hamming = 1;       // bits corrected while decoding: more bits, more false positives
  int bits_corrected = 2;    // what the decoder tables are built for
};

struct TagDetection {
  std::string family;
  int id = 0;
  std::array<cv::Point2d, 4> corners;
  cv::Point2d center;
  int hamming = 0;
  double decision_margin = 0;
  std::string marker_id() const { return family + ":" + std::to_string(id); }
};

class AprilTagDetector {
 public:
  // Throws InputError for an unknown family name.
  explicit AprilTagDetector(AprilTagOptions options = {});
  ~AprilTagDetector();
  AprilTagDetector(const AprilTagDetector&) = delete;
  AprilTagDetector& operator=(const AprilTagDetector&) = delete;

  // `gray` is 8-bit, one or three channels. Only the region `roi` is searched (the whole
  // image when empty); corners come back in full-image pixels.
  std::vector<TagDetection> detect(const cv::Mat& image, cv::Rect roi = {});
  // Same, with a decimation of its own (small regions are searched at full resolution).
  std::vector<TagDetection> detect(const cv::Mat& image, cv::Rect roi, float decimation);

  const AprilTagOptions& options() const { return options_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  AprilTagOptions options_;
};

// The printed pattern of one tag, one pixel per bit cell (white border included), as 8-bit
// black and white: for drawing test scenes and printing markers. Throws InputError when the
// family is unknown or the id out of range.
cv::Mat apriltag_image(const std::string& family, int id);
// The black square's edge in bit cells and the full image's edge (with the white border),
// e.g. 8 and 10 for tag36h11.
int apriltag_black_width(const std::string& family);

}  // namespace rostro::tracking

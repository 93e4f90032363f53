// The three NASA Swarmathon photos in shared/fixtures/apriltag/: every expected tag36h11
// detection is found with its four corners within 1 px, in the listed order.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <regex>
#include <string>

#include "tracking/apriltag_detector.hpp"

namespace fs = std::filesystem;
using rostro::tracking::AprilTagDetector;
using rostro::tracking::AprilTagOptions;
using rostro::tracking::TagDetection;

namespace {

struct Expected {
  int id;
  std::array<cv::Point2d, 4> corners;
};

// Lines of "id, (x y), (x y), (x y), (x y)".
std::vector<Expected> read_expected(const fs::path& path) {
  std::ifstream in(path);
  std::vector<Expected> out;
  std::string line;
  const std::regex number(R"([-+]?[0-9]*\.?[0-9]+)");
  while (std::getline(in, line)) {
    std::vector<double> v;
    for (auto it = std::sregex_iterator(line.begin(), line.end(), number);
         it != std::sregex_iterator(); ++it)
      v.push_back(std::stod(it->str()));
    if (v.size() != 9) continue;
    Expected e;
    e.id = static_cast<int>(v[0]);
    for (int k = 0; k < 4; ++k) e.corners[k] = {v[1 + 2 * k], v[2 + 2 * k]};
    out.push_back(e);
  }
  return out;
}

// The listed corners are in libapriltag's own pixel convention (centres at +0.5); rostro
// reports them with centres at integers, so the offset is added back before comparing.
double max_corner_error(const Expected& e, const TagDetection& d) {
  const cv::Point2d offset(rostro::tracking::kApriltagPixelOffset,
                           rostro::tracking::kApriltagPixelOffset);
  double worst = 0;
  for (int k = 0; k < 4; ++k)
    worst = std::max(worst, cv::norm(e.corners[k] - (d.corners[k] + offset)));
  return worst;
}

fs::path fixture_dir() {
  return fs::path(ROSTRO_SHARED_DIR) / "fixtures" / "apriltag";
}

}  // namespace

class AprilTagFixture : public testing::TestWithParam<std::string> {};

TEST_P(AprilTagFixture, EveryExpectedTagWithinOnePixel) {
  fs::path image_path = fixture_dir() / (GetParam() + ".jpg");
  if (!fs::exists(image_path)) GTEST_SKIP() << "fixture absent: " << image_path;
  cv::Mat image = cv::imread(image_path.string(), cv::IMREAD_GRAYSCALE);
  ASSERT_FALSE(image.empty());
  auto expected = read_expected(fixture_dir() / (GetParam() + ".txt"));
  ASSERT_FALSE(expected.empty());

  AprilTagOptions options;
  options.decimation = 1;        // the tags are small in these photos (12 px and up)
  options.refine_edges = false;  // the listed corners are the unrefined quad fit's
  options.max_hamming = 2;
  AprilTagDetector detector(options);
  auto found = detector.detect(image);

  for (const Expected& e : expected) {
    double best = 1e9;
    for (const TagDetection& d : found)
      if (d.id == e.id) best = std::min(best, max_corner_error(e, d));
    EXPECT_LE(best, 1.0) << GetParam() << ": tag " << e.id << " at " << e.corners[0];
  }
}

INSTANTIATE_TEST_SUITE_P(Photos, AprilTagFixture,
                         testing::Values("33369213973_9d9bb4cc96_c", "34085369442_304b6bafd9_c",
                                         "34139872896_defdb2f8d9_c"));

// V4L2 error paths that need no camera: a missing node, a node that is not V4L2, and the
// enumeration helpers.
#include <gtest/gtest.h>

#include <fstream>

#include "capture/open_source.hpp"
#include "capture/v4l2_device.hpp"
#include "facecore/error.hpp"
#include "test_dir.hpp"

namespace rostro::capture {
namespace {

std::string open_error(const std::string& spec, const SourceOptions& options = {}) {
  try {
    open_frame_source(spec, options);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(V4l2Errors, MissingDeviceIsNamed) {
  const std::string message = open_error("/dev/video99");
  EXPECT_NE(message.find("/dev/video99"), std::string::npos) << message;
  EXPECT_NE(message.find("no such device"), std::string::npos) << message;
}

TEST(V4l2Errors, DevNullIsNotAV4l2Device) {
  V4l2DeviceInfo info;
  try {
    open_v4l2_capture_device("/dev/null", info);
    FAIL() << "/dev/null opened as a V4L2 device";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("/dev/null"), std::string::npos) << message;
    EXPECT_NE(message.find("not a V4L2 device"), std::string::npos) << message;
  }
  EXPECT_THROW(query_v4l2_device("/dev/null"), InputError);
  // Through the source spec too: anything under /dev is treated as a device.
  const std::string message = open_error("/dev/null");
  EXPECT_NE(message.find("not a V4L2 device"), std::string::npos) << message;
}

TEST(V4l2Errors, RegularFileIsNotAV4l2Device) {
  testing::TestDir dir;
  const auto path = (dir.path / "video0").string();
  std::ofstream(path) << "not a device";
  V4l2DeviceInfo info;
  EXPECT_THROW(open_v4l2_capture_device(path, info), InputError);
}

TEST(V4l2Enumeration, VideoNodesInNaturalOrder) {
  testing::TestDir dir;
  for (const char* name : {"video10", "video2", "video0", "videox", "vbi0", "video"}) {
    std::ofstream((dir.path / name).string()) << "";
  }
  const auto nodes = list_video_nodes(dir.path.string());
  ASSERT_EQ(nodes.size(), 3u);
  EXPECT_EQ(std::filesystem::path(nodes[0]).filename(), "video0");
  EXPECT_EQ(std::filesystem::path(nodes[1]).filename(), "video2");
  EXPECT_EQ(std::filesystem::path(nodes[2]).filename(), "video10");
  EXPECT_TRUE(list_video_nodes((dir.path / "absent").string()).empty());
}

TEST(V4l2Enumeration, StepwiseSizesSampleCommonSizes) {
  // A sensor offering 320..1920 x 240..1080 in steps of 16 x 8.
  const auto sizes = sample_stepwise_sizes(320, 1920, 16, 240, 1080, 8);
  const auto has = [&](int w, int h) {
    return std::find(sizes.begin(), sizes.end(), std::pair{w, h}) != sizes.end();
  };
  EXPECT_TRUE(has(640, 480));
  EXPECT_TRUE(has(1280, 720));
  EXPECT_TRUE(has(1920, 1080));   // also the largest
  EXPECT_FALSE(has(2560, 1440));  // beyond the range
  EXPECT_TRUE(has(320, 240));
  // 1000 wide would not fit a step of 16 from 320: (1000 - 320) % 16 != 0
  for (const auto& [w, h] : sizes) {
    EXPECT_EQ((w - 320) % 16, 0) << w;
    EXPECT_EQ((h - 240) % 8, 0) << h;
  }
  // A range with no common size still gives its largest size.
  const auto odd = sample_stepwise_sizes(100, 300, 2, 100, 200, 2);
  ASSERT_EQ(odd.size(), 1u);
  EXPECT_EQ(odd[0], std::pair(300, 200));
}

TEST(V4l2Enumeration, ListingNeverThrows) {
  // On a machine without cameras this is empty; with cameras each entry is a capture node.
  std::vector<std::string> problems;
  const auto devices = list_v4l2_devices(&problems);
  for (const auto& device : devices) EXPECT_FALSE(device.path.empty());
}

}  // namespace
}  // namespace rostro::capture

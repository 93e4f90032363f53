// Video files written by the test with cv::VideoWriter, read back through open_frame_source.
#include <gtest/gtest.h>

#include <fstream>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>
#include <random>

#include "capture/open_source.hpp"
#include "facecore/error.hpp"
#include "test_dir.hpp"

namespace rostro::capture {
namespace {

constexpr int kFrames = 24;
constexpr double kFps = 12.0;
const cv::Size kSize(96, 64);

// Frame i is a flat grey of level 8 i with a white square whose x position is i, so both
// order and content can be checked after lossy compression.
cv::Mat synthetic_frame(int i) {
  cv::Mat image(kSize, CV_8UC3, cv::Scalar::all(8 * i));
  cv::rectangle(image, cv::Rect(i, 20, 16, 16), cv::Scalar::all(255), cv::FILLED);
  return image;
}

std::string write_video(const std::filesystem::path& dir, const std::string& name,
                        const char* fourcc) {
  const std::string path = (dir / name).string();
  cv::VideoWriter writer(path, cv::CAP_FFMPEG,
                         cv::VideoWriter::fourcc(fourcc[0], fourcc[1], fourcc[2], fourcc[3]), kFps,
                         kSize);
  if (!writer.isOpened()) return {};
  for (int i = 0; i < kFrames; ++i) writer.write(synthetic_frame(i));
  writer.release();
  return path;
}

void check_read_back(const std::string& path) {
  auto source = open_frame_source(path);
  ASSERT_TRUE(source);
  EXPECT_EQ(source->frame_size(), kSize);
  EXPECT_NEAR(source->nominal_fps(), kFps, 0.01);
  EXPECT_EQ(source->frame_count(), kFrames);
  int count = 0;
  double last_time = -1;
  while (auto frame = source->next()) {
    EXPECT_EQ(frame->sequence, count);
    EXPECT_EQ(frame->image.size(), kSize);
    EXPECT_EQ(frame->image.type(), CV_8UC3);
    EXPECT_GT(frame->timestamp_s, last_time) << "frame " << count;
    // The container's times for a constant-rate file are i / fps.
    EXPECT_NEAR(frame->timestamp_s, count / kFps, 1e-3) << "frame " << count;
    // Content: the grey level of the background identifies the frame.
    const double background = cv::mean(frame->image(cv::Rect(60, 50, 30, 10)))[0];
    EXPECT_NEAR(background, 8 * count, 6) << "frame " << count;
    last_time = frame->timestamp_s;
    ++count;
  }
  EXPECT_EQ(count, kFrames);
  EXPECT_EQ(source->stats().delivered, kFrames);
  EXPECT_EQ(source->stats().dropped, 0);
  EXPECT_FALSE(source->next());  // stays at the end
}

TEST(VideoFileSource, MjpegAviReadsBackEveryFrame) {
  testing::TestDir dir;
  const auto path = write_video(dir.path, "take.avi", "MJPG");
  ASSERT_FALSE(path.empty()) << "cv::VideoWriter could not write MJPG/AVI";
  check_read_back(path);
}

TEST(VideoFileSource, Mpeg4Mp4ReadsBackEveryFrame) {
  testing::TestDir dir;
  const auto path = write_video(dir.path, "take.mp4", "mp4v");
  if (path.empty()) GTEST_SKIP() << "this OpenCV/FFmpeg build cannot write mp4v/MP4";
  check_read_back(path);
}

TEST(VideoFileSource, MissingFileIsNamed) {
  try {
    open_frame_source("/nonexistent/take.mp4");
    FAIL() << "a missing file opened";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/take.mp4"), std::string::npos) << e.what();
  }
}

TEST(VideoFileSource, CorruptFileIsNamed) {
  testing::TestDir dir;
  const auto path = (dir.path / "corrupt.mp4").string();
  {
    std::ofstream out(path, std::ios::binary);
    std::mt19937 random(7);
    for (int i = 0; i < 20000; ++i) out.put(static_cast<char>(random() & 0xff));
  }
  try {
    auto source = open_frame_source(path);
    // If FFmpeg somehow opened it, it must at least not yield a frame of garbage size.
    FAIL() << "random bytes opened as " << source->description();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("corrupt.mp4"), std::string::npos) << e.what();
  }
}

TEST(VideoFileSource, TruncatedFileIsNamed) {
  // A real MP4 cut to its first 200 bytes: the header is there, the index is not.
  testing::TestDir dir;
  const auto full = write_video(dir.path, "full.mp4", "mp4v");
  if (full.empty()) GTEST_SKIP() << "this OpenCV/FFmpeg build cannot write mp4v/MP4";
  const auto cut = (dir.path / "cut.mp4").string();
  {
    std::ifstream in(full, std::ios::binary);
    std::vector<char> head(200);
    in.read(head.data(), static_cast<std::streamsize>(head.size()));
    std::ofstream(cut, std::ios::binary).write(head.data(), in.gcount());
  }
  EXPECT_THROW(open_frame_source(cut), InputError);
}

}  // namespace
}  // namespace rostro::capture

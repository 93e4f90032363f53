// Video and PNG-folder output: the frame count survives the round trip through ffmpeg,
// audio is muxed in, and nothing is left behind when a write is abandoned.

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>
#include <string>

#include "facecore/error.hpp"
#include "output_test_support.hpp"
#include "render/contact_sheet.hpp"
#include "render/frame_sink.hpp"
#include "render/video_writer.hpp"

namespace rostro::render {
namespace {
namespace fs = std::filesystem;
using test::count_frames;
using test::TempDir;

cv::Mat numbered_frame(int index, cv::Size size) {
  cv::Mat frame(size, CV_8UC3, cv::Scalar(40, 40, 40));
  // A bright bar whose position encodes the frame index.
  cv::rectangle(frame, cv::Rect(4 * index % (size.width - 8), 0, 8, size.height),
                cv::Scalar(255, 255, 255), cv::FILLED);
  return frame;
}

// A second of 16-bit mono silence at 16 kHz.
void write_wav(const fs::path& path, int seconds) {
  const std::uint32_t rate = 16000;
  const std::uint32_t data_bytes = rate * 2 * static_cast<std::uint32_t>(seconds);
  std::ofstream out(path, std::ios::binary);
  auto u32 = [&](std::uint32_t v) { out.write(reinterpret_cast<const char*>(&v), 4); };
  auto u16 = [&](std::uint16_t v) { out.write(reinterpret_cast<const char*>(&v), 2); };
  out.write("RIFF", 4);
  u32(36 + data_bytes);
  out.write("WAVEfmt ", 8);
  u32(16);
  u16(1);
  u16(1);
  u32(rate);
  u32(rate * 2);
  u16(2);
  u16(16);
  out.write("data", 4);
  u32(data_bytes);
  const std::string zeros(data_bytes, '\0');
  out.write(zeros.data(), static_cast<std::streamsize>(zeros.size()));
}

VideoOptions at_fps(double fps, fs::path audio = {}) {
  VideoOptions options;
  options.fps = fps;
  options.audio = std::move(audio);
  return options;
}

bool ffmpeg_available() {
  return std::system("ffmpeg -version >/dev/null 2>&1") == 0;
}

TEST(VideoWriter, FrameCountSurvivesTheRoundTrip) {
  if (!ffmpeg_available()) GTEST_SKIP() << "ffmpeg is not installed";
  TempDir dir;
  const fs::path out = dir.path() / "clip.mp4";
  VideoWriter writer(out, at_fps(25.0));
  for (int i = 0; i < 37; ++i) writer.write(numbered_frame(i, {161, 121}));  // odd size
  EXPECT_FALSE(fs::exists(out)) << "the video appears only on finish()";
  writer.finish();
  ASSERT_TRUE(fs::exists(out));
  EXPECT_EQ(count_frames(out), 37);
  EXPECT_EQ(dir.entries(), 1u) << "no temporary or log file left behind";
  cv::VideoCapture capture(out.string());
  EXPECT_NEAR(capture.get(cv::CAP_PROP_FPS), 25.0, 0.01);
}

TEST(VideoWriter, MuxesAudio) {
  if (!ffmpeg_available()) GTEST_SKIP() << "ffmpeg is not installed";
  TempDir dir;
  const fs::path wav = dir.path() / "speech.wav";
  write_wav(wav, 1);
  const fs::path out = dir.path() / "talk.mp4";
  VideoWriter writer(out, at_fps(25.0, wav));
  for (int i = 0; i < 25; ++i) writer.write(numbered_frame(i, {64, 48}));
  writer.finish();
  EXPECT_EQ(count_frames(out), 25);
  // ffprobe lists an audio stream.
  const fs::path listing = dir.path() / "streams.txt";
  const std::string command = "ffprobe -v error -show_entries stream=codec_type -of csv=p=0 '" +
                              out.string() + "' > '" + listing.string() + "'";
  ASSERT_EQ(std::system(command.c_str()), 0);
  std::ifstream in(listing);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("audio"), std::string::npos) << text;
  EXPECT_NE(text.find("video"), std::string::npos) << text;
}

TEST(VideoWriter, AbandonedWriteLeavesNothing) {
  if (!ffmpeg_available()) GTEST_SKIP() << "ffmpeg is not installed";
  TempDir dir;
  const fs::path out = dir.path() / "never.mp4";
  {
    VideoWriter writer(out, at_fps(30.0));
    for (int i = 0; i < 5; ++i) writer.write(numbered_frame(i, {64, 48}));
    EXPECT_THROW(writer.write(numbered_frame(0, {32, 48})), std::invalid_argument);
  }
  EXPECT_FALSE(fs::exists(out));
  EXPECT_EQ(dir.entries(), 0u);
}

TEST(VideoWriter, RejectsMissingAudioAndEmptyVideos) {
  TempDir dir;
  EXPECT_THROW(VideoWriter(dir.path() / "a.mp4", at_fps(25.0, dir.path() / "no.wav")), InputError);
  EXPECT_THROW(VideoWriter(dir.path() / "missing-folder" / "a.mp4", at_fps(25.0)), InputError);
  EXPECT_THROW(VideoWriter(dir.path() / "a.mp4", at_fps(0.0)), InputError);
  VideoWriter empty(dir.path() / "empty.mp4", at_fps(25.0));
  EXPECT_THROW(empty.finish(), InputError);
  EXPECT_EQ(dir.entries(), 0u);
}

TEST(FrameFolderWriter, WritesNumberedPngsOnFinish) {
  TempDir dir;
  const fs::path folder = dir.path() / "frames";
  {
    FrameFolderWriter abandoned(folder);
    abandoned.write(numbered_frame(0, {32, 24}));
  }
  EXPECT_FALSE(fs::exists(folder));
  EXPECT_EQ(dir.entries(), 0u);

  FrameFolderWriter writer(folder);
  for (int i = 0; i < 3; ++i) writer.write(numbered_frame(i, {32, 24}));
  EXPECT_FALSE(fs::exists(folder));
  writer.finish();
  ASSERT_TRUE(fs::is_directory(folder));
  EXPECT_EQ(dir.entries(), 1u);
  const cv::Mat first = cv::imread((folder / "frame_000000.png").string());
  ASSERT_FALSE(first.empty());
  EXPECT_EQ(cv::norm(first, numbered_frame(0, {32, 24}), cv::NORM_INF), 0.0);  // lossless
  EXPECT_TRUE(fs::exists(folder / "frame_000002.png"));
  EXPECT_FALSE(fs::exists(folder / "frame_000003.png"));

  // A second run into the existing folder replaces its frames.
  FrameFolderWriter again(folder);
  again.write(numbered_frame(5, {32, 24}));
  again.finish();
  EXPECT_EQ(cv::norm(cv::imread((folder / "frame_000000.png").string()),
                     numbered_frame(5, {32, 24}), cv::NORM_INF),
            0.0);
}

TEST(ContactSheet, TilesImagesInAGrid) {
  std::vector<SheetTile> tiles;
  for (int i = 0; i < 5; ++i)
    tiles.push_back({numbered_frame(i, {40, 30}), std::string("tile ").append(std::to_string(i))});
  const cv::Mat sheet = contact_sheet(tiles, 3);
  EXPECT_GT(sheet.cols, 3 * 40);
  EXPECT_LT(sheet.cols, 3 * 60);
  EXPECT_GT(sheet.rows, 2 * 30);
  EXPECT_THROW(contact_sheet({}, 3), std::invalid_argument);
}

}  // namespace
}  // namespace rostro::render

// `rostro play` end to end: a fixture .fap becomes a video with one frame per FAP frame, a
// malformed .fap is rejected with one line and no output, and `rostro pose` rejects an
// unknown FAP. The library path (render_stream) is tested directly as well.

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>
#include <sstream>
#include <string>

#include "face_test_support.hpp"
#include "facecore/error.hpp"
#include "facecore/fap_io.hpp"
#include "output_test_support.hpp"
#include "render/expression_clip.hpp"
#include "render/fap_assignments.hpp"
#include "render/fap_stream_source.hpp"
#include "render/video_writer.hpp"

namespace rostro::render {
namespace {
namespace fs = std::filesystem;
using test::count_frames;
using test::TempDir;

const fs::path kFixtures = fs::path(ROSTRO_SHARED_DIR) / "fixtures" / "xface";
const fs::path kRostro = fs::path(ROSTRO_BINARY_DIR) / "rostro";

struct CommandResult {
  int exit_code;
  std::string err;
};

CommandResult run_rostro(const std::string& args, const fs::path& dir) {
  const fs::path err = dir / "stderr.txt";
  const std::string command = "'" + kRostro.string() + "' " + args + " 2>'" + err.string() + "'";
  const int status = std::system(command.c_str());
  std::ifstream in(err);
  std::stringstream text;
  text << in.rdbuf();
  fs::remove(err);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, text.str()};
}

void write_text(const fs::path& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
}

// Five frames of the first fixture with one value line cut short.
std::string malformed_fap() {
  std::string mask(68 * 2, ' ');
  for (int i = 0; i < 68; ++i) mask[static_cast<std::size_t>(2 * i)] = i == 2 ? '1' : '0';
  std::string text = "2.1 broken 25 3\n";
  text += mask + "\n0 100\n";
  text += mask + "\n1 200\n";
  text += mask + "\n2\n";  // the frame number and no value for FAP 3
  return text;
}

TEST(Play, RenderStreamWritesOneVideoFramePerFapFrame) {
  const fs::path fixture = kFixtures / "joy.fap";
  if (!fs::exists(fixture)) GTEST_SKIP() << "fixture " << fixture << " is absent";
  MAKE_FACE_RENDERER_OR_SKIP(face, 160, 120);
  TempDir dir;
  auto source = open_fap_source(fixture);
  const double fps = source->header().fps;
  const FapStream whole = read_fap_stream(fixture);
  VideoOptions options;
  options.fps = fps;
  VideoWriter writer(dir.path() / "joy.mp4", options);
  long progress_calls = 0;
  const long n =
      render_stream(*source, *face, CameraPose::front(), writer, [&](long) { ++progress_calls; });
  EXPECT_EQ(n, static_cast<long>(whole.frames.size()));
  EXPECT_EQ(progress_calls, n);
  EXPECT_EQ(count_frames(dir.path() / "joy.mp4"), static_cast<int>(whole.frames.size()));
}

TEST(Play, MalformedStreamLeavesNoVideo) {
  MAKE_FACE_RENDERER_OR_SKIP(face, 64, 48);
  TempDir dir;
  const fs::path bad = dir.path() / "bad.fap";
  write_text(bad, malformed_fap());
  const fs::path out = dir.path() / "out.mp4";
  {
    auto source = open_fap_source(bad);
    VideoWriter writer(out, VideoOptions{});
    EXPECT_THROW(render_stream(*source, *face, CameraPose::front(), writer), InputError);
  }
  EXPECT_FALSE(fs::exists(out));
  fs::remove(bad);
  EXPECT_TRUE(dir.empty());
}

TEST(Play, ExpressionClipRisesFromNeutral) {
  const FapStream clip = expression_clip(1, 63);
  ASSERT_GT(clip.frames.size(), 10u);
  EXPECT_EQ(clip.frames.front().expression.intensity1, 0);
  EXPECT_EQ(clip.frames.back().expression.intensity1, 63);
  for (std::size_t i = 1; i < clip.frames.size(); ++i) {
    EXPECT_GE(clip.frames[i].expression.intensity1, clip.frames[i - 1].expression.intensity1);
    EXPECT_TRUE(clip.frames[i].has(kExpressionFap));
  }
  EXPECT_THROW(expression_clip(7, 63), InputError);
  EXPECT_THROW(expression_clip(1, 64), InputError);
}

TEST(Play, PoseSpecParsesIdsAndNames) {
  const FapFrame frame = parse_fap_assignments("3=400, raise_l_cornerlip=150,14=-20.5");
  EXPECT_DOUBLE_EQ(frame.get(3), 400.0);
  EXPECT_DOUBLE_EQ(frame.get(14), -20.5);
  EXPECT_DOUBLE_EQ(frame.get(*find_fap("raise_l_cornerlip")), 150.0);
  EXPECT_EQ(frame.mask.count(), 3u);
  EXPECT_TRUE(parse_fap_assignments("").mask.none());
  for (const char* bad :
       {"99=1", "0=5", "open_mouth=3", "3", "3=", "3=abc", "3=1,3=2", "1=5", "2=5", "3=1e999"}) {
    EXPECT_THROW(parse_fap_assignments(bad), InputError) << bad;
  }
}

TEST(PlayCommand, WritesAVideoMatchingTheFixture) {
  const fs::path fixture = kFixtures / "anger.fap";
  if (!fs::exists(fixture)) GTEST_SKIP() << "fixture " << fixture << " is absent";
  if (!fs::exists(kRostro)) GTEST_SKIP() << kRostro << " is not built";
  MAKE_FACE_RENDERER_OR_SKIP(probe, 16, 16);
  TempDir dir;
  const fs::path out = dir.path() / "anger.mp4";
  const CommandResult run = run_rostro("play '" + fixture.string() + "' -o '" + out.string() +
                                           "' --width 160 --height 120 --camera three-quarter",
                                       dir.path());
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(count_frames(out), static_cast<int>(read_fap_stream(fixture).frames.size()));
}

TEST(PlayCommand, RejectsAMalformedFapWithOneLineAndNoOutput) {
  if (!fs::exists(kRostro)) GTEST_SKIP() << kRostro << " is not built";
  TempDir dir;
  const fs::path bad = dir.path() / "bad.fap";
  write_text(bad, malformed_fap());
  const fs::path out = dir.path() / "out.mp4";
  const fs::path frames = dir.path() / "frames";
  const CommandResult run =
      run_rostro("play '" + bad.string() + "' -o '" + out.string() + "' --frames '" +
                     frames.string() + "' --width 64 --height 48",
                 dir.path());
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
  EXPECT_NE(run.err.find("bad.fap"), std::string::npos) << run.err;
  EXPECT_FALSE(fs::exists(out));
  EXPECT_FALSE(fs::exists(frames));

  const CommandResult missing = run_rostro(
      "play '" + (dir.path() / "nope.fap").string() + "' -o '" + out.string() + "'", dir.path());
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_EQ(std::count(missing.err.begin(), missing.err.end(), '\n'), 1) << missing.err;
  fs::remove(bad);
  EXPECT_TRUE(dir.empty());
}

TEST(PoseCommand, RejectsAnUnknownFapAndWritesAnImageOtherwise) {
  if (!fs::exists(kRostro)) GTEST_SKIP() << kRostro << " is not built";
  TempDir dir;
  const fs::path png = dir.path() / "face.png";
  const CommandResult bad = run_rostro("pose 3=400,99=1 -o '" + png.string() + "'", dir.path());
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_NE(bad.err.find("99"), std::string::npos) << bad.err;
  EXPECT_EQ(std::count(bad.err.begin(), bad.err.end(), '\n'), 1) << bad.err;
  EXPECT_FALSE(fs::exists(png));

  MAKE_FACE_RENDERER_OR_SKIP(probe, 16, 16);
  const CommandResult good =
      run_rostro("pose 3=400,12=150 --width 96 --height 72 -o '" + png.string() + "'", dir.path());
  ASSERT_EQ(good.exit_code, 0) << good.err;
  const cv::Mat image = cv::imread(png.string());
  EXPECT_EQ(image.size(), cv::Size(96, 72));
}

}  // namespace
}  // namespace rostro::render

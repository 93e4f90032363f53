// The commands with a window, run for real on an X server without a screen (Xvfb): what is
// on screen (a screenshot), what the keys do (typed through xdotool), and the one line a
// window command prints when there is no display. Skips, naming the missing tools, when
// Xvfb, xdotool, xwd or ImageMagick's convert is not installed (scripts/install-deps.sh
// installs them).

#include <gtest/gtest.h>

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <regex>
#include <string>

#include "tests/support/x_display.hpp"

namespace rostro::test {
namespace {

namespace fs = std::filesystem;
using std::chrono::seconds;

const std::string kRostro = std::string(ROSTRO_BINARY_DIR) + "/rostro";
const std::string kLayout = std::string(ROSTRO_DATA_DIR) + "/layouts/default.json";
// The renderer's background (render/gl_mesh_drawer.hpp, Shading::background) in BGR; the
// synthetic clips are rendered on it too.
const cv::Vec3b kBackground(66, 56, 51);

fs::path scratch(const std::string& name) {
  auto dir = fs::temp_directory_path() / ("rostro-window-" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

// The share of pixels in `region` that are neither the renderer's background nor black (the
// bare X root window): what a camera image or a head puts there.
double drawn_share(const cv::Mat& region) {
  long drawn = 0;
  for (int y = 0; y < region.rows; ++y) {
    for (int x = 0; x < region.cols; ++x) {
      const cv::Vec3b p = region.at<cv::Vec3b>(y, x);
      int from_background = 0, brightness = 0;
      for (int c = 0; c < 3; ++c) {
        from_background = std::max(from_background, std::abs(p[c] - kBackground[c]));
        brightness = std::max(brightness, static_cast<int>(p[c]));
      }
      if (from_background > 24 && brightness > 24) ++drawn;
    }
  }
  return static_cast<double>(drawn) / std::max(1, region.rows * region.cols);
}

// The share of light pixels (text) in `region`.
double light_share(const cv::Mat& region) {
  cv::Mat grey;
  cv::extractChannel(region, grey, 1);
  return static_cast<double>(cv::countNonZero(grey > 180)) / std::max(1, region.rows * region.cols);
}

// "Geometry: 1120x548" from xdotool.
cv::Size window_size(const XDisplay& x, const std::string& window) {
  const std::string text = shell(x.env() + "xdotool getwindowgeometry " + window);
  std::smatch m;
  if (!std::regex_search(text, m, std::regex("Geometry: (\\d+)x(\\d+)"))) return {};
  return {std::stoi(m[1]), std::stoi(m[2])};
}

// A test on its own Xvfb display, x(); skipped, naming what is missing, without the tools.
class WindowOnXvfb : public ::testing::Test {
 protected:
  void SetUp() override {
    const std::string missing = XDisplay::missing_tools();
    if (!missing.empty())
      GTEST_SKIP() << "window tests need " << missing
                   << " (Debian: xvfb xdotool x11-apps imagemagick)";
    x_ = std::make_unique<XDisplay>();
    ASSERT_FALSE(x_->name().empty()) << "Xvfb did not start";
  }
  const XDisplay& x() const { return *x_; }

 private:
  std::unique_ptr<XDisplay> x_;
};

// A marker clip in `dir`: 1 s neutral (the calibration), then `motion_s` seconds of motion drawn
// from drive.fap, which is left beside it. Returns rostro's output if it failed, else "".
std::string make_clip(const fs::path& dir, int motion_s) {
  int code = 0;
  const std::string fap = (dir / "drive.fap").string();
  const std::string out = shell(kRostro + " fap generate --seconds " + std::to_string(motion_s) +
                                    " --fps 25 -o " + fap + " && " + kRostro + " synth -o " +
                                    (dir / "clip").string() + " --fap " + fap + " --neutral-lead 1",
                                &code);
  return code == 0 ? "" : out;
}

TEST_F(WindowOnXvfb, LiveShowsCameraAndHeadAndItsKeysDoWhatTheySay) {
  const XDisplay& x = this->x();
  const fs::path dir = scratch("live");
  ASSERT_EQ(make_clip(dir, 24), "");
  const fs::path clip = dir / "clip.mp4";
  const fs::path out = dir / "out.txt", err = dir / "err.txt";
  Background live("cd " + dir.string() + " && " + x.env() + kRostro + " live --camera " +
                      clip.string() + " --layout " + kLayout,
                  out, err);
  ASSERT_TRUE(wait_for_text(err, "calibrated the actor", seconds(60))) << read_text(err);
  const std::string window = x.find_window("rostro live", seconds(30));
  ASSERT_FALSE(window.empty()) << read_text(err);
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));  // a few tracked frames drawn

  // The view: camera image (left, scaled to the head's 480 rows) beside the head (a
  // 480x480 square on the right), the figures and the keys in the rows below.
  const fs::path png = dir / "live-window.png";
  ASSERT_TRUE(x.screenshot(png));
  const cv::Mat screen = cv::imread(png.string());
  const cv::Size size = window_size(x, window);
  ASSERT_GT(size.width, 480 + 100) << "window " << size.width << "x" << size.height;
  ASSERT_GT(size.height, 480 + 40);
  const cv::Rect camera(0, 0, size.width - 480, 480), head(size.width - 480, 0, 480, 480),
      text(0, 480, size.width, size.height - 480);
  EXPECT_GT(drawn_share(screen(camera)), 0.15) << png;
  EXPECT_GT(drawn_share(screen(head)), 0.15) << png;
  EXPECT_GT(light_share(screen(text)), 0.01) << png;
  // Outside the window the screen is still bare.
  EXPECT_LT(drawn_share(screen(cv::Rect(0, size.height + 10, 1280, 800 - size.height - 10))),
            0.001);

  x.key(window, "t");
  EXPECT_TRUE(wait_for_text(err, "tracking reset", seconds(30))) << read_text(err);
  x.key(window, "c");
  EXPECT_TRUE(wait_for_text(err, "calibrated the actor", seconds(30), 2)) << read_text(err);
  x.key(window, "r");
  EXPECT_TRUE(wait_for_text(err, "recording live-take.fap", seconds(30))) << read_text(err);
  std::this_thread::sleep_for(std::chrono::seconds(1));
  x.key(window, "r");
  EXPECT_TRUE(wait_for_text(err, "live-take.fap: ", seconds(30))) << read_text(err);
  x.key(window, "q");
  ASSERT_EQ(live.wait_for(seconds(30)), 0) << read_text(err);

  // Frames flowed, and Q ended the run before the clip did (25 s, 625 frames).
  const std::string summary = read_text(out);
  std::smatch m;
  ASSERT_TRUE(
      std::regex_search(summary, m,
                        std::regex("frames: (\\d+) captured, \\d+ for calibration, (\\d+) sent, "
                                   "(\\d+) rendered")))
      << summary;
  EXPECT_LT(std::stol(m[1]), 625) << summary;
  EXPECT_GT(std::stol(m[2]), 25) << summary;
  EXPECT_GT(std::stol(m[3]), 25) << summary;
  EXPECT_NE(summary.find("recorded live-take.fap"), std::string::npos) << summary;
  const std::string info = shell(kRostro + " fap info " + (dir / "live-take.fap").string());
  EXPECT_TRUE(std::regex_search(info, std::regex("frames +[1-9]"))) << info;
}

TEST_F(WindowOnXvfb, PlayShowsTheHeadOnTheAudioClockAndItsKeysWork) {
  const XDisplay& x = this->x();
  const fs::path dir = scratch("play");
  shell(kRostro + " fap generate --seconds 24 --fps 25 -o " + (dir / "drive.fap").string());
  // 10 s of a quiet tone: the audio clock the picture follows (SDL's dummy driver plays it
  // nowhere, at the pace of a sound card).
  const fs::path wav = dir / "tone.wav";
  {
    const std::uint32_t rate = 16000, count = 10 * rate, bytes = 2 * count;
    std::ofstream f(wav, std::ios::binary);
    auto u32 = [&](std::uint32_t v) { f.write(reinterpret_cast<const char*>(&v), 4); };
    auto u16 = [&](std::uint16_t v) { f.write(reinterpret_cast<const char*>(&v), 2); };
    f << "RIFF";
    u32(36 + bytes);
    f << "WAVEfmt ";
    u32(16), u16(1), u16(1), u32(rate), u32(2 * rate), u16(2), u16(16);
    f << "data";
    u32(bytes);
    for (std::uint32_t i = 0; i < count; ++i)
      u16(static_cast<std::uint16_t>(i % 40 < 20 ? 800 : -800));
  }
  const fs::path out = dir / "out.txt", err = dir / "err.txt";
  Background play(x.env() + "SDL_AUDIODRIVER=dummy " + kRostro + " play " +
                      (dir / "drive.fap").string() + " --window --audio " + wav.string(),
                  out, err);
  const std::string window = x.find_window("rostro play", seconds(60));
  ASSERT_FALSE(window.empty()) << read_text(err);
  const std::regex frame_number("frame (\\d+)/");
  const std::string playing = x.wait_for_title(
      window, [&](const std::string& t) { return std::regex_search(t, frame_number); },
      seconds(30));
  ASSERT_TRUE(std::regex_search(playing, frame_number)) << playing;
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  const fs::path png = dir / "play-window.png";
  ASSERT_TRUE(x.screenshot(png));
  const cv::Mat screen = cv::imread(png.string());
  const cv::Size size = window_size(x, window);
  ASSERT_EQ(size, cv::Size(640, 480));
  EXPECT_GT(drawn_share(screen(cv::Rect(0, 0, 640, 480))), 0.15) << png;
  EXPECT_NE(read_text(err).find("sound through dummy"), std::string::npos) << read_text(err);

  // Space pauses: the title says so, and its clock stands still.
  x.key(window, "space");
  const std::string title = x.wait_for_title(
      window, [](const std::string& t) { return t.find("(paused)") != std::string::npos; },
      seconds(10));
  EXPECT_NE(title.find("(paused)"), std::string::npos) << title;
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  EXPECT_EQ(x.title(window), title);
  // Right seeks 5 s on (from paused, the clock jumps by exactly that).
  x.key(window, "Right");
  const std::string seeked = x.wait_for_title(
      window, [&](const std::string& t) { return t != title; }, seconds(10));
  std::smatch before, after;
  ASSERT_TRUE(std::regex_search(title, before, frame_number)) << title;
  ASSERT_TRUE(std::regex_search(seeked, after, frame_number)) << seeked;
  EXPECT_NEAR(static_cast<double>(std::stol(after[1]) - std::stol(before[1])), 125, 1)
      << title << " / " << seeked;
  x.key(window, "q");
  ASSERT_EQ(play.wait_for(seconds(30)), 0) << read_text(err);
  EXPECT_NE(read_text(out).find("stopped by the user"), std::string::npos) << read_text(out);
}

// The share of pixels that changed by more than a little between two images of one size.
double changed_share(const cv::Mat& a, const cv::Mat& b) {
  cv::Mat diff, grey;
  cv::absdiff(a, b, diff);
  cv::extractChannel(diff, grey, 2);
  return static_cast<double>(cv::countNonZero(grey > 30)) / std::max(1, a.rows * a.cols);
}

TEST_F(WindowOnXvfb, EditNudgesAFapOnTheHeadAndSavesALibraryThatPoseRenders) {
  const XDisplay& x = this->x();
  const fs::path dir = scratch("edit");
  const fs::path data(ROSTRO_DATA_DIR);
  fs::copy_file(data / "expressions.json", dir / "expressions.json");
  fs::copy_file(data / "visemes.json", dir / "visemes.json");
  const std::string libraries = " --expressions " + (dir / "expressions.json").string() +
                                " --visemes " + (dir / "visemes.json").string();
  const fs::path out = dir / "out.txt", err = dir / "err.txt";
  Background edit(x.env() + kRostro + " edit --entry joy --select open_jaw" + libraries, out, err);
  const std::string window = x.find_window("rostro edit", seconds(60));
  ASSERT_FALSE(window.empty()) << read_text(err);
  // The sliders' panel is the left 460 pixels of the 1280x800 window, the head the rest.
  const cv::Rect head(460, 0, 820, 800);
  // Screenshots until `done` holds of one, for up to 20 s (software rendering on a loaded
  // machine draws a frame in well under a second, but not always within a fixed wait).
  auto screenshot_until = [&](const fs::path& png, auto done) {
    cv::Mat shot;
    const auto until = std::chrono::steady_clock::now() + seconds(20);
    do {
      std::this_thread::sleep_for(std::chrono::milliseconds(500));
      if (x.screenshot(png)) shot = cv::imread(png.string());
    } while ((shot.empty() || !done(shot)) && std::chrono::steady_clock::now() < until);
    return shot;
  };
  const cv::Mat before = screenshot_until(dir / "before.png", [&](const cv::Mat& shot) {
    return drawn_share(shot(head)) > 0.15 && light_share(shot(cv::Rect(0, 0, 460, 800))) > 0.01;
  });
  ASSERT_FALSE(before.empty());
  EXPECT_GT(drawn_share(before(head)), 0.15);
  EXPECT_GT(light_share(before(cv::Rect(0, 0, 460, 800))), 0.01);  // the sliders' text

  // PageUp x 15 opens the jaw by 15 x 20 MNS units: the mouth in the picture changes.
  x.key(window,
        "Prior Prior Prior Prior Prior Prior Prior Prior Prior Prior Prior Prior "
        "Prior Prior Prior");
  const cv::Mat after = screenshot_until(dir / "after.png", [&](const cv::Mat& shot) {
    return changed_share(before(head), shot(head)) > 0.002;
  });
  ASSERT_FALSE(after.empty());
  EXPECT_GT(changed_share(before(head), after(head)), 0.002) << dir;
  // The other sliders stay as they were (left of the scrollbar, whose grab shrinks once ImGui
  // has measured the panel's content, a frame or two after it first draws it).
  const cv::Rect other_sliders(0, 200, 440, 600);
  EXPECT_EQ(changed_share(before(other_sliders), after(other_sliders)), 0.0);

  x.key(window, "ctrl+s");
  EXPECT_TRUE(wait_for_text(out, "saved ", seconds(30))) << read_text(out) << read_text(err);
  x.key(window, "Escape");
  ASSERT_EQ(edit.wait_for(seconds(30)), 0) << read_text(err);

  // The saved library: rostro pose draws its joy with the jaw open wider than data/'s.
  int code = 0;
  shell(kRostro + " pose --expression joy" + libraries + " -o " + (dir / "edited.png").string(),
        &code);
  ASSERT_EQ(code, 0);
  shell(kRostro + " pose --expression joy -o " + (dir / "default.png").string(), &code);
  ASSERT_EQ(code, 0);
  EXPECT_GT(changed_share(cv::imread((dir / "edited.png").string()),
                          cv::imread((dir / "default.png").string())),
            0.002);
}

TEST(Window, WithoutADisplayEachWindowCommandSaysSoInOneLine) {
  const fs::path dir = scratch("no-display");
  ASSERT_EQ(make_clip(dir, 1), "");
  const fs::path clip = dir / "clip.mp4";
  const std::string no_display = "env -u DISPLAY -u WAYLAND_DISPLAY ";
  int code = 0;
  std::string text = shell(
      no_display + kRostro + " live --camera " + clip.string() + " --layout " + kLayout, &code);
  EXPECT_EQ(code, 1);
  EXPECT_NE(text.find("no display for the live window"), std::string::npos) << text;
  EXPECT_NE(text.find("use --headless"), std::string::npos) << text;
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 1) << text;
  text = shell(no_display + kRostro + " play " + (dir / "drive.fap").string() + " --window", &code);
  EXPECT_EQ(code, 1);
  EXPECT_NE(text.find("no display for the playback window"), std::string::npos) << text;
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 1) << text;
  text = shell(no_display + kRostro + " edit", &code);
  EXPECT_EQ(code, 1);
  EXPECT_NE(text.find("no display for the editor"), std::string::npos) << text;
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 1) << text;
}

}  // namespace
}  // namespace rostro::test

// The whole live path, headless, as CI runs it: a `rostro synth` clip (the default head with
// the default layout's dots, its jaw driven by a known FAP curve) played as the camera at
// its real frame rate, through tracking, calibration from the first second, the Ceres fit
// and the hierarchy, to a VMC receiver inside the test on loopback, a raw FAP UDP receiver
// and a .fap recording.

#include "live/pipeline.hpp"

#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <lo/lo.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <cmath>
#include <filesystem>
#include <map>
#include <string>
#include <thread>
#include <vector>

#include "eval/synth.hpp"
#include "facecore/error.hpp"
#include "facecore/expression_library.hpp"
#include "facecore/face_model.hpp"
#include "facecore/fap_io.hpp"
#include "mapping/hierarchy.hpp"
#include "render/render_error.hpp"
#include "render/video_writer.hpp"
#include "tracking/layout.hpp"

namespace rostro::live {
namespace {

constexpr double kFps = 25;
constexpr int kNeutralFrames = 30;  // more than the one calibration second
constexpr int kMotionFrames = 50;
constexpr int kTailFrames = 10;
constexpr double kPeakJaw = 350;  // open_jaw, MNS units: jawOpen 0.5 by data/live/arkit.json

double driving_jaw(long frame) {
  const long k = frame - kNeutralFrames;
  if (k < 0 || k >= kMotionFrames) return 0;
  const double s = std::sin(M_PI * static_cast<double>(k) / kMotionFrames);
  return kPeakJaw * s * s;
}

// One VMC bundle as the receiver saw it.
struct Bundle {
  int blend_values = 0;
  std::map<std::string, float> blend;
  bool head_bone = false;
  double time_s = -1;
};

struct VmcLog {
  std::vector<Bundle> bundles;
  Bundle current;
  int stray_blend_values = 0;
};

int on_vmc(const char* path, const char* types, lo_arg** argv, int argc, lo_message, void* user) {
  auto* log = static_cast<VmcLog*>(user);
  const std::string p(path);
  if (p == "/VMC/Ext/Blend/Val" && argc == 2 && types[0] == 's' && types[1] == 'f') {
    ++log->current.blend_values;
    log->current.blend[&argv[0]->s] = argv[1]->f;
  } else if (p == "/VMC/Ext/Bone/Pos" && argc == 8 && std::string(&argv[0]->s) == "Head") {
    log->current.head_bone = true;
  } else if (p == "/VMC/Ext/T" && argc == 1 && types[0] == 'f') {
    // The time closes the sender's bundle.
    log->current.time_s = argv[0]->f;
    log->bundles.push_back(std::move(log->current));
    log->current = {};
  }
  return 0;
}

class LivePipeline : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = std::filesystem::path(ROSTRO_BINARY_DIR) / "tests" / "live_pipeline";
    std::filesystem::create_directories(dir_);
    clip_ = dir_ / "jaw.mp4";
    FapStream drive;
    drive.header.fps = kFps;
    for (long i = 0; i < kNeutralFrames + kMotionFrames + kTailFrames; ++i) {
      FapFrame f;
      f.index = i;
      f.time_s = static_cast<double>(i) / kFps;
      f.set(3, driving_jaw(i));
      drive.frames.push_back(f);
    }
    drive.header.frame_count = static_cast<long>(drive.frames.size());
    try {
      const FaceModel model = load_default_face_model();
      const ExpressionLibrary library = ExpressionLibrary::load_default();
      const tracking::MarkerLayout layout = tracking::load_layout(tracking::default_layout_path());
      const auto painted = eval::place_markers(model, layout);
      eval::SynthOptions so;
      so.dot_diameter_mm = layout.dot_diameter_mm;
      so.dark_dots = layout.polarity == tracking::DotPolarity::Dark;
      render::VideoOptions vo;
      vo.fps = kFps;
      render::VideoWriter sink(clip_, vo);
      eval::synthesize(model, &library, painted, drive, so, sink);
    } catch (const render::RenderUnavailable& e) {
      skip_reason_ = std::string("no headless OpenGL to render the clip: ") + e.what();
    }
  }

  void SetUp() override {
    if (!skip_reason_.empty()) GTEST_SKIP() << skip_reason_;
  }

  static inline std::filesystem::path dir_;
  static inline std::filesystem::path clip_;
  static inline std::string skip_reason_;
};

TEST_F(LivePipeline, HeadlessClipSendsOneVmcSetPerFrameFollowingTheJaw) {
  // VMC receiver on loopback, any free port.
  VmcLog vmc_log;
  lo_server server = lo_server_new_with_proto(nullptr, LO_UDP, nullptr);
  ASSERT_NE(server, nullptr);
  lo_server_add_method(server, nullptr, nullptr, on_vmc, &vmc_log);
  // Raw FAP receiver: a plain UDP socket.
  const int fap_socket = socket(AF_INET, SOCK_DGRAM, 0);
  ASSERT_GE(fap_socket, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ASSERT_EQ(bind(fap_socket, reinterpret_cast<sockaddr*>(&address), sizeof address), 0);
  socklen_t length = sizeof address;
  getsockname(fap_socket, reinterpret_cast<sockaddr*>(&address), &length);
  timeval timeout{0, 20000};
  setsockopt(fap_socket, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);

  std::atomic<bool> done{false};
  std::vector<std::string> datagrams;
  std::thread receiver([&] {
    char buffer[65536];
    while (!done) {
      lo_server_recv_noblock(server, 5);
      const ssize_t n = recv(fap_socket, buffer, sizeof buffer, 0);
      if (n > 0) datagrams.emplace_back(buffer, static_cast<std::size_t>(n));
    }
    while (lo_server_recv_noblock(server, 50) > 0) {
    }
    ssize_t n = 0;
    while ((n = recv(fap_socket, buffer, sizeof buffer, 0)) > 0)
      datagrams.emplace_back(buffer, static_cast<std::size_t>(n));
  });

  PipelineOptions o;
  o.camera = clip_.string();
  o.layout = tracking::load_layout(tracking::default_layout_path());
  o.mapper.hierarchy = mapping::default_hierarchy();
  VmcOptions vmc;
  vmc.port = lo_server_get_port(server);
  o.vmc = vmc;
  o.fap_udp = UdpTarget{"127.0.0.1", ntohs(address.sin_port)};
  o.record = dir_ / "live.fap";
  std::filesystem::remove(o.record);
  o.log = [](const std::string&) {};
  PipelineReport report;
  std::string error;
  try {
    Pipeline pipeline(std::move(o));
    report = pipeline.run();
  } catch (const std::exception& e) {
    error = e.what();  // stop the receiver before failing, or its thread ends the process
  }
  done = true;
  receiver.join();
  lo_server_free(server);
  close(fap_socket);
  ASSERT_TRUE(error.empty()) << "the pipeline failed: " << error;

  ASSERT_FALSE(report.failure) << *report.failure;
  const long total = kNeutralFrames + kMotionFrames + kTailFrames;
  EXPECT_EQ(report.frames_captured, total);
  // Every captured frame is calibrated on, sent, or skipped by the newest-wins hand-off.
  EXPECT_EQ(report.frames_calibration + report.frames_output + report.skipped_processing, total);
  EXPECT_EQ(report.frames_calibration, static_cast<long>(kFps));  // the first second
  ASSERT_GT(report.frames_output, total / 2);

  // One complete set per frame sent: 52 blend shapes, the head bone and the time.
  ASSERT_EQ(static_cast<long>(vmc_log.bundles.size()), report.frames_output);
  ASSERT_EQ(static_cast<long>(datagrams.size()), report.frames_output);
  for (const auto& b : vmc_log.bundles) {
    EXPECT_EQ(b.blend_values, 52);
    EXPECT_EQ(b.blend.size(), 52u);
    EXPECT_TRUE(b.head_bone);
  }

  // jawOpen follows the driving curve: near zero at rest, rising to about half at the peak.
  std::vector<double> sent, driven;
  double rest_max = 0, peak = 0;
  for (const auto& b : vmc_log.bundles) {
    const long frame = std::lround(b.time_s * kFps);
    const double jaw = b.blend.at("jawOpen");
    sent.push_back(jaw);
    driven.push_back(driving_jaw(frame) / 700.0);
    if (driving_jaw(frame) == 0) rest_max = std::max(rest_max, jaw);
    if (driving_jaw(frame) > 0.9 * kPeakJaw) peak = std::max(peak, jaw);
  }
  EXPECT_LT(rest_max, 0.08);
  EXPECT_GT(peak, 0.35);
  EXPECT_LT(peak, 0.65);
  double mean_s = 0, mean_d = 0;
  for (std::size_t i = 0; i < sent.size(); ++i) {
    mean_s += sent[i] / static_cast<double>(sent.size());
    mean_d += driven[i] / static_cast<double>(sent.size());
  }
  double sd = 0, ss = 0, dd = 0;
  for (std::size_t i = 0; i < sent.size(); ++i) {
    sd += (sent[i] - mean_s) * (driven[i] - mean_d);
    ss += (sent[i] - mean_s) * (sent[i] - mean_s);
    dd += (driven[i] - mean_d) * (driven[i] - mean_d);
  }
  EXPECT_GT(sd / std::sqrt(ss * dd), 0.9) << "jawOpen does not follow the driving open_jaw";

  // The raw FAP datagrams are .fap text after the tag line.
  EXPECT_EQ(datagrams.front().rfind("rostro-fap 25", 0), 0u) << datagrams.front();

  // The recording holds every frame from the end of calibration at the clip's rate
  // (frames skipped by the hand-off are filled), and its open_jaw follows the drive too.
  ASSERT_EQ(report.recordings.size(), 1u);
  const FapStream recorded = read_fap_stream(report.recordings.front());
  EXPECT_DOUBLE_EQ(recorded.header.fps, kFps);
  EXPECT_GE(static_cast<long>(recorded.frames.size()), report.frames_output);
  EXPECT_LE(static_cast<long>(recorded.frames.size()), total - static_cast<long>(kFps));
  double recorded_peak = 0;
  for (const auto& f : recorded.frames) recorded_peak = std::max(recorded_peak, f.get(3));
  EXPECT_GT(recorded_peak, 0.7 * kPeakJaw);
  EXPECT_LT(recorded_peak, 1.3 * kPeakJaw);

  EXPECT_EQ(report.stats.delay.count(), static_cast<std::size_t>(report.frames_output));
  EXPECT_EQ(report.stats.capture.count(), static_cast<std::size_t>(total));
}

TEST(ParseHostPort, AcceptsHostPortAndRejectsTheRest) {
  EXPECT_EQ(parse_host_port("10.0.0.2:39539", "--vmc").host, "10.0.0.2");
  EXPECT_EQ(parse_host_port("10.0.0.2:39539", "--vmc").port, 39539);
  EXPECT_EQ(parse_host_port(":9000", "--fap-udp").host, "127.0.0.1");
  EXPECT_THROW(parse_host_port("localhost", "--vmc"), InputError);
  EXPECT_THROW(parse_host_port("localhost:0", "--vmc"), InputError);
  EXPECT_THROW(parse_host_port("localhost:12ab", "--vmc"), InputError);
}

}  // namespace
}  // namespace rostro::live

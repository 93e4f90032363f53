// The live path end to end, as `rostro live --headless` runs it: a rendered clip of the
// default head (range of motion, default layout's dots) played at its real 25 fps through
// capture (decoding), tracking, the Ceres fit + hierarchy, the VMC and raw FAP outputs (to
// loopback ports nobody listens on: sending costs the same), and the offscreen head render.
// Reported as counters: p50/p99 per stage and of the capture-to-output delay, in ms.
#include <arpa/inet.h>
#include <benchmark/benchmark.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <filesystem>
#include <map>

#include "eval/synth.hpp"
#include "facecore/expression_library.hpp"
#include "facecore/face_model.hpp"
#include "live/pipeline.hpp"
#include "mapping/hierarchy.hpp"
#include "render/video_writer.hpp"
#include "tracking/layout.hpp"

namespace {

using namespace rostro;

constexpr double kSeconds = 4.0;

// A loopback UDP port that takes datagrams and never reads them (the kernel drops what
// overflows), so sending costs what it costs with a real receiver.
struct SilentReceiver {
  int fd = socket(AF_INET, SOCK_DGRAM, 0);
  int port = 0;
  SilentReceiver() {
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a);
    socklen_t n = sizeof a;
    getsockname(fd, reinterpret_cast<sockaddr*>(&a), &n);
    port = ntohs(a.sin_port);
  }
  ~SilentReceiver() { close(fd); }
};

// One clip per size, rendered once.
std::filesystem::path clip(int width, int height) {
  static std::map<std::pair<int, int>, std::filesystem::path> made;
  auto& path = made[{width, height}];
  if (!path.empty()) return path;
  path = std::filesystem::temp_directory_path() /
         ("rostro_bench_live_" + std::to_string(width) + "x" + std::to_string(height) + ".mp4");
  FapStream drive = eval::range_of_motion(25);
  drive.frames.resize(static_cast<std::size_t>(kSeconds * 25));
  const FaceModel model = load_default_face_model();
  const ExpressionLibrary library = ExpressionLibrary::load_default();
  const tracking::MarkerLayout layout = tracking::load_layout(tracking::default_layout_path());
  eval::SynthOptions so;
  so.width = width;
  so.height = height;
  so.dot_diameter_mm = layout.dot_diameter_mm;
  so.dark_dots = layout.polarity == tracking::DotPolarity::Dark;
  so.yaw_deg = 10;
  so.pitch_deg = 5;
  render::VideoOptions vo;
  vo.fps = 25;
  render::VideoWriter sink(path, vo);
  eval::synthesize(model, &library, eval::place_markers(model, layout), drive, so, sink);
  return path;
}

void BM_LivePath(benchmark::State& state) {
  const int width = static_cast<int>(state.range(0));
  const int height = static_cast<int>(state.range(1));
  const auto video = clip(width, height);
  SilentReceiver vmc_port, fap_port;
  live::PipelineReport report;
  for (auto _ : state) {
    live::PipelineOptions o;
    o.camera = video.string();
    o.layout = tracking::load_layout(tracking::default_layout_path());
    o.mapper.hierarchy = mapping::default_hierarchy();
    o.vmc = live::VmcOptions{"127.0.0.1", vmc_port.port};
    o.fap_udp = live::UdpTarget{"127.0.0.1", fap_port.port};
    o.render_head = true;
    o.log = [](const std::string&) {};
    live::Pipeline pipeline(std::move(o));
    report = pipeline.run();
  }
  const auto& s = report.stats;
  const std::pair<const char*, const live::LatencyStats*> stages[] = {
      {"capture", &s.capture},    {"tracking", &s.tracking}, {"fit", &s.fit},
      {"deform", &s.deformation}, {"render", &s.render},     {"processing", &s.processing},
      {"delay", &s.delay}};
  for (const auto& [name, stat] : stages) {
    state.counters[std::string(name) + "_p50_ms"] = stat->quantile(0.5);
    state.counters[std::string(name) + "_p99_ms"] = stat->quantile(0.99);
  }
  state.counters["frames_sent"] = static_cast<double>(report.frames_output);
  state.counters["skipped"] = static_cast<double>(report.skipped_processing);
  state.SetLabel(report.failure ? *report.failure : report.source);
}

}  // namespace

BENCHMARK(BM_LivePath)
    ->Args({640, 480})
    ->Args({1280, 720})
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_MAIN();

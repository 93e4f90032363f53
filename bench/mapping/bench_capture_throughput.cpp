// rostro capture's per-frame work without decoding: a 1280x720 take rendered by synth is held
// in memory, then every frame goes through tracking and the FAP mapping (Ceres fit +
// hierarchy), as `rostro capture` does after calibrating from the first second. Reported as
// frames per second (aim: 400 or more).

#include <benchmark/benchmark.h>

#include <opencv2/core.hpp>
#include <vector>

#include "calib/actor_prior.hpp"
#include "eval/synth.hpp"
#include "facecore/expression_library.hpp"
#include "facecore/face_model.hpp"
#include "mapping/fap_mapper.hpp"
#include "mapping/hierarchy.hpp"
#include "render/frame_sink.hpp"
#include "tracking/layout.hpp"
#include "tracking/marker_tracker.hpp"

namespace {

using namespace rostro;

class MemorySink : public render::FrameSink {
 public:
  void write(const cv::Mat& bgr) override { frames.push_back(bgr.clone()); }
  void finish() override {}
  long frames_written() const override { return static_cast<long>(frames.size()); }
  std::vector<cv::Mat> frames;
};

struct Take {
  std::vector<cv::Mat> frames;
  calib::ActorProfile profile;
  tracking::MarkerLayout layout;
};

constexpr int kCalibrationFrames = 25;

const Take& take() {
  static const Take t = [] {
    Take out;
    out.layout = tracking::load_layout(tracking::default_layout_path());
    const FaceModel model = load_default_face_model();
    const ExpressionLibrary library = ExpressionLibrary::load_default();
    FapStream drive = eval::range_of_motion(25);
    drive.frames.resize(100);
    eval::prepend_neutral(drive, 1.0);
    eval::SynthOptions so;
    so.width = 1280;
    so.height = 720;
    so.dot_diameter_mm = out.layout.dot_diameter_mm;
    so.dark_dots = out.layout.polarity == tracking::DotPolarity::Dark;
    MemorySink sink;
    const eval::SynthResult r =
        eval::synthesize(model, &library, eval::place_markers(model, out.layout), drive, so, sink);
    out.frames = std::move(sink.frames);
    tracking::MarkerTracker tracker(out.layout);
    std::vector<tracking::TrackedFrame> neutral;
    for (int i = 0; i < kCalibrationFrames; ++i)
      neutral.push_back(tracker.track(out.frames[static_cast<std::size_t>(i)], i, i / 25.0));
    const calib::ActorPrior prior = calib::load_actor_prior();
    out.profile = calib::calibrate_actor(
        neutral, r.intrinsics, calib::actor_calibration_options(out.layout, prior, "bench"));
    return out;
  }();
  return t;
}

void BM_CaptureTrackAndFit1280x720(benchmark::State& state) {
  const Take& t = take();
  mapping::MapperOptions options;
  options.hierarchy = mapping::default_hierarchy();
  long frames = 0;
  for (auto _ : state) {
    tracking::MarkerTracker tracker(t.layout);
    auto mapper = mapping::make_fap_mapper(t.profile, options);
    for (std::size_t i = 0; i < t.frames.size(); ++i) {
      const auto tracked = tracker.track(t.frames[i], static_cast<long>(i), static_cast<double>(i) / 25.0);
      if (i < kCalibrationFrames) continue;  // rostro capture maps these too, after calibrating
      benchmark::DoNotOptimize(mapper->map(tracked));
      ++frames;
    }
  }
  state.SetItemsProcessed(frames);
  state.counters["fps"] =
      benchmark::Counter(static_cast<double>(frames), benchmark::Counter::kIsRate);
}

BENCHMARK(BM_CaptureTrackAndFit1280x720)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(3);

}  // namespace

BENCHMARK_MAIN();

// Tracking cost per frame at 1280x720 with the default layout (31 dots, 3 AprilTags), frames
// decoded beforehand so only tracking is timed; beside it, the AprilTag detector run on
// every whole frame, which is what re-detection in small windows avoids.

#include <benchmark/benchmark.h>

#include <filesystem>
#include <map>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>
#include <string>

#include "tests/support/synthetic_scene.hpp"
#include "tracking/apriltag_detector.hpp"
#include "tracking/layout.hpp"
#include "tracking/marker_tracker.hpp"

namespace {

using namespace rostro::tracking;

const MarkerLayout& layout() {
  static MarkerLayout l =
      load_layout(std::filesystem::path(ROSTRO_DATA_DIR) / "layouts" / "default.json");
  return l;
}

const std::vector<cv::Mat>& frames() {
  static std::vector<cv::Mat> f = [] {
    cv::setNumThreads(1);  // one core: the figure the issue asks for
    testing::SceneOptions o;
    o.size = {1280, 720};
    o.px_per_mm = 3.6;  // a face about 500 px tall
    o.dot_diameter_px = 10;
    testing::SyntheticScene scene(layout(), o);
    std::vector<cv::Mat> out;
    std::map<std::string, testing::Truth> truth;
    for (int k = 0; k < 60; ++k) out.push_back(scene.render(k, truth));
    return out;
  }();
  return f;
}

TrackerOptions options() {
  TrackerOptions o;
  o.dots.min_diameter_px = 5;
  o.dots.max_diameter_px = 20;
  o.identification.face_model.clear();  // the tests' scene is a skin texture, not a face
  return o;
}

// MarkerTracker::track on an already-identified take: LK, snapping, tag windows, checks.
void BM_TrackFrame(benchmark::State& state) {
  const auto& f = frames();
  MarkerTracker tracker(layout(), options());
  tracker.track(f[0], 0, 0);
  if (!tracker.started()) {
    state.SkipWithError("the markers were not identified on the first frame");
    return;
  }
  // The identification's second look (TrackerOptions::second_look_after) is part of the start.
  size_t k = 1;
  for (; k <= static_cast<size_t>(options().second_look_after) && k + 1 < f.size(); ++k)
    tracker.track(f[k], static_cast<long>(k), 0);
  long valid = 0, seen = 0;
  std::map<std::string, double> step_ms;  // each named step's time, summed
  for (auto _ : state) {
    TrackedFrame t = tracker.track(f[k], static_cast<long>(k), 0);
    for (const auto& m : t.markers) valid += m.valid, ++seen;
    for (const StepTime& s : tracker.step_times()) step_ms[s.step] += s.ms;
    if (++k == f.size()) k = 1;
  }
  state.counters["valid_fraction"] =
      seen ? static_cast<double>(valid) / static_cast<double>(seen) : 0;
  // Milliseconds a frame in each step (the steps' sum is below the whole: grey conversion,
  // region bookkeeping and the result's assembly are in no step).
  for (const auto& [step, ms] : step_ms)
    state.counters[step + "_ms"] = benchmark::Counter(ms, benchmark::Counter::kAvgIterations);
}
BENCHMARK(BM_TrackFrame)->Unit(benchmark::kMillisecond);

// The floor: the image pyramid and LK on 31 points, nothing else.
void BM_PyramidAndLk31(benchmark::State& state) {
  const auto& f = frames();
  std::vector<cv::Point2f> points;
  for (int i = 0; i < 31; ++i) points.emplace_back(400 + 15 * i, 300 + (i % 5) * 20);
  std::vector<cv::Mat> previous, current;
  cv::buildOpticalFlowPyramid(f[0], previous, {13, 13}, 2);
  size_t k = 1;
  std::vector<cv::Point2f> out;
  std::vector<uchar> status;
  std::vector<float> err;
  for (auto _ : state) {
    cv::buildOpticalFlowPyramid(f[k], current, {13, 13}, 2);
    cv::calcOpticalFlowPyrLK(previous, current, points, out, status, err, {13, 13}, 2);
    std::swap(previous, current);
    if (++k == f.size()) k = 1;
  }
}
BENCHMARK(BM_PyramidAndLk31)->Unit(benchmark::kMillisecond);

// The AprilTag detector over the whole frame, as if tags were re-detected everywhere.
void BM_AprilTagWholeFrame(benchmark::State& state) {
  AprilTagOptions o;
  o.decimation = static_cast<float>(state.range(0));
  AprilTagDetector detector(o);
  const auto& f = frames();
  size_t k = 0;
  long found = 0, runs = 0;
  for (auto _ : state) {
    found += static_cast<long>(detector.detect(f[k]).size());
    ++runs;
    if (++k == f.size()) k = 0;
  }
  state.counters["tags_found"] = runs ? static_cast<double>(found) / static_cast<double>(runs) : 0;
}
BENCHMARK(BM_AprilTagWholeFrame)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();

// Bare-face tracking cost per frame on one core: the default head rendered bare (the range of
// motion, sensor noise 2) at 640x480 and 1280x720, frames rendered beforehand so only tracking
// is timed. LandmarkTracker::track is the whole step (find the face again near where it was,
// fit the 68 landmarks, steady them); beside it the landmark fit alone, the whole-image face
// search that finding a face (first frame, after a loss) costs, and the detector's look again
// near a followed face that every tenth frame costs.

#include <benchmark/benchmark.h>

#include <map>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>

#include "eval/synth.hpp"
#include "facecore/face_model.hpp"
#include "tracking/landmark_tracker.hpp"

namespace {

using namespace rostro;

struct BareClip {
  std::vector<cv::Mat> frames;
  FeaturePointPositions neutral;
};

const BareClip& clip(int width, int height) {
  static std::map<int, BareClip> clips;
  auto [at, made] = clips.try_emplace(width);
  if (made) {
    cv::setNumThreads(1);  // one core: the figure the issue asks for
    const FaceModel model = load_default_face_model();
    const tracking::MarkerLayout layout = tracking::landmark_layout(
        tracking::default_ibug_mapping(), model.feature_point_positions());
    FapStream drive = eval::range_of_motion(25);
    drive.frames.resize(100);
    eval::SynthOptions o;
    o.width = width;
    o.height = height;
    o.noise_sigma = 2;
    render::MemoryFrameSink sink;
    eval::synthesize(model, nullptr, eval::place_markers(model, layout), drive, o, sink);
    at->second.frames = std::move(sink.frames);
    at->second.neutral = model.feature_point_positions();
  }
  return at->second;
}

void BM_LandmarkTrackFrame(benchmark::State& state) {
  const BareClip& c = clip(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
  tracking::LandmarkTracker tracker(tracking::default_ibug_mapping(), c.neutral);
  tracker.track(c.frames[0], 0, 0);
  std::size_t k = 1;
  for (auto _ : state) {
    const tracking::TrackedFrame t =
        tracker.track(c.frames[k], static_cast<long>(k), static_cast<double>(k) / 25);
    benchmark::DoNotOptimize(t.markers.data());
    k = k + 1 < c.frames.size() ? k + 1 : 1;
  }
  state.counters["searches"] = static_cast<double>(tracker.searches());
}
BENCHMARK(BM_LandmarkTrackFrame)
    ->Args({640, 480})
    ->Args({1280, 720})
    ->Unit(benchmark::kMillisecond);

// The clip's first frame in grey and the face the detector finds on it; nullopt (the benchmark
// skipped, saying why) when there is none.
std::optional<cv::Rect2d> first_face(benchmark::State& state, tracking::LandmarkModel& model,
                                     cv::Mat& gray) {
  const BareClip& c = clip(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
  cv::cvtColor(c.frames[0], gray, cv::COLOR_BGR2GRAY);
  const auto faces = model.detect(gray, {0, 0, gray.cols, gray.rows}, 100, 0);
  if (faces.empty()) {
    state.SkipWithError("no face on the first frame");
    return std::nullopt;
  }
  return faces[0].box;
}

void BM_LandmarkFit(benchmark::State& state) {
  tracking::LandmarkModel model(tracking::default_landmark_model());
  cv::Mat gray;
  const auto face = first_face(state, model, gray);
  if (!face) return;
  for (auto _ : state) benchmark::DoNotOptimize(model.fit(gray, *face).data());
}
BENCHMARK(BM_LandmarkFit)->Args({640, 480})->Args({1280, 720})->Unit(benchmark::kMillisecond);

// The whole-image search for faces at least 100 px wide (LandmarkTrackerOptions::min_face_px).
void BM_FaceSearch(benchmark::State& state) {
  const BareClip& c = clip(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
  tracking::LandmarkModel model(tracking::default_landmark_model());
  cv::Mat gray;
  cv::cvtColor(c.frames[0], gray, cv::COLOR_BGR2GRAY);
  for (auto _ : state)
    benchmark::DoNotOptimize(model.detect(gray, {0, 0, gray.cols, gray.rows}, 100, 0).data());
}
BENCHMARK(BM_FaceSearch)->Args({640, 480})->Args({1280, 720})->Unit(benchmark::kMillisecond);

// The detector's look again around a followed face (LandmarkTrackerOptions::look_window, the
// third argument in tenths: 15 the default, 20 the window the tracker used before), as
// LandmarkTracker makes it every check_every frames: the face at 0.8 of its size fills the
// detector's smallest window.
void BM_FaceLookAgain(benchmark::State& state) {
  tracking::LandmarkModel model(tracking::default_landmark_model());
  cv::Mat gray;
  const auto found = first_face(state, model, gray);
  if (!found) return;
  const cv::Rect2d& face = *found;
  const double k = static_cast<double>(state.range(2)) / 10;
  const cv::Rect window =
      cv::Rect(cv::Point(static_cast<int>(face.x - face.width * (k - 1) / 2),
                         static_cast<int>(face.y - face.height * (k - 1) / 2)),
               cv::Size(static_cast<int>(face.width * k), static_cast<int>(face.height * k))) &
      cv::Rect(0, 0, gray.cols, gray.rows);
  for (auto _ : state)
    benchmark::DoNotOptimize(model.detect(gray, window, 0.8 * face.width, -0.5).data());
}
BENCHMARK(BM_FaceLookAgain)
    ->Args({640, 480, 15})
    ->Args({640, 480, 20})
    ->Args({1280, 720, 15})
    ->Args({1280, 720, 20})
    ->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();

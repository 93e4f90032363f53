// rostro capture's per-frame work without decoding: a 1280x720 take rendered by synth is held
// in memory, then every frame goes through tracking and the FAP mapping (Ceres fit +
// hierarchy), as `rostro capture` does after calibrating from the first second. Reported as
// frames per second (aim: 400 or more), wall and CPU, with tracking's and the fit's shares.
// BM_CaptureTrackAndFit1280x720 is one core, the work one step after the other;
// BM_CaptureTwoCores1280x720 is `rostro capture` on two cores, with the same tracks and FAPs:
// OpenCV's pool at 2 threads (LK's own parallel loop), the dots measured on two threads
// (TrackerOptions::threads) and the fit pipelined on a worker thread. Arguments: OpenCV
// threads, tracker threads, pipelined (0/1); {2, 2, 1} is `rostro capture`, the others
// attribute the gain.

#include <benchmark/benchmark.h>

#include <cstdlib>
#include <ctime>
#include <opencv2/core.hpp>
#include <opencv2/core/utility.hpp>
#include <vector>

#include "bench/mapping/capture_take.hpp"
#include "calib/actor_prior.hpp"
#include "mapping/fap_mapper.hpp"
#include "mapping/hierarchy.hpp"
#include "mapping/pipelined_take_mapper.hpp"
#include "tracking/layout.hpp"
#include "tracking/marker_tracker.hpp"

namespace {

using namespace rostro;

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
    // ROSTRO_CAPTURE_TAKE: capture_profile's CACHE file, read instead of rendering the take.
    const char* cache = std::getenv("ROSTRO_CAPTURE_TAKE");
    bench::RenderedTake r = cache ? bench::cached_capture_take(cache, out.layout)
                                  : bench::render_capture_take(out.layout);
    out.frames = std::move(r.frames);
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

double clock_ms(clockid_t clock) {
  timespec t{};
  clock_gettime(clock, &t);
  return 1e3 * static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_nsec);
}
double thread_cpu_ms() {
  return clock_ms(CLOCK_THREAD_CPUTIME_ID);
}

// One iteration is one frame of a take in progress: the tracker and the mapper carry on from
// frame to frame as in `rostro capture`, identification and calibration (once per take) done
// beforehand. The clip is played forwards and backwards in turn, so the motion stays
// continuous however many frames the benchmark asks for. CPU time of tracking and of the
// mapping is counted apart.
void BM_CaptureTrackAndFit1280x720(benchmark::State& state) {
  cv::setNumThreads(1);  // one core: the figure the issue asks for
  const Take& t = take();
  mapping::MapperOptions options;
  options.hierarchy = mapping::default_hierarchy();
  tracking::MarkerTracker tracker(t.layout);
  auto mapper = mapping::make_fap_mapper(t.profile, options);
  const long first = kCalibrationFrames, last = static_cast<long>(t.frames.size()) - 1;
  for (long i = 0; i < first; ++i)
    tracker.track(t.frames[static_cast<std::size_t>(i)], i, static_cast<double>(i) / 25.0);
  long i = first, step = 1, count = first;
  double track_ms = 0, map_ms = 0;
  for (auto _ : state) {
    const double t0 = thread_cpu_ms();
    const auto tracked = tracker.track(t.frames[static_cast<std::size_t>(i)], count,
                                       static_cast<double>(count) / 25.0);
    const double t1 = thread_cpu_ms();
    benchmark::DoNotOptimize(mapper->map(tracked));
    const double t2 = thread_cpu_ms();
    track_ms += t1 - t0, map_ms += t2 - t1;
    ++count;
    if (i + step < first || i + step > last) step = -step;
    i += step;
  }
  const auto n = static_cast<double>(state.iterations());
  state.counters["track_cpu_ms"] = track_ms / n;
  state.counters["map_cpu_ms"] = map_ms / n;
  state.counters["cpu_fps"] = 1e3 * n / (track_ms + map_ms);
  state.counters["fps"] = benchmark::Counter(1, benchmark::Counter::kIsIterationInvariantRate);
}

BENCHMARK(BM_CaptureTrackAndFit1280x720)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(3);

// The same take on two cores. The fit of a frame finishes after its iteration (one frame or a
// few behind), so wall and CPU time are taken over the whole run including finish(), which
// maps the frames still queued: `fps` and `cpu_ms` (every thread of the process per frame).
// `main_cpu_ms` is the calling thread's share: the work left on the frame-to-frame path,
// which a busy machine (whose other core is not free) does not hide as it hides wall time.
void BM_CaptureTwoCores1280x720(benchmark::State& state) {
  cv::setNumThreads(static_cast<int>(state.range(0)));
  const int tracker_threads = static_cast<int>(state.range(1));
  const bool pipelined = state.range(2) != 0;
  const Take& t = take();
  mapping::MapperOptions options;
  options.hierarchy = mapping::default_hierarchy();
  tracking::TrackerOptions tracker_options;
  tracker_options.threads = tracker_threads;
  tracking::MarkerTracker tracker(t.layout, tracker_options);
  auto mapper = mapping::make_fap_mapper(t.profile, options);
  mapping::PipelinedTakeMapper pipeline(t.layout, options, t.profile.camera, t.profile,
                                        kCalibrationFrames);
  const long first = kCalibrationFrames, last = static_cast<long>(t.frames.size()) - 1;
  for (long i = 0; i < first; ++i)
    tracker.track(t.frames[static_cast<std::size_t>(i)], i, static_cast<double>(i) / 25.0);
  long i = first, step = 1, count = first, mapped = 0;
  const double wall0 = clock_ms(CLOCK_MONOTONIC), cpu0 = clock_ms(CLOCK_PROCESS_CPUTIME_ID),
               main0 = thread_cpu_ms();
  for (auto _ : state) {
    auto tracked = tracker.track(t.frames[static_cast<std::size_t>(i)], count,
                                 static_cast<double>(count) / 25.0);
    if (pipelined)
      mapped += static_cast<long>(pipeline.push(std::move(tracked)).size());
    else
      benchmark::DoNotOptimize(mapper->map(tracked)), ++mapped;
    ++count;
    if (i + step < first || i + step > last) step = -step;
    i += step;
  }
  mapped += static_cast<long>(pipeline.finish().size());
  const double wall = clock_ms(CLOCK_MONOTONIC) - wall0,
               cpu = clock_ms(CLOCK_PROCESS_CPUTIME_ID) - cpu0, main = thread_cpu_ms() - main0;
  if (mapped != static_cast<long>(state.iterations())) state.SkipWithError("frames lost");
  const auto n = static_cast<double>(state.iterations());
  state.counters["fps"] = 1e3 * n / wall;
  state.counters["cpu_ms"] = cpu / n;
  state.counters["main_cpu_ms"] = main / n;
  cv::setNumThreads(1);
}

BENCHMARK(BM_CaptureTwoCores1280x720)
    ->Args({2, 2, 1})
    ->Args({2, 1, 1})
    ->Args({1, 1, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MinTime(3);

}  // namespace

BENCHMARK_MAIN();

// bench_capture_throughput's one-core and two-core capture side by side, in short alternating
// blocks, for a host whose speed drifts by the minute (other work on the machine):
//
//   capture_ab CACHE [ROUNDS [BLOCK [OPENCV_THREADS TRACKER_THREADS PIPELINED]]]
//
// CACHE is capture_profile's take file (rendered there when missing). Each round runs BLOCK
// frames (default 100) one core, the work one step after the other (cv::setNumThreads(1),
// one tracker thread, the fit after each frame), then BLOCK frames two cores (by default
// OpenCV's pool at 2, two tracker threads, the fit pipelined on a worker thread; the last
// three arguments choose otherwise), each with its own tracker and mapper carrying on from
// block to block (the pipeline's last frame or two of a block are fitted during the next
// one-core block, as many as it carries into the next block: a steady state). Printed: each
// round's wall frames per second for both and their ratio, then the medians. The ratio of a
// round compares two blocks a fraction of a second apart, so the host's drift mostly cancels.
// Each round also prints the CPU the rest of the machine used meanwhile (from /proc/stat, in
// cores): two cores can only gain when nothing else holds the second one, so the medians are
// also given over the rounds where the others used under a tenth of a core.

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <opencv2/core.hpp>
#include <opencv2/core/utility.hpp>
#include <string>
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
constexpr long kCalibrationFrames = 25;

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : v[v.size() / 2];
}

// One capture carrying on through the take (played forwards and backwards), as the benchmark.
struct Capture {
  const std::vector<cv::Mat>& frames;
  tracking::MarkerTracker tracker;
  long i = kCalibrationFrames, step = 1, count = kCalibrationFrames;
  Capture(const std::vector<cv::Mat>& f, const tracking::MarkerLayout& layout, int threads)
      : frames(f), tracker(layout, options(threads)) {
    for (long k = 0; k < kCalibrationFrames; ++k)
      tracker.track(frames[static_cast<size_t>(k)], k, static_cast<double>(k) / 25.0);
  }
  static tracking::TrackerOptions options(int threads) {
    tracking::TrackerOptions o;
    o.threads = threads;
    return o;
  }
  tracking::TrackedFrame next() {
    auto out =
        tracker.track(frames[static_cast<size_t>(i)], count, static_cast<double>(count) / 25.0);
    ++count;
    const long last = static_cast<long>(frames.size()) - 1;
    if (i + step < kCalibrationFrames || i + step > last) step = -step;
    i += step;
    return out;
  }
};

// CPU seconds the whole machine has spent busy (every core), from /proc/stat.
double machine_busy_s() {
  std::ifstream stat("/proc/stat");
  std::string cpu;
  long long user = 0, nice = 0, system = 0, idle = 0, iowait = 0, irq = 0, softirq = 0, steal = 0;
  stat >> cpu >> user >> nice >> system >> idle >> iowait >> irq >> softirq >> steal;
  return static_cast<double>(user + nice + system + irq + softirq + steal) / 100.0;  // USER_HZ
}
double process_cpu_s() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: capture_ab CACHE [ROUNDS [BLOCK]]\n");
    return 2;
  }
  const int rounds = argc > 2 ? std::stoi(argv[2]) : 20;
  const long block = argc > 3 ? std::stol(argv[3]) : 100;
  const int opencv_threads = argc > 4 ? std::stoi(argv[4]) : 2;
  const int tracker_threads = argc > 5 ? std::stoi(argv[5]) : 2;
  const bool pipelined = argc > 6 ? std::stoi(argv[6]) != 0 : true;
  const tracking::MarkerLayout layout = tracking::load_layout(tracking::default_layout_path());
  const bench::RenderedTake take = bench::cached_capture_take(argv[1], layout);

  cv::setNumThreads(1);
  tracking::MarkerTracker calibration_tracker(layout);
  std::vector<tracking::TrackedFrame> neutral;
  for (long k = 0; k < kCalibrationFrames; ++k)
    neutral.push_back(calibration_tracker.track(take.frames[static_cast<size_t>(k)], k,
                                                static_cast<double>(k) / 25.0));
  const calib::ActorProfile profile = calib::calibrate_actor(
      neutral, take.intrinsics,
      calib::actor_calibration_options(layout, calib::load_actor_prior(), "bench"));
  mapping::MapperOptions options;
  options.hierarchy = mapping::default_hierarchy();

  Capture one(take.frames, layout, 1), two(take.frames, layout, tracker_threads);
  auto mapper = mapping::make_fap_mapper(profile, options);
  auto mapper_two = mapping::make_fap_mapper(profile, options);
  mapping::PipelinedTakeMapper pipeline(layout, options, profile.camera, profile,
                                        kCalibrationFrames);
  long pushed = 0, mapped = 0;
  std::vector<double> one_fps, two_fps, ratio, quiet_one, quiet_two, quiet_ratio;
  for (int r = 0; r < rounds; ++r) {
    const double busy0 = machine_busy_s(), own0 = process_cpu_s();
    const auto round0 = std::chrono::steady_clock::now();
    cv::setNumThreads(1);
    auto t0 = std::chrono::steady_clock::now();
    for (long n = 0; n < block; ++n) mapper->map(one.next());
    const double a = static_cast<double>(block) / seconds_since(t0);

    cv::setNumThreads(opencv_threads);
    t0 = std::chrono::steady_clock::now();
    for (long n = 0; n < block; ++n, ++pushed)
      if (pipelined)
        mapped += static_cast<long>(pipeline.push(two.next()).size());
      else
        mapper_two->map(two.next()), ++mapped;
    const double b = static_cast<double>(block) / seconds_since(t0);
    one_fps.push_back(a), two_fps.push_back(b), ratio.push_back(b / a);
    const double others = std::max(0.0, (machine_busy_s() - busy0) - (process_cpu_s() - own0)) /
                          seconds_since(round0);
    if (others < 0.1) quiet_one.push_back(a), quiet_two.push_back(b), quiet_ratio.push_back(b / a);
    std::printf(
        "round %2d  one core %6.1f fps  two cores %6.1f fps  ratio %.2f  others %.2f cores\n",
        r + 1, a, b, b / a, others);
  }
  mapped += static_cast<long>(pipeline.finish().size());
  if (mapped != pushed) std::fprintf(stderr, "frames lost: %ld of %ld\n", pushed - mapped, pushed);
  std::printf("two cores: OpenCV threads %d, tracker threads %d, %s\n", opencv_threads,
              tracker_threads, pipelined ? "fit pipelined" : "fit after each frame");
  std::printf("median    one core %6.1f fps  two cores %6.1f fps  ratio %.2f\n", median(one_fps),
              median(two_fps), median(ratio));
  std::printf("quiet     one core %6.1f fps  two cores %6.1f fps  ratio %.2f  (%zu rounds)\n",
              median(quiet_one), median(quiet_two), median(quiet_ratio), quiet_ratio.size());
  return 0;
}

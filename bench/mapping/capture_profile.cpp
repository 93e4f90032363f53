// A deterministic view of bench_capture_throughput's per-frame work, for profilers and for
// checking that a speed change leaves the tracks alone.
//
//   capture_profile CACHE [FRAMES [THREADS]]
//   capture_profile --video CLIP.mp4
//
// The first run renders the benchmark's take (1280x720, range of motion after one neutral
// second, the same as bench_capture_throughput) and keeps it in CACHE (raw BGR frames and the
// camera intrinsics), so later runs, under valgrind too, skip llvmpipe. Each run then
// calibrates from the first second and tracks and maps FRAMES frames (default 200) played
// forwards and backwards, as the benchmark does. Only that loop is collected under
// `valgrind --tool=callgrind --collect-atstart=no`, so the instruction counts are the loop's.
// It prints a hash of every tracked position, validity and quality and of every FAP value:
// equal hashes before and after a change mean bit-identical tracks and FAPs. THREADS 2 runs
// the two-core capture instead (the dots measured on 2 threads, the fit pipelined on a worker
// thread, as `rostro capture` does): its hashes must equal the one-thread run's. With --video it
// tracks every frame of a clip (as `rostro track` does, default options) and prints the
// tracks' hash only.

#include <valgrind/callgrind.h>

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <opencv2/core.hpp>
#include <opencv2/core/utility.hpp>
#include <opencv2/videoio.hpp>
#include <optional>
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

constexpr int kCalibrationFrames = 25;

struct Hash {
  uint64_t h = 1469598103934665603ull;  // FNV-1a
  void add(const void* p, size_t n) {
    const auto* b = static_cast<const unsigned char*>(p);
    for (size_t i = 0; i < n; ++i) h = (h ^ b[i]) * 1099511628211ull;
  }
  template <typename T>
  void add(const T& v) {
    add(&v, sizeof v);
  }
};

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::cerr << "usage: capture_profile CACHE [FRAMES [THREADS]]\n";
    return 2;
  }
  const int threads = argc > 3 ? std::stoi(argv[3]) : 1;
  cv::setNumThreads(threads);
  if (std::string(argv[1]) == "--video" && argc > 2) {
    cv::VideoCapture video(argv[2]);
    tracking::MarkerTracker tracker(tracking::load_layout(tracking::default_layout_path()));
    Hash hash;
    long n = 0, valid = 0;
    for (cv::Mat frame; video.read(frame); ++n)
      for (const auto& m : tracker.track(frame, n, static_cast<double>(n) / 25.0).markers) {
        hash.add(m.valid);
        if (m.valid) hash.add(m.position.x), hash.add(m.position.y), ++valid;
        hash.add(m.quality);
      }
    std::printf("%s: frames %ld  valid markers %ld  track hash %016llx\n", argv[2], n, valid,
                static_cast<unsigned long long>(hash.h));
    return 0;
  }
  const std::filesystem::path cache = argv[1];
  const long frames = argc > 2 ? std::stol(argv[2]) : 200;
  const tracking::MarkerLayout layout = tracking::load_layout(tracking::default_layout_path());
  const bench::RenderedTake t = bench::cached_capture_take(cache, layout);
  if (t.frames.size() <= kCalibrationFrames) throw std::runtime_error("take too short");

  tracking::MarkerTracker calibration_tracker(layout);
  std::vector<tracking::TrackedFrame> neutral;
  for (int i = 0; i < kCalibrationFrames; ++i)
    neutral.push_back(calibration_tracker.track(t.frames[static_cast<size_t>(i)], i, i / 25.0));
  const calib::ActorProfile profile = calib::calibrate_actor(
      neutral, t.intrinsics,
      calib::actor_calibration_options(layout, calib::load_actor_prior(), "bench"));

  mapping::MapperOptions options;
  options.hierarchy = mapping::default_hierarchy();
  tracking::TrackerOptions tracker_options;
  tracker_options.threads = threads;
  tracking::MarkerTracker tracker(layout, tracker_options);
  // One thread: the fit after each frame's tracking; more: on a worker, one frame behind.
  auto mapper = mapping::make_fap_mapper(profile, options);
  std::optional<mapping::PipelinedTakeMapper> pipeline;
  if (threads > 1) pipeline.emplace(layout, options, profile.camera, profile, kCalibrationFrames);
  const long first = kCalibrationFrames, last = static_cast<long>(t.frames.size()) - 1;
  for (long i = 0; i < first; ++i)
    tracker.track(t.frames[static_cast<size_t>(i)], i, static_cast<double>(i) / 25.0);
  Hash track_hash, fap_hash;
  std::vector<long> valid_count(layout.markers.size(), 0);
  long i = first, step = 1, count = first, valid = 0;
  CALLGRIND_TOGGLE_COLLECT;
  for (long n = 0; n < frames; ++n) {
    const auto tracked =
        tracker.track(t.frames[static_cast<size_t>(i)], count, static_cast<double>(count) / 25.0);
    if (pipeline)
      for (const FapFrame& fap : pipeline->push(tracked)) fap_hash.add(fap.values);
    else
      fap_hash.add(mapper->map(tracked).values);
    for (size_t k = 0; k < tracked.markers.size(); ++k) {
      const auto& m = tracked.markers[k];
      valid_count[k] += m.valid;
      track_hash.add(m.valid);
      if (m.valid) track_hash.add(m.position.x), track_hash.add(m.position.y), ++valid;
      track_hash.add(m.quality);
    }
    ++count;
    if (i + step < first || i + step > last) step = -step;
    i += step;
  }
  if (pipeline)
    for (const FapFrame& fap : pipeline->finish()) fap_hash.add(fap.values);
  CALLGRIND_TOGGLE_COLLECT;
  std::printf("frames %ld  valid markers %ld  track hash %016llx  fap hash %016llx\n", frames,
              valid, static_cast<unsigned long long>(track_hash.h),
              static_cast<unsigned long long>(fap_hash.h));
  for (size_t k = 0; k < valid_count.size(); ++k)
    if (valid_count[k] < frames)
      std::printf("  %s valid in %ld of %ld frames\n", layout.markers[k].id.c_str(), valid_count[k],
                  frames);
  return 0;
}

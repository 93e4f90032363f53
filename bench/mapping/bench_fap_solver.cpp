// Per-frame cost of the mapping methods on a synthetic take: 34 markers (the default
// layout), a moving head (yaw +-25, pitch +-15 degrees) and a changing expression, 0.2 px
// noise, warm-started frame after frame as in `rostro capture`.
#include <benchmark/benchmark.h>
#include <time.h>

#include <algorithm>
#include <chrono>
#include <numeric>

#include "mapping/fap_solver.hpp"
#include "mapping/hierarchy.hpp"
#include "mapping/seed2d_mapper.hpp"
#include "tests/support/synthetic_face.hpp"

namespace {

using namespace rostro;

struct Take {
  test::SyntheticActor actor = test::make_actor();
  tracking::HeadPose neutral = test::head_pose(0, 0, 0);
  std::vector<tracking::TrackedFrame> frames;
  calib::ActorProfile profile;
  // The same actor calibrated with default intrinsics 35 % short of the camera's focal length:
  // the fit then also refines the focal length every frame.
  calib::ActorProfile default_camera_profile;

  Take() {
    std::mt19937 rng(42);
    std::vector<tracking::TrackedFrame> still;
    for (int i = 0; i < 15; ++i) still.push_back(test::render(actor, {}, neutral, 0.2, rng, i));
    profile = calib::calibrate_actor(still, actor.camera, test::calibration_options());
    calib::CameraIntrinsics guess = calib::default_intrinsics(actor.camera.image_size);
    guess.fx = guess.fy = 650;
    default_camera_profile = calib::calibrate_actor(still, guess, test::calibration_options());
    for (int i = 0; i < 250; ++i) {
      const double t = i / 250.0;
      const auto faps = test::test_expression(std::sin(2 * M_PI * 3 * t));
      const auto pose = test::head_pose(25 * std::sin(2 * M_PI * t), 15 * std::sin(4 * M_PI * t),
                                        2 * std::sin(6 * M_PI * t));
      frames.push_back(test::render(actor, faps, pose, 0.2, rng, i));
    }
  }
};

// CPU time of the calling thread, microseconds: the figure that does not depend on what
// else runs on the machine (other builds share its two cores).
double thread_cpu_us() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) * 1e6 + static_cast<double>(t.tv_nsec) / 1e3;
}

void report(benchmark::State& state, std::vector<double> us, const std::string& prefix) {
  std::sort(us.begin(), us.end());
  state.counters[prefix + "median_us"] = us[us.size() / 2];
  state.counters[prefix + "mean_us"] =
      std::accumulate(us.begin(), us.end(), 0.0) / static_cast<double>(us.size());
  state.counters[prefix + "p95_us"] = us[us.size() * 95 / 100];
  state.counters[prefix + "max_us"] = us.back();
}

const Take& take() {
  static const Take t;
  return t;
}

void BM_CeresFitWarmStarted(benchmark::State& state) {
  const Take& t = take();
  mapping::FapSolver solver(state.range(0) ? t.default_camera_profile : t.profile);
  std::vector<double> us, cpu;
  std::size_t i = 0;
  long iterations = 0;
  for (auto _ : state) {
    const auto start = std::chrono::steady_clock::now();
    const double cpu_start = thread_cpu_us();
    auto r = solver.fit(t.frames[i]);
    cpu.push_back(thread_cpu_us() - cpu_start);
    us.push_back(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start)
                     .count());
    iterations += r.iterations;
    benchmark::DoNotOptimize(r);
    i = (i + 1) % t.frames.size();
    if (i == 0) solver.reset();
  }
  report(state, us, "wall_");
  report(state, cpu, "cpu_");
  state.counters["lm_iterations"] =
      static_cast<double>(iterations) / static_cast<double>(state.iterations());
}
// Argument 0: calibrated camera; 1: default intrinsics, focal length refined as it goes.
BENCHMARK(BM_CeresFitWarmStarted)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

void BM_Seed2d(benchmark::State& state) {
  const Take& t = take();
  const mapping::Seed2dMapper mapper(t.profile);
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(mapper.map(t.frames[i]));
    i = (i + 1) % t.frames.size();
  }
}
BENCHMARK(BM_Seed2d)->Unit(benchmark::kMicrosecond);

void BM_Hierarchy(benchmark::State& state) {
  const Take& t = take();
  const auto hierarchy =
      mapping::read_hierarchy(std::filesystem::path(ROSTRO_DATA_DIR) / "hierarchy.json");
  mapping::FapSolver solver(t.profile);
  const FapFrame fitted = solver.fit(t.frames[10]).faps;
  for (auto _ : state) {
    FapFrame f = fitted;
    benchmark::DoNotOptimize(mapping::apply_hierarchy(hierarchy, t.profile.fapu, f));
  }
}
BENCHMARK(BM_Hierarchy)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();

// Reading and writing a one-hour, 60 fps .fap file with every FAP set (216,000 frames),
// through the streaming source and sink. Reports throughput and the peak resident memory,
// which must not grow with the file.

#include <benchmark/benchmark.h>
#include <sys/resource.h>

#include <filesystem>
#include <vector>

#include "facecore/fap_io.hpp"
#include "facecore/fap_summary.hpp"

namespace {

constexpr long kFrames = 60L * 60 * 60;
constexpr double kFps = 60;

std::filesystem::path bench_file() {
  return std::filesystem::temp_directory_path() / "rostro-bench-hour.fap";
}

double peak_rss_mb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;
}

// Frames are generated once and cycled, so the benchmark times the writer, not sin().
const std::vector<rostro::FapFrame>& frame_cycle() {
  static const std::vector<rostro::FapFrame> cycle = [] {
    std::array<bool, rostro::kFapCount> all{};
    all.fill(true);
    std::vector<rostro::FapFrame> frames;
    for (long i = 0; i < 600; ++i) frames.push_back(rostro::synthetic_fap_frame(i, kFps, all, 7));
    return frames;
  }();
  return cycle;
}

void BM_WriteOneHour60fps(benchmark::State& state) {
  const auto& cycle = frame_cycle();
  for (auto _ : state) {
    rostro::FapHeader header;
    header.fps = kFps;
    auto sink = rostro::open_fap_sink(bench_file(), header);
    rostro::FapFrame frame;
    for (long i = 0; i < kFrames; ++i) {
      frame = cycle[static_cast<std::size_t>(i % 600)];
      frame.index = i;
      sink->write(frame);
    }
    sink->finish();
  }
  const auto bytes = static_cast<int64_t>(std::filesystem::file_size(bench_file()));
  state.SetBytesProcessed(bytes * state.iterations());
  state.counters["file_MB"] = static_cast<double>(bytes) / 1e6;
  state.counters["peak_rss_MB"] = peak_rss_mb();
}

void BM_ReadOneHour60fps(benchmark::State& state) {
  long frames = 0;
  for (auto _ : state) {
    auto source = rostro::open_fap_source(bench_file());
    rostro::FapFrame frame;
    frames = 0;
    while (source->next(frame)) ++frames;
    benchmark::DoNotOptimize(frame);
  }
  if (frames != kFrames) state.SkipWithError("read a different number of frames than written");
  const auto bytes = static_cast<int64_t>(std::filesystem::file_size(bench_file()));
  state.SetBytesProcessed(bytes * state.iterations());
  state.counters["peak_rss_MB"] = peak_rss_mb();
}

// Write first: the read benchmark reads the file it leaves.
BENCHMARK(BM_WriteOneHour60fps)->Unit(benchmark::kMillisecond)->Iterations(2)->UseRealTime();
BENCHMARK(BM_ReadOneHour60fps)->Unit(benchmark::kMillisecond)->Iterations(2)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();

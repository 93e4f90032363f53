// Deformation time per frame with every low-level FAP moving (translations, eyeball and head
// rotations), for the default head and a 200,000-vertex head, on one thread and on two
// (BM_Deform/<vertices>/<threads>; the deformer's own default is every core from 50,000
// vertices). Pin to one core for the one-thread figure, to two for the two-thread one; the
// time that counts for two threads is real time, not CPU time. BM_DeformHeadStill keeps the
// head's turn (FAPs 48-50) from frame to frame and deforms into a kept DeformedMesh, as
// `play`, `live` and rendering do: the vertices only the turn moves are not placed again.

#include <benchmark/benchmark.h>

#include <map>
#include <memory>

#include "facecore/deformer.hpp"
#include "facecore/head_generator.hpp"

namespace {

struct Setup {
  rostro::FaceModel model;
  std::unique_ptr<rostro::Deformer> deformer;  // set_threads per benchmark
};

const Setup& setup(int vertices) {
  static std::map<int, std::unique_ptr<Setup>> cache;
  auto& s = cache[vertices];
  if (!s) {
    s = std::make_unique<Setup>();
    s->model = rostro::generate_head(rostro::HeadOptions{vertices});
    s->deformer = std::make_unique<rostro::Deformer>(s->model);
  }
  return *s;
}

// Every FAP 3..68 set and changing from frame to frame; with `head_still`, 48-50 stay.
rostro::FapFrame moving_frame(long frame, bool head_still) {
  rostro::FapFrame f;
  for (int id = 3; id <= rostro::kFapCount; ++id) {
    const bool turn = id >= 48 && id <= 50;
    f.set(id, 100.0 + static_cast<double>(((head_still && turn ? 0 : frame) * 7 + id * 13) % 50));
  }
  return f;
}

void BM_Deform(benchmark::State& state) {
  const Setup& s = setup(static_cast<int>(state.range(0)));
  s.deformer->set_threads(static_cast<int>(state.range(1)));
  std::vector<Eigen::Vector3f> positions;
  long frame = 0;
  for (auto _ : state) {
    s.deformer->deform(moving_frame(frame, false), positions);
    benchmark::DoNotOptimize(positions.data());
    ++frame;
  }
  state.counters["vertices"] = static_cast<double>(s.model.positions.size());
}
BENCHMARK(BM_Deform)
    ->Args({5000, 1})
    ->Args({200000, 1})
    ->Args({200000, 2})
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

void BM_DeformHeadStill(benchmark::State& state) {
  const Setup& s = setup(static_cast<int>(state.range(0)));
  s.deformer->set_threads(static_cast<int>(state.range(1)));
  rostro::DeformedMesh mesh;
  long frame = 0;
  for (auto _ : state) {
    s.deformer->deform(moving_frame(frame, true), mesh);
    benchmark::DoNotOptimize(mesh.positions().data());
    ++frame;
  }
}
BENCHMARK(BM_DeformHeadStill)
    ->Args({200000, 1})
    ->Args({200000, 2})
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

void BM_Normals(benchmark::State& state) {
  const Setup& s = setup(static_cast<int>(state.range(0)));
  std::vector<Eigen::Vector3f> normals;
  for (auto _ : state) {
    s.deformer->normals(s.model.positions, normals);
    benchmark::DoNotOptimize(normals.data());
  }
}
BENCHMARK(BM_Normals)->Arg(5000)->Arg(200000)->Unit(benchmark::kMillisecond);

void BM_Compile(benchmark::State& state) {
  const Setup& s = setup(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    rostro::Deformer d(s.model);
    benchmark::DoNotOptimize(&d);
  }
}
BENCHMARK(BM_Compile)->Arg(5000)->Arg(200000)->Unit(benchmark::kMillisecond)->Iterations(3);

}  // namespace
BENCHMARK_MAIN();

// Offscreen rendering speed with the default head: frames per second at 640x480 and
// 1280x720, drawing only (fixed mesh) and the whole per-frame path of `rostro play`
// (deform, upload, draw, multisample resolve, read back into a cv::Mat).

#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>

#include "facecore/expression_library.hpp"
#include "facecore/face_model.hpp"
#include "render/face_renderer.hpp"
#include "render/render_error.hpp"

namespace {

using rostro::render::CameraPose;
using rostro::render::FaceRenderer;

struct Head {
  rostro::FaceModel model = rostro::load_default_face_model();
  rostro::ExpressionLibrary library = rostro::ExpressionLibrary::load_default();
  static Head& get() {
    static Head head;
    return head;
  }
};

std::unique_ptr<FaceRenderer> make(benchmark::State& state, int samples) {
  rostro::render::RenderOptions options;
  options.width = static_cast<int>(state.range(0));
  options.height = static_cast<int>(state.range(1));
  options.samples = samples;
  try {
    auto face = std::make_unique<FaceRenderer>(Head::get().model, &Head::get().library, options);
    state.SetLabel(face->renderer().description());
    return face;
  } catch (const rostro::render::RenderUnavailable& e) {
    state.SkipWithError(e.what());
    return nullptr;
  }
}

// A frame that moves the jaw, lips and brows differently each time.
rostro::FapFrame moving_frame(long k) {
  rostro::FapFrame frame;
  const double t = static_cast<double>(k) / 25.0;
  frame.set(3, 300.0 + 250.0 * std::sin(2.0 * t));
  frame.set(12, 120.0 * std::sin(3.0 * t));
  frame.set(13, 120.0 * std::sin(3.0 * t + 0.5));
  frame.set(31, 150.0 * std::sin(1.3 * t));
  frame.set(32, 150.0 * std::sin(1.3 * t));
  frame.set(19, 200.0 * (1.0 + std::sin(0.7 * t)));
  return frame;
}

void BM_RenderFixedMesh(benchmark::State& state) {
  auto face = make(state, static_cast<int>(state.range(2)));
  if (!face) return;
  cv::Mat image;
  face->render_into(moving_frame(0), CameraPose::front(), image);
  for (auto _ : state) {
    face->renderer().render_into(CameraPose::front(), face->framing(), image);
    benchmark::DoNotOptimize(image.data);
  }
  state.counters["fps"] =
      benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}

void BM_DeformAndRender(benchmark::State& state) {
  auto face = make(state, static_cast<int>(state.range(2)));
  if (!face) return;
  cv::Mat image;
  long k = 0;
  for (auto _ : state) {
    face->render_into(moving_frame(k++), CameraPose::front(), image);
    benchmark::DoNotOptimize(image.data);
  }
  state.counters["fps"] =
      benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}

// Arguments: width, height, multisampling.
BENCHMARK(BM_RenderFixedMesh)
    ->Args({640, 480, 4})
    ->Args({1280, 720, 4})
    ->Args({640, 480, 1})
    ->Args({1280, 720, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_DeformAndRender)
    ->Args({640, 480, 4})
    ->Args({1280, 720, 4})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();

// Per-frame cost of turning camera buffers into BGR at 1280x720: YUYV conversion and
// MJPEG decoding (what a V4L2 webcam sends), on a textured synthetic frame.
#include <benchmark/benchmark.h>

#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "capture/pixel_convert.hpp"

namespace {

constexpr int kWidth = 1280;
constexpr int kHeight = 720;

// Noise plus shapes, so JPEG has real detail to code (a flat frame decodes unrealistically fast).
cv::Mat textured_frame() {
  cv::Mat image(kHeight, kWidth, CV_8UC3);
  cv::randu(image, cv::Scalar::all(0), cv::Scalar::all(255));
  cv::GaussianBlur(image, image, cv::Size(7, 7), 2.0);
  for (int i = 0; i < 40; ++i) {
    cv::circle(image, {(i * 97) % kWidth, (i * 53) % kHeight}, 6 + i % 10, cv::Scalar(20, 30, 40),
               cv::FILLED);
  }
  return image;
}

std::vector<std::uint8_t> yuyv_frame() {
  // Any byte pattern is valid YUYV; the conversion cost does not depend on content.
  cv::Mat packed(kHeight, kWidth * 2, CV_8UC1);
  cv::randu(packed, 0, 255);
  return {packed.datastart, packed.dataend};
}

void BM_YuyvToBgr720p(benchmark::State& state) {
  cv::setNumThreads(1);  // one core: the figure per frame a capture thread pays
  const auto yuyv = yuyv_frame();
  for (auto _ : state) {
    cv::Mat bgr =
        rostro::capture::yuyv_to_bgr(yuyv.data(), yuyv.size(), kWidth, kHeight, kWidth * 2);
    benchmark::DoNotOptimize(bgr.data);
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_YuyvToBgr720p)->Unit(benchmark::kMillisecond);

void BM_MjpegDecode720p(benchmark::State& state) {
  cv::setNumThreads(1);
  std::vector<std::uint8_t> jpeg;
  cv::imencode(".jpg", textured_frame(), jpeg,
               {cv::IMWRITE_JPEG_QUALITY, static_cast<int>(state.range(0))});
  for (auto _ : state) {
    cv::Mat bgr = rostro::capture::decode_mjpeg(jpeg.data(), jpeg.size());
    benchmark::DoNotOptimize(bgr.data);
  }
  state.counters["jpeg_kB"] = static_cast<double>(jpeg.size()) / 1000.0;
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_MjpegDecode720p)->Arg(80)->Arg(95)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();

#pragma once
// The take both capture benchmarks run (bench_capture_throughput, capture_profile): the
// default head through the range of motion after one neutral second, 1280x720, with the
// default layout's markers, rendered by synth and held in memory as BGR frames.

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <opencv2/core.hpp>
#include <stdexcept>
#include <utility>
#include <vector>

#include "calib/camera_intrinsics.hpp"
#include "eval/synth.hpp"
#include "facecore/expression_library.hpp"
#include "facecore/face_model.hpp"
#include "render/frame_sink.hpp"
#include "tracking/layout.hpp"

namespace rostro::bench {

constexpr int kTakeWidth = 1280, kTakeHeight = 720;

struct RenderedTake {
  std::vector<cv::Mat> frames;
  calib::CameraIntrinsics intrinsics;
};

inline RenderedTake render_capture_take(const tracking::MarkerLayout& layout) {
  class MemorySink : public render::FrameSink {
   public:
    void write(const cv::Mat& bgr) override { frames.push_back(bgr.clone()); }
    void finish() override {}
    long frames_written() const override { return static_cast<long>(frames.size()); }
    std::vector<cv::Mat> frames;
  };
  const FaceModel model = load_default_face_model();
  const ExpressionLibrary library = ExpressionLibrary::load_default();
  FapStream drive = eval::range_of_motion(25);
  drive.frames.resize(100);
  eval::prepend_neutral(drive, 1.0);
  eval::SynthOptions so;
  so.width = kTakeWidth;
  so.height = kTakeHeight;
  so.dot_diameter_mm = layout.dot_diameter_mm;
  so.dark_dots = layout.polarity == tracking::DotPolarity::Dark;
  MemorySink sink;
  const eval::SynthResult r =
      eval::synthesize(model, &library, eval::place_markers(model, layout), drive, so, sink);
  return {std::move(sink.frames), r.intrinsics};
}

// The take kept in a file (capture_profile's CACHE), so that later runs skip llvmpipe: rendered
// and saved when `path` does not exist, else read. Layout: frame count, fx fy cx cy, then the
// frames' BGR bytes.
inline RenderedTake cached_capture_take(const std::filesystem::path& path,
                                        const tracking::MarkerLayout& layout) {
  if (!std::filesystem::exists(path)) {
    const RenderedTake t = render_capture_take(layout);
    std::ofstream out(path, std::ios::binary);
    const auto n = static_cast<int32_t>(t.frames.size());
    out.write(reinterpret_cast<const char*>(&n), sizeof n);
    const double k[4] = {t.intrinsics.fx, t.intrinsics.fy, t.intrinsics.cx, t.intrinsics.cy};
    out.write(reinterpret_cast<const char*>(k), sizeof k);
    for (const cv::Mat& f : t.frames)
      out.write(reinterpret_cast<const char*>(f.data), static_cast<std::streamsize>(f.total() * 3));
  }
  std::ifstream in(path, std::ios::binary);
  int32_t n = 0;
  double k[4];
  in.read(reinterpret_cast<char*>(&n), sizeof n);
  in.read(reinterpret_cast<char*>(k), sizeof k);
  RenderedTake t;
  t.intrinsics = calib::default_intrinsics({kTakeWidth, kTakeHeight});
  t.intrinsics.fx = k[0], t.intrinsics.fy = k[1], t.intrinsics.cx = k[2], t.intrinsics.cy = k[3];
  t.intrinsics.source = "synth";
  for (int32_t i = 0; i < n; ++i) {
    cv::Mat f(kTakeHeight, kTakeWidth, CV_8UC3);
    in.read(reinterpret_cast<char*>(f.data), static_cast<std::streamsize>(f.total() * 3));
    t.frames.push_back(f);
  }
  if (!in || t.frames.empty()) throw std::runtime_error("bad take cache " + path.string());
  return t;
}

}  // namespace rostro::bench

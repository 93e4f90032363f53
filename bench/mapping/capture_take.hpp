#pragma once
// The take both capture benchmarks run (bench_capture_throughput, capture_profile): the
// default head through the range of motion after one neutral second, 1280x720, with the
// default layout's markers, rendered by synth and held in memory as BGR frames.

#include <opencv2/core.hpp>
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

}  // namespace rostro::bench

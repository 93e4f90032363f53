#pragma once
// A face model deformed by FAP frames and drawn offscreen: the piece `rostro play`,
// `rostro pose` and `rostro synth` share. The camera is framed once on the neutral head, so
// it stays still while the face moves.

#include <Eigen/Core>
#include <functional>
#include <memory>
#include <opencv2/core.hpp>
#include <vector>

#include "facecore/deformer.hpp"
#include "facecore/expression_library.hpp"
#include "facecore/face_model.hpp"
#include "facecore/fap_frame.hpp"
#include "facecore/fap_io.hpp"
#include "render/camera.hpp"
#include "render/frame_sink.hpp"
#include "render/offscreen_renderer.hpp"
#include "render/render_mesh.hpp"

namespace rostro::render {

// The model's neutral mesh as renderer input; vertices without colours get a skin tone.
RenderMesh to_render_mesh(const FaceModel& model);

// The bounds of the neutral head above a line `below_chin` x (top - chin) below the chin, so
// that a long neck or shoulders do not shrink the face: a portrait framing (0.12), or with
// more of the neck and shoulders. The top is the skull's (11.4) where the model has it, so
// that hair does not shrink the face either. Models without a chin point (2.1) keep their full
// bounds.
Bounds portrait_bounds(const FaceModel& model, const Bounds& full, float below_chin = 0.12f);

// Flattens deformed positions into the renderer's x, y, z list.
void flatten(const std::vector<Eigen::Vector3f>& positions, std::vector<float>& out);

class FaceRenderer {
 public:
  // `model` and `library` must outlive the renderer; with a library, FAPs 1 (viseme) and 2
  // (expression) are expanded. Throws RenderUnavailable when no OpenGL context exists.
  FaceRenderer(const FaceModel& model, const ExpressionLibrary* library,
               const RenderOptions& options = {});

  cv::Mat render(const FapFrame& frame, const CameraPose& pose);
  void render_into(const FapFrame& frame, const CameraPose& pose, cv::Mat& bgr);

  // The neutral head's bounds (down to a little below the chin), on which the camera is
  // framed; set_framing() picks another box (e.g. the mouth for a close-up).
  const Bounds& framing() const { return framing_; }
  void set_framing(const Bounds& frame) { framing_ = frame; }
  // The vertex positions of the last rendered frame (for ground truth in synth).
  const std::vector<Eigen::Vector3f>& positions() const { return mesh_.positions(); }
  OffscreenRenderer& renderer() { return renderer_; }
  const Deformer& deformer() const { return deformer_; }

 private:
  Deformer deformer_;
  OffscreenRenderer renderer_;
  Bounds framing_;
  DeformedMesh mesh_;
  std::vector<float> flat_;
};

// Renders every frame of `source` into `sink` (one image per FAP frame, in order) and
// finishes the sink. `progress` is called with the number of frames done. Returns the count.
// An InputError from the source (a malformed frame) propagates before finish(), so the
// sink's output is discarded.
long render_stream(FapSource& source, FaceRenderer& face, const CameraPose& pose, FrameSink& sink,
                   const std::function<void(long)>& progress = {});

}  // namespace rostro::render

#include "render/face_renderer.hpp"

#include <algorithm>

namespace rostro::render {
namespace {

constexpr float kSkin[3] = {0.87f, 0.68f, 0.58f};

}  // namespace

Bounds portrait_bounds(const FaceModel& model, const Bounds& full, float below_chin) {
  const FeaturePointId chin{2, 1}, skull_top{11, 4};
  if (!model.has_feature_point(chin)) return full;
  const auto chin_y = static_cast<float>(model.feature_point(chin).y());
  if (chin_y <= full.min[1] || chin_y >= full.max[1]) return full;
  // Up to the top of the skull where the model has it, not the hair over it: the same face
  // fills the same share of the frame whatever the hair's volume (the camera's margin leaves
  // room for the hair above the box).
  float top = full.max[1];
  if (model.has_feature_point(skull_top))
    top = std::clamp(static_cast<float>(model.feature_point(skull_top).y()), chin_y, full.max[1]);
  const float bottom = std::max(full.min[1], chin_y - below_chin * (top - chin_y));
  std::vector<float> above;  // the vertices above the bottom line, flattened
  for (const Eigen::Vector3f& p : model.positions)
    if (p.y() >= bottom) above.insert(above.end(), {p.x(), p.y(), p.z()});
  Bounds b = bounds_of(above);
  b.min[1] = bottom;
  b.max[1] = top;
  return b;
}

RenderMesh to_render_mesh(const FaceModel& model) {
  RenderMesh mesh;
  flatten(model.positions, mesh.positions);
  mesh.colors.reserve(mesh.positions.size());
  const bool coloured = model.colors.size() == model.positions.size();
  for (std::size_t v = 0; v < model.positions.size(); ++v) {
    // A missing or non-finite colour (NaN would draw as white) falls back to skin.
    const bool usable = coloured && model.colors[v].allFinite();
    for (int k = 0; k < 3; ++k) {
      mesh.colors.push_back(usable ? std::clamp(model.colors[v][k], 0.0f, 1.0f)
                                   : kSkin[static_cast<std::size_t>(k)]);
    }
  }
  if (!model.texture.empty() && model.texcoords.size() == model.positions.size()) {
    mesh.texture = model.texture;
    mesh.texcoords.reserve(2 * model.texcoords.size());
    for (const Eigen::Vector2f& uv : model.texcoords)
      mesh.texcoords.insert(mesh.texcoords.end(), {uv.x(), uv.y()});
  }
  mesh.triangles.reserve(3 * model.triangles.size());
  for (const Eigen::Vector3i& t : model.triangles) {
    mesh.triangles.insert(mesh.triangles.end(),
                          {static_cast<std::uint32_t>(t.x()), static_cast<std::uint32_t>(t.y()),
                           static_cast<std::uint32_t>(t.z())});
  }
  return mesh;
}

void flatten(const std::vector<Eigen::Vector3f>& positions, std::vector<float>& out) {
  out.resize(3 * positions.size());
  for (std::size_t v = 0; v < positions.size(); ++v) {
    out[3 * v] = positions[v].x();
    out[3 * v + 1] = positions[v].y();
    out[3 * v + 2] = positions[v].z();
  }
}

FaceRenderer::FaceRenderer(const FaceModel& model, const ExpressionLibrary* library,
                           const RenderOptions& options)
    : deformer_(model, library), renderer_(options) {
  renderer_.set_mesh(to_render_mesh(model));
  framing_ = portrait_bounds(model, renderer_.mesh_bounds());
}

cv::Mat FaceRenderer::render(const FapFrame& frame, const CameraPose& pose) {
  cv::Mat bgr;
  render_into(frame, pose, bgr);
  return bgr;
}

void FaceRenderer::render_into(const FapFrame& frame, const CameraPose& pose, cv::Mat& bgr) {
  deformer_.deform(frame, mesh_);
  flatten(mesh_.positions(), flat_);
  renderer_.update_positions(flat_);
  renderer_.render_into(pose, framing_, bgr);
}

long render_stream(FapSource& source, FaceRenderer& face, const CameraPose& pose, FrameSink& sink,
                   const std::function<void(long)>& progress) {
  FapFrame frame;
  cv::Mat image;
  long done = 0;
  while (source.next(frame)) {
    face.render_into(frame, pose, image);
    sink.write(image);
    ++done;
    if (progress) progress(done);
  }
  sink.finish();
  return done;
}

}  // namespace rostro::render

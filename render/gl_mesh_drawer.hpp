#pragma once
// The drawing code both back ends share (offscreen EGL and the GLFW window): shaders for
// skin shading of per-vertex colours or a texture, the mesh's GPU buffers, and one draw call per
// frame. Every method needs a current OpenGL 3.3 core context; the owner makes it current first.

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "render/camera.hpp"
#include "render/render_mesh.hpp"

namespace rostro::render {

struct Shading {
  std::array<float, 3> background{0.20f, 0.22f, 0.26f};
  float ambient = 0.28f;
  float key = 0.72f;       // main light, upper left of the camera
  float fill = 0.22f;      // softer light from the right
  float specular = 0.10f;  // skin sheen
  float shininess = 24.0f;
};

class GlMeshDrawer {
 public:
  GlMeshDrawer();  // compiles the shaders; throws RenderUnavailable on failure
  ~GlMeshDrawer();
  GlMeshDrawer(const GlMeshDrawer&) = delete;
  GlMeshDrawer& operator=(const GlMeshDrawer&) = delete;

  // Uploads topology, colours, texture and positions; throws std::invalid_argument for a bad mesh.
  void set_mesh(const RenderMesh& mesh);
  // New positions for the same vertices (x, y, z each); normals are recomputed.
  void update_positions(std::span<const float> positions);
  // Clears the bound framebuffer to the background and draws the mesh, in the `width` x
  // `height` rectangle whose lower-left corner is (x, y) (the rest is left alone).
  void draw(const CameraMatrices& camera, int width, int height, const Shading& shading, int x = 0,
            int y = 0);

  const Bounds& mesh_bounds() const { return bounds_; }
  std::size_t vertex_count() const { return vertex_count_; }

 private:
  void upload_texture(const RenderMesh& mesh);  // a white texel when the mesh has none

  unsigned program_ = 0;
  unsigned vao_ = 0;
  unsigned position_buffer_ = 0;
  unsigned normal_buffer_ = 0;
  unsigned color_buffer_ = 0;
  unsigned index_buffer_ = 0;
  unsigned texcoord_buffer_ = 0;
  unsigned texture_ = 0;
  std::size_t vertex_count_ = 0;
  std::size_t index_count_ = 0;
  std::vector<std::uint32_t> triangles_;
  std::vector<float> normals_;
  Bounds bounds_;
};

}  // namespace rostro::render

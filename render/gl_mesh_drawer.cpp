#include "render/gl_mesh_drawer.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "render/gl_api.hpp"
#include "render/render_error.hpp"

namespace rostro::render {
namespace {

constexpr const char* kVertexShader = R"(#version 330 core
layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec3 in_color;
layout(location = 3) in vec4 in_texcoord;  // cos 2 pi u, sin 2 pi u, t, 1 where textured
uniform mat4 u_view;
uniform mat4 u_projection;
out vec3 v_position;  // view space
out vec3 v_normal;    // view space
out vec3 v_color;
out vec4 v_texcoord;
void main() {
  vec4 p = u_view * vec4(in_position, 1.0);
  v_position = p.xyz;
  v_normal = mat3(u_view) * in_normal;  // the view is a rigid motion: no inverse-transpose
  v_color = in_color;
  v_texcoord = in_texcoord;
  gl_Position = u_projection * p;
}
)";

// Lambert with a little wrap (light bleeding past the terminator reads as skin), a soft fill
// light, ambient, and a faint Blinn-Phong sheen. Lights are fixed relative to the camera so
// every view of the head is lit the same way.
constexpr const char* kFragmentShader = R"(#version 330 core
in vec3 v_position;
in vec3 v_normal;
in vec3 v_color;
in vec4 v_texcoord;
uniform sampler2D u_texture;
uniform float u_ambient;
uniform float u_key;
uniform float u_fill;
uniform float u_specular;
uniform float u_shininess;
out vec4 out_color;
void main() {
  vec3 n = normalize(v_normal);
  if (!gl_FrontFacing) n = -n;
  vec3 view_dir = normalize(-v_position);
  vec3 key_dir = normalize(vec3(-0.45, 0.55, 0.75));
  vec3 fill_dir = normalize(vec3(0.7, 0.1, 0.6));
  const float wrap = 0.25;
  float key = max((dot(n, key_dir) + wrap) / (1.0 + wrap), 0.0);
  float fill = max(dot(n, fill_dir), 0.0);
  vec3 h = normalize(key_dir + view_dir);
  float spec = pow(max(dot(n, h), 0.0), u_shininess) * step(0.0, dot(n, key_dir));
  vec2 uv = vec2(atan(v_texcoord.y, v_texcoord.x) / 6.28318531, v_texcoord.z);
  vec2 du = dFdx(uv), dv = dFdy(uv);
  du.x -= round(du.x);
  dv.x -= round(dv.x);
  vec3 albedo = mix(v_color, textureGrad(u_texture, uv, du, dv).rgb, clamp(v_texcoord.w, 0.0, 1.0));
  vec3 c = albedo * (u_ambient + u_key * key + u_fill * fill) + vec3(u_specular * spec);
  out_color = vec4(min(c, vec3(1.0)), 1.0);
}
)";

unsigned compile(GLenum type, const char* source) {
  const GLuint shader = glCreateShader(type);
  glShaderSource(shader, 1, &source, nullptr);
  glCompileShader(shader);
  GLint ok = GL_FALSE;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (ok != GL_TRUE) {
    char log[1024] = {};
    glGetShaderInfoLog(shader, sizeof log, nullptr, log);
    glDeleteShader(shader);
    throw RenderUnavailable(std::string("OpenGL shader does not compile: ") + log);
  }
  return shader;
}

GLsizeiptr bytes(std::size_t count, std::size_t size) {
  return static_cast<GLsizeiptr>(count * size);
}

}  // namespace

GlMeshDrawer::GlMeshDrawer() {
  const GLuint vs = compile(GL_VERTEX_SHADER, kVertexShader);
  const GLuint fs = compile(GL_FRAGMENT_SHADER, kFragmentShader);
  program_ = glCreateProgram();
  glAttachShader(program_, vs);
  glAttachShader(program_, fs);
  glLinkProgram(program_);
  glDeleteShader(vs);
  glDeleteShader(fs);
  GLint ok = GL_FALSE;
  glGetProgramiv(program_, GL_LINK_STATUS, &ok);
  if (ok != GL_TRUE) {
    char log[1024] = {};
    glGetProgramInfoLog(program_, sizeof log, nullptr, log);
    glDeleteProgram(program_);
    throw RenderUnavailable(std::string("OpenGL program does not link: ") + log);
  }
  GLuint buffers[5];
  glGenBuffers(5, buffers);
  position_buffer_ = buffers[0];
  normal_buffer_ = buffers[1];
  color_buffer_ = buffers[2];
  index_buffer_ = buffers[3];
  texcoord_buffer_ = buffers[4];
  glGenVertexArrays(1, &vao_);
  glBindVertexArray(vao_);
  const GLuint per_attribute[3] = {position_buffer_, normal_buffer_, color_buffer_};
  for (GLuint location = 0; location < 3; ++location) {
    glBindBuffer(GL_ARRAY_BUFFER, per_attribute[location]);
    glEnableVertexAttribArray(location);
    glVertexAttribPointer(location, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
  }
  glBindBuffer(GL_ARRAY_BUFFER, texcoord_buffer_);
  glEnableVertexAttribArray(3);
  glVertexAttribPointer(3, 4, GL_FLOAT, GL_FALSE, 0, nullptr);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, index_buffer_);
  glBindVertexArray(0);
  glGenTextures(1, &texture_);
}

GlMeshDrawer::~GlMeshDrawer() {
  const GLuint buffers[5] = {position_buffer_, normal_buffer_, color_buffer_, index_buffer_,
                             texcoord_buffer_};
  glDeleteBuffers(5, buffers);
  glDeleteTextures(1, &texture_);
  glDeleteVertexArrays(1, &vao_);
  glDeleteProgram(program_);
}

void GlMeshDrawer::set_mesh(const RenderMesh& mesh) {
  validate(mesh);
  vertex_count_ = mesh.vertex_count();
  index_count_ = mesh.triangles.size();
  triangles_ = mesh.triangles;
  glBindVertexArray(vao_);
  glBindBuffer(GL_ARRAY_BUFFER, color_buffer_);
  glBufferData(GL_ARRAY_BUFFER, bytes(mesh.colors.size(), sizeof(float)), mesh.colors.data(),
               GL_STATIC_DRAW);
  upload_texture(mesh);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, index_buffer_);
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, bytes(index_count_, sizeof(std::uint32_t)),
               mesh.triangles.data(), GL_STATIC_DRAW);
  glBindBuffer(GL_ARRAY_BUFFER, position_buffer_);
  glBufferData(GL_ARRAY_BUFFER, bytes(mesh.positions.size(), sizeof(float)), nullptr,
               GL_DYNAMIC_DRAW);
  glBindBuffer(GL_ARRAY_BUFFER, normal_buffer_);
  glBufferData(GL_ARRAY_BUFFER, bytes(mesh.positions.size(), sizeof(float)), nullptr,
               GL_DYNAMIC_DRAW);
  glBindVertexArray(0);
  update_positions(mesh.positions);
  bounds_ = bounds_of(mesh.positions);
}

void GlMeshDrawer::upload_texture(const RenderMesh& mesh) {
  // Per vertex: u as a point on the unit circle, t (the image's rows run down), textured or not.
  std::vector<float> texcoords(4 * vertex_count_, 0.0f);
  const bool textured = !mesh.texcoords.empty();
  for (std::size_t v = 0; textured && v < vertex_count_; ++v) {
    const float u = mesh.texcoords[2 * v], t = mesh.texcoords[2 * v + 1];
    if (!std::isfinite(u) || !std::isfinite(t)) continue;
    const float angle = 2.0f * std::numbers::pi_v<float> * u;
    texcoords[4 * v] = std::cos(angle);
    texcoords[4 * v + 1] = std::sin(angle);
    texcoords[4 * v + 2] = 1.0f - t;
    texcoords[4 * v + 3] = 1.0f;
  }
  glBindBuffer(GL_ARRAY_BUFFER, texcoord_buffer_);
  glBufferData(GL_ARRAY_BUFFER, bytes(texcoords.size(), sizeof(float)), texcoords.data(),
               GL_STATIC_DRAW);
  const std::uint8_t white[3] = {255, 255, 255};
  glBindTexture(GL_TEXTURE_2D, texture_);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB8, textured ? mesh.texture.width : 1,
               textured ? mesh.texture.height : 1, 0, GL_RGB, GL_UNSIGNED_BYTE,
               textured ? mesh.texture.rgb.data() : white);
  glGenerateMipmap(GL_TEXTURE_2D);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  glBindTexture(GL_TEXTURE_2D, 0);
}

void GlMeshDrawer::update_positions(std::span<const float> positions) {
  if (positions.size() != 3 * vertex_count_) {
    throw std::invalid_argument("render mesh: " + std::to_string(positions.size() / 3) +
                                " positions for a mesh of " + std::to_string(vertex_count_) +
                                " vertices");
  }
  compute_vertex_normals(positions, triangles_, normals_);
  glBindBuffer(GL_ARRAY_BUFFER, position_buffer_);
  glBufferSubData(GL_ARRAY_BUFFER, 0, bytes(positions.size(), sizeof(float)), positions.data());
  glBindBuffer(GL_ARRAY_BUFFER, normal_buffer_);
  glBufferSubData(GL_ARRAY_BUFFER, 0, bytes(normals_.size(), sizeof(float)), normals_.data());
  glBindBuffer(GL_ARRAY_BUFFER, 0);
}

void GlMeshDrawer::draw(const CameraMatrices& camera, int width, int height, const Shading& shading,
                        int x, int y) {
  glViewport(x, y, width, height);
  glEnable(GL_SCISSOR_TEST);  // the clear stays inside the rectangle
  glScissor(x, y, width, height);
  glClearColor(shading.background[0], shading.background[1], shading.background[2], 1.0f);
  glClearDepth(1.0);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glDisable(GL_SCISSOR_TEST);
  if (index_count_ == 0) return;
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDisable(GL_CULL_FACE);  // the mouth interior and eyelids are seen from both sides
  glUseProgram(program_);
  glUniformMatrix4fv(glGetUniformLocation(program_, "u_view"), 1, GL_FALSE, camera.view.data());
  glUniformMatrix4fv(glGetUniformLocation(program_, "u_projection"), 1, GL_FALSE,
                     camera.projection.data());
  glUniform1f(glGetUniformLocation(program_, "u_ambient"), shading.ambient);
  glUniform1f(glGetUniformLocation(program_, "u_key"), shading.key);
  glUniform1f(glGetUniformLocation(program_, "u_fill"), shading.fill);
  glUniform1f(glGetUniformLocation(program_, "u_specular"), shading.specular);
  glUniform1f(glGetUniformLocation(program_, "u_shininess"), shading.shininess);
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, texture_);
  glUniform1i(glGetUniformLocation(program_, "u_texture"), 0);
  glBindVertexArray(vao_);
  glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(index_count_), GL_UNSIGNED_INT, nullptr);
  glBindVertexArray(0);
  glBindTexture(GL_TEXTURE_2D, 0);
  glUseProgram(0);
}

}  // namespace rostro::render

// Face model textures: PNG files round-trip and bad ones are one clear error; baking paints
// each texel with the colour of the mesh point it shows, the short way across the seam; OBJ
// texture coordinates survive a write and a read.

#include "facecore/texture.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "facecore/error.hpp"
#include "facecore/obj_io.hpp"
#include "facecore/texture_bake.hpp"

namespace rostro {
namespace {

namespace fs = std::filesystem;

fs::path scratch(const std::string& name) {
  const fs::path dir = fs::path(ROSTRO_BINARY_DIR) / "test_texture" / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::string error_of(const fs::path& path) {
  try {
    read_texture(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(Texture, RoundTripsThroughPngAndBadFilesAreOneClearError) {
  const fs::path dir = scratch("png");
  Texture t;
  t.width = 3;
  t.height = 2;
  t.rgb = {255, 0, 0, 0, 255, 0, 0, 0, 255, 10, 20, 30, 40, 50, 60, 70, 80, 90};
  write_texture(t, dir / "t.png");
  const Texture back = read_texture(dir / "t.png");
  EXPECT_EQ(back.width, 3);
  EXPECT_EQ(back.height, 2);
  EXPECT_EQ(back.rgb, t.rgb);  // rows top to bottom, r g b
  EXPECT_NE(error_of(dir / "missing.png").find("missing.png: the texture image does not exist"),
            std::string::npos);
  std::ofstream(dir / "text.png") << "not an image";
  EXPECT_NE(error_of(dir / "text.png").find("text.png: the texture is not an image"),
            std::string::npos);
}

TEST(TextureBake, EachTexelTakesThePointItShowsTheShortWayAcrossTheSeam) {
  // One triangle across u = 0 (u 0.9 -> 1.1 the short way), v 0 -> 1; the colour is the point's
  // x in red, so texels left to right across the seam must grow in red.
  FaceModel m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  m.triangles = {{0, 1, 2}};
  m.texcoords = {{0.9f, 0.0f}, {0.1f, 0.0f}, {0.9f, 1.0f}};
  const Texture t = bake_texture(m, {0}, 40, 10, [](const TexelPoint& p) {
    return Eigen::Vector3f(static_cast<float>(p.position.x()), static_cast<float>(p.uv.x() > 1.0),
                           0);
  });
  auto red = [&](int x, int row) { return t.rgb[3 * (row * 40 + x)]; };
  auto green = [&](int x, int row) { return t.rgb[3 * (row * 40 + x) + 1]; };
  // Bottom row (v near 0): u from 0.9 (x = 36) to 1.1 (x = 4 past the seam).
  EXPECT_LT(red(36, 9), 40);
  EXPECT_GT(red(38, 9), red(36, 9));
  EXPECT_GT(red(1, 9), red(38, 9));  // past the seam, still growing: the short way
  EXPECT_EQ(green(1, 9), 255);       // and told u past 1
  EXPECT_EQ(green(37, 9), 0);
  // The middle of the texture, far from the triangle, takes the nearest covered texel's.
  EXPECT_EQ(red(10, 9), red(3, 9)) << "filled from the nearest texel along its row";
  // Sampling returns what was baked (texel centres), wrapping in u.
  const Eigen::Vector3f c = sample_texture(t, Eigen::Vector2f((1 + 0.5f) / 40, 1 - 9.5f / 10));
  EXPECT_NEAR(c.x(), red(1, 9) / 255.0f, 1e-3);
  const Eigen::Vector3f wrapped =
      sample_texture(t, Eigen::Vector2f(1 + (1 + 0.5f) / 40, 1 - 9.5f / 10));
  EXPECT_NEAR(wrapped.x(), c.x(), 1e-6);
}

TEST(ObjTexcoords, SurviveAWriteAndARead) {
  const fs::path dir = scratch("obj");
  ObjMesh mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {2, 2, 2}};
  const float nan = std::numeric_limits<float>::quiet_NaN();
  // A face across the seam (u 0.95 and 0.05), one plain face, one untextured vertex.
  mesh.texcoords = {{0.95f, 0.1f}, {0.05f, 0.1f}, {0.05f, 0.9f}, {0.95f, 0.9f}, {nan, nan}};
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}, {2, 3, 4}};
  write_obj(mesh, dir / "m.obj");
  std::ifstream in(dir / "m.obj");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("vt 1.050000 0.100000"), std::string::npos)
      << "a face across the seam is written past u = 1:\n"
      << text;
  EXPECT_NE(text.find("f 3 4 5\n"), std::string::npos) << "a face with an untextured vertex";
  const ObjMesh back = read_obj(dir / "m.obj");
  ASSERT_EQ(back.texcoords.size(), 5u);
  for (std::size_t v = 0; v < 4; ++v)
    EXPECT_LT((back.texcoords[v] - mesh.texcoords[v]).norm(), 1e-5f) << "vertex " << v;
  EXPECT_FALSE(back.texcoords[4].allFinite());
  std::ofstream(dir / "bad.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/2 3/1\n";
  try {
    read_obj(dir / "bad.obj");
    ADD_FAILURE() << "a texture coordinate out of range was read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.obj:5: texture coordinate 2 is out of range (the file has 1 texture coordinates so far)"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace rostro

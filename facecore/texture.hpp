#pragma once
// A face model's colour texture: an RGB image the skin's texture coordinates point into. It
// carries what a vertex colour cannot at a mesh's density: brows, lash lines, the lips'
// border and the hairline as sharp as the image. Stored beside the mesh as a PNG.

#include <cstdint>
#include <filesystem>
#include <vector>

namespace rostro {

struct Texture {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;  // rows top to bottom, r g b per texel, 0..255

  bool empty() const { return rgb.empty(); }
};

// Reads a PNG (or any image OpenCV reads) as RGB; throws InputError naming the file when it is
// missing or not an image.
Texture read_texture(const std::filesystem::path& path);

// Writes a PNG atomically; throws InputError naming the file when it cannot be written.
void write_texture(const Texture& texture, const std::filesystem::path& path);

}  // namespace rostro

#include "facecore/texture.hpp"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "facecore/atomic_file.hpp"
#include "facecore/error.hpp"

namespace rostro {

Texture read_texture(const std::filesystem::path& path) {
  if (!std::filesystem::exists(path))
    throw InputError(path.string() + ": the texture image does not exist");
  const cv::Mat bgr = cv::imread(path.string(), cv::IMREAD_COLOR);
  if (bgr.empty()) throw InputError(path.string() + ": the texture is not an image OpenCV reads");
  cv::Mat rgb;
  cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
  Texture texture;
  texture.width = rgb.cols;
  texture.height = rgb.rows;
  texture.rgb.resize(static_cast<std::size_t>(rgb.cols) * static_cast<std::size_t>(rgb.rows) * 3);
  for (int r = 0; r < rgb.rows; ++r)
    std::copy_n(rgb.ptr<std::uint8_t>(r), 3 * rgb.cols,
                texture.rgb.begin() + static_cast<std::ptrdiff_t>(3 * r * rgb.cols));
  return texture;
}

void write_texture(const Texture& texture, const std::filesystem::path& path) {
  const cv::Mat rgb(texture.height, texture.width, CV_8UC3,
                    const_cast<std::uint8_t*>(texture.rgb.data()));
  cv::Mat bgr;
  cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
  std::vector<std::uint8_t> png;
  if (!cv::imencode(".png", bgr, png))
    throw InputError(path.string() + ": the texture cannot be encoded as PNG");
  AtomicFile file(path);
  file.write(std::string_view(reinterpret_cast<const char*>(png.data()), png.size()));
  file.commit();
}

}  // namespace rostro

#include "capture/image_folder_source.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>

#include "facecore/error.hpp"

namespace rostro::capture {
namespace {

constexpr double kDefaultFolderFps = 25.0;

bool is_digit(char c) {
  return std::isdigit(static_cast<unsigned char>(c)) != 0;
}

bool has_image_extension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  static const char* const kExtensions[] = {".png",  ".jpg", ".jpeg", ".bmp", ".tif",
                                            ".tiff", ".pgm", ".ppm",  ".pbm", ".webp"};
  return std::any_of(std::begin(kExtensions), std::end(kExtensions),
                     [&](const char* e) { return ext == e; });
}

cv::Mat read_image(const std::string& path) {
  cv::Mat image;
  try {
    image = cv::imread(path, cv::IMREAD_COLOR);
  } catch (const cv::Exception&) {
    image.release();
  }
  if (image.empty()) throw InputError(path + ": not a readable image (corrupt or unsupported)");
  return image;
}

class ImageFolderSource final : public FrameSource {
 public:
  ImageFolderSource(std::string folder, std::vector<std::string> files, double fps)
      : folder_(std::move(folder)), files_(std::move(files)), fps_(fps) {
    // The first image fixes the frame size; read it now so a bad folder fails at open.
    first_ = read_image(files_.front());
    size_ = first_.size();
  }

  std::optional<Frame> next() override {
    if (index_ >= files_.size()) return std::nullopt;
    const std::string& path = files_[index_];
    cv::Mat image = index_ == 0 ? std::move(first_) : read_image(path);
    if (image.size() != size_) {
      throw InputError(
          fmt::format("{}: image is {}x{}, expected {}x{} like the first image of the folder", path,
                      image.cols, image.rows, size_.width, size_.height));
    }
    Frame frame;
    frame.image = std::move(image);
    frame.sequence = static_cast<std::int64_t>(index_);
    frame.timestamp_s = static_cast<double>(index_) / fps_;
    ++index_;
    ++stats_.delivered;
    return frame;
  }
  double nominal_fps() const override { return fps_; }
  std::int64_t frame_count() const override { return static_cast<std::int64_t>(files_.size()); }
  cv::Size frame_size() const override { return size_; }
  SourceStats stats() const override { return stats_; }
  std::string description() const override {
    return fmt::format("image folder {} ({} images, {}x{} @ {:g} fps)", folder_, files_.size(),
                       size_.width, size_.height, fps_);
  }

 private:
  std::string folder_;
  std::vector<std::string> files_;
  double fps_;
  cv::Mat first_;
  cv::Size size_;
  std::size_t index_ = 0;
  SourceStats stats_;
};

}  // namespace

bool natural_less(const std::string& a, const std::string& b) {
  std::size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    if (is_digit(a[i]) && is_digit(b[j])) {
      // Compare the digit runs by value: skip leading zeros, then length, then digits.
      std::size_t i_end = i, j_end = j;
      while (i_end < a.size() && is_digit(a[i_end])) ++i_end;
      while (j_end < b.size() && is_digit(b[j_end])) ++j_end;
      std::size_t i_start = i, j_start = j;
      while (i_start + 1 < i_end && a[i_start] == '0') ++i_start;
      while (j_start + 1 < j_end && b[j_start] == '0') ++j_start;
      const std::size_t i_len = i_end - i_start, j_len = j_end - j_start;
      if (i_len != j_len) return i_len < j_len;
      const int cmp = a.compare(i_start, i_len, b, j_start, j_len);
      if (cmp != 0) return cmp < 0;
      i = i_end;
      j = j_end;
      continue;
    }
    if (a[i] != b[j]) return static_cast<unsigned char>(a[i]) < static_cast<unsigned char>(b[j]);
    ++i;
    ++j;
  }
  if ((a.size() - i) != (b.size() - j)) return (a.size() - i) < (b.size() - j);
  return a < b;  // equal by value ("img01" vs "img1"): fall back to bytes for a total order
}

std::vector<std::string> list_image_files(const std::string& folder) {
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(folder, ec)) {
    if (!entry.is_regular_file(ec) || !has_image_extension(entry.path())) continue;
    names.push_back(entry.path().filename().string());
  }
  if (ec) throw InputError(folder + ": cannot list folder: " + ec.message());
  std::sort(names.begin(), names.end(), natural_less);
  std::vector<std::string> paths;
  paths.reserve(names.size());
  for (const auto& name : names) paths.push_back((std::filesystem::path(folder) / name).string());
  return paths;
}

std::unique_ptr<FrameSource> open_image_folder_source(const std::string& folder, double fps) {
  auto files = list_image_files(folder);
  if (files.empty()) {
    throw InputError(
        folder +
        ": no images in folder (expected .png, .jpg, .bmp, .tif, .pgm, .ppm or .webp files)");
  }
  return std::make_unique<ImageFolderSource>(folder, std::move(files),
                                             fps > 0 ? fps : kDefaultFolderFps);
}

}  // namespace rostro::capture

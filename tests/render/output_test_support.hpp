#pragma once
// Shared by the render tests that write files: a scratch folder removed afterwards, and the
// number of frames a video really holds (read back through OpenCV/FFmpeg).

#include <unistd.h>

#include <filesystem>
#include <iterator>
#include <opencv2/videoio.hpp>
#include <string>

namespace rostro::render::test {

class TempDir {
 public:
  TempDir() {
    path_ = std::filesystem::temp_directory_path() /
            ("rostro-render-test-" + std::to_string(::getpid()) + "-" + std::to_string(count_++));
    std::filesystem::create_directories(path_);
  }
  ~TempDir() { std::filesystem::remove_all(path_); }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  const std::filesystem::path& path() const { return path_; }
  std::size_t entries() const {
    return static_cast<std::size_t>(std::distance(std::filesystem::directory_iterator(path_), {}));
  }
  bool empty() const { return entries() == 0; }

 private:
  std::filesystem::path path_;
  static inline int count_ = 0;
};

// -1 when the file does not open as a video.
inline int count_frames(const std::filesystem::path& video) {
  cv::VideoCapture capture(video.string());
  if (!capture.isOpened()) return -1;
  int n = 0;
  cv::Mat frame;
  while (capture.read(frame)) ++n;
  return n;
}

}  // namespace rostro::render::test

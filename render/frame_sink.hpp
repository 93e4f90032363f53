#pragma once
// Where rendered frames go: an mp4 (VideoWriter), a folder of PNGs (FrameFolderWriter) or
// memory (MemoryFrameSink).
// Both write under a temporary name and put the result in place only on finish(), so an
// interrupted run never leaves a half-written video or a partial frame folder behind.

#include <filesystem>
#include <memory>
#include <opencv2/core.hpp>
#include <vector>

namespace rostro::render {

class FrameSink {
 public:
  virtual ~FrameSink() = default;
  // An 8-bit BGR image, every frame the same size. Throws std::invalid_argument otherwise.
  virtual void write(const cv::Mat& bgr) = 0;
  // Completes the output and moves it into place. Without it the output is discarded.
  virtual void finish() = 0;
  virtual long frames_written() const = 0;
};

// Keeps every frame in memory (tests and benchmarks that look at the pixels).
class MemoryFrameSink : public FrameSink {
 public:
  void write(const cv::Mat& bgr) override { frames.push_back(bgr.clone()); }
  void finish() override {}
  long frames_written() const override { return static_cast<long>(frames.size()); }
  std::vector<cv::Mat> frames;
};

// Writes `frame_000000.png`, `frame_000001.png`, ... into `folder` (created if needed;
// files of the same names already there are replaced on finish()).
class FrameFolderWriter : public FrameSink {
 public:
  explicit FrameFolderWriter(std::filesystem::path folder);
  ~FrameFolderWriter() override;
  void write(const cv::Mat& bgr) override;
  void finish() override;
  long frames_written() const override { return count_; }

  static std::string frame_name(long index);

 private:
  std::filesystem::path folder_;
  std::filesystem::path staging_;
  long count_ = 0;
  bool finished_ = false;
  cv::Size size_;
};

// Writes `bgr` as an image (format from the extension: .png, .jpg, ...) through a
// temporary file. Throws rostro::InputError when it cannot be encoded or written.
void write_image(const std::filesystem::path& path, const cv::Mat& bgr);

}  // namespace rostro::render

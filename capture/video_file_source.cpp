#include "capture/video_file_source.hpp"

#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "facecore/error.hpp"

namespace rostro::capture {
namespace {

class VideoFileSource final : public FrameSource {
 public:
  explicit VideoFileSource(const std::string& path);

  std::optional<Frame> next() override;
  double nominal_fps() const override { return fps_; }
  std::int64_t frame_count() const override { return frame_count_; }
  cv::Size frame_size() const override { return size_; }
  SourceStats stats() const override { return stats_; }
  std::string description() const override {
    return fmt::format("video file {} ({}x{} @ {:g} fps)", path_, size_.width, size_.height, fps_);
  }

 private:
  std::string path_;
  cv::VideoCapture capture_;
  double fps_ = 0;
  std::int64_t frame_count_ = -1;
  cv::Size size_;
  std::int64_t index_ = 0;
  std::optional<double> first_ms_;
  double last_timestamp_s_ = -1;
  SourceStats stats_;
};

VideoFileSource::VideoFileSource(const std::string& path) : path_(path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw InputError(path + ": no such video file");
  if (std::filesystem::is_directory(path, ec))
    throw InputError(path + ": is a folder, expected a video file");
  bool opened = false;
  try {
    opened = capture_.open(path, cv::CAP_FFMPEG);
  } catch (const cv::Exception&) {
    opened = false;
  }
  if (!opened || !capture_.isOpened()) {
    throw InputError(path +
                     ": not a video FFmpeg can read (corrupt, truncated or an unknown format)");
  }
  fps_ = capture_.get(cv::CAP_PROP_FPS);
  if (!(fps_ > 0) || !std::isfinite(fps_))
    fps_ = 25.0;  // containers without a rate: a usual default
  const double count = capture_.get(cv::CAP_PROP_FRAME_COUNT);
  frame_count_ = count > 0 ? static_cast<std::int64_t>(std::llround(count)) : -1;
  size_ = {static_cast<int>(capture_.get(cv::CAP_PROP_FRAME_WIDTH)),
           static_cast<int>(capture_.get(cv::CAP_PROP_FRAME_HEIGHT))};
  if (size_.width <= 0 || size_.height <= 0) {
    throw InputError(path + ": video has no picture size (no video stream?)");
  }
}

std::optional<Frame> VideoFileSource::next() {
  cv::Mat image;
  bool ok = false;
  try {
    ok = capture_.read(image);
  } catch (const cv::Exception& e) {
    throw InputError(fmt::format("{}: frame {}: cannot decode: {}", path_, index_, e.what()));
  }
  if (!ok || image.empty()) return std::nullopt;
  if (image.channels() == 1) cv::cvtColor(image, image, cv::COLOR_GRAY2BGR);
  if (image.depth() != CV_8U) image.convertTo(image, CV_8U);

  Frame frame;
  frame.image = std::move(image);
  frame.sequence = index_;
  // The presentation time of the frame just read; relative to the first frame.
  const double ms = capture_.get(cv::CAP_PROP_POS_MSEC);
  if (!first_ms_) first_ms_ = ms;
  double t = (ms - *first_ms_) / 1000.0;
  // A container without usable times (all zero, or going backwards) falls back to the
  // nominal rate so times stay strictly increasing.
  if (index_ > 0 && !(t > last_timestamp_s_)) t = last_timestamp_s_ + 1.0 / fps_;
  frame.timestamp_s = t;
  last_timestamp_s_ = t;
  ++index_;
  ++stats_.delivered;
  return frame;
}

}  // namespace

std::unique_ptr<FrameSource> open_video_file_source(const std::string& path) {
  return std::make_unique<VideoFileSource>(path);
}

}  // namespace rostro::capture

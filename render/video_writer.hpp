#pragma once
// Writes frames to an H.264 video through an ffmpeg subprocess fed raw BGR frames, with an
// optional WAV muxed in. Video and audio both start at time 0, so frame k is shown at audio
// time k / fps: a FAP stream planned on the audio clock stays in sync. The file is written
// under a temporary name beside the destination and renamed into place by finish().

#include <filesystem>
#include <string>

#include "render/frame_sink.hpp"

namespace rostro::render {

struct VideoOptions {
  double fps = 25.0;
  std::filesystem::path audio;  // a WAV (or any audio ffmpeg reads) to mux in; empty for none
  int crf = 18;                 // x264 quality: lower is better and larger
  std::string preset = "veryfast";
  std::string ffmpeg = "ffmpeg";  // the program; $ROSTRO_FFMPEG overrides it
};

class VideoWriter : public FrameSink {
 public:
  // Checks the audio file exists (InputError) and the destination folder. ffmpeg starts
  // with the first frame, when the size is known.
  VideoWriter(std::filesystem::path destination, VideoOptions options);
  ~VideoWriter() override;
  VideoWriter(const VideoWriter&) = delete;
  VideoWriter& operator=(const VideoWriter&) = delete;

  void write(const cv::Mat& bgr) override;
  // Waits for ffmpeg, checks it succeeded, renames into place. Throws InputError naming
  // the destination and ffmpeg's last message otherwise. With no frames written there is
  // no video: that is an error too.
  void finish() override;
  long frames_written() const override { return count_; }

 private:
  std::filesystem::path destination_;
  std::filesystem::path temporary_;
  std::filesystem::path log_;
  VideoOptions options_;
  cv::Size size_;
  long count_ = 0;
  int pipe_fd_ = -1;
  int pid_ = -1;
  bool finished_ = false;

  void start(cv::Size size);
  int wait_for_ffmpeg();
  std::string ffmpeg_message() const;
  void abandon() noexcept;
};

}  // namespace rostro::render

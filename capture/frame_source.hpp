#pragma once
// Where frames come from: a V4L2 or libcamera device, a video file or an image folder.
// Every source gives frames with a timestamp and a sequence number, so that dropped frames
// are visible downstream.

#include <cstdint>
#include <memory>
#include <opencv2/core.hpp>
#include <optional>
#include <string>

namespace rostro::capture {

struct Frame {
  cv::Mat image;              // BGR, 8 bits per channel
  double timestamp_s = 0;     // from the driver or the container, seconds from the first frame
  std::int64_t sequence = 0;  // the source's own frame counter; gaps are dropped frames
};

struct SourceStats {
  std::int64_t delivered = 0;  // frames handed out
  std::int64_t dropped = 0;    // gaps in the sequence numbers seen so far
};

class FrameSource {
 public:
  virtual ~FrameSource() = default;
  // The next frame, or nullopt at the end of a file. A device that fails mid-take throws
  // InputError; frames already delivered stay valid.
  virtual std::optional<Frame> next() = 0;
  virtual double nominal_fps() const = 0;
  // Total frames when known in advance (files and folders), else -1.
  virtual std::int64_t frame_count() const { return -1; }
  virtual cv::Size frame_size() const = 0;
  virtual SourceStats stats() const = 0;
  virtual std::string description() const = 0;
};

}  // namespace rostro::capture

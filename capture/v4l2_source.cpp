#include "capture/v4l2_source.hpp"

#include <fmt/format.h>
#include <linux/videodev2.h>
#include <poll.h>
#include <sys/mman.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <vector>

#include "capture/capture_mode.hpp"
#include "capture/pixel_convert.hpp"
#include "capture/sequence_counter.hpp"
#include "capture/v4l2_device.hpp"
#include "facecore/error.hpp"

namespace rostro::capture {
namespace {

constexpr std::uint32_t kBufferCount = 4;
// A camera that sends nothing for this long is treated as failed (a stalled USB stream).
constexpr int kFrameTimeoutMs = 5000;
// Frames that fail to decode in a row before the source gives up.
constexpr int kMaxBadFramesInARow = 30;

std::string errno_text(int err) {
  return std::strerror(err);
}

struct MappedBuffer {
  void* start = MAP_FAILED;
  std::size_t length = 0;
};

class V4l2Source final : public FrameSource {
 public:
  V4l2Source(const std::string& path, const SourceOptions& options);
  ~V4l2Source() override;
  V4l2Source(const V4l2Source&) = delete;
  V4l2Source& operator=(const V4l2Source&) = delete;

  std::optional<Frame> next() override;
  double nominal_fps() const override { return mode_.fps(); }
  cv::Size frame_size() const override { return {mode_.width, mode_.height}; }
  SourceStats stats() const override { return stats_; }
  std::string description() const override {
    return fmt::format("V4L2 {} '{}' {}", info_.path, info_.card, describe_mode(mode_));
  }

 private:
  void negotiate(const SourceOptions& options);
  void set_control(std::uint32_t id, std::int32_t value, const char* what);
  void apply_exposure_and_gain(const SourceOptions& options);
  void start_streaming();
  void stop_streaming() noexcept;
  [[noreturn]] void fail(const std::string& what);
  cv::Mat convert(const MappedBuffer& buffer, std::size_t bytes_used) const;

  V4l2DeviceInfo info_;
  FileDescriptor fd_;
  CaptureMode mode_;
  std::size_t bytes_per_line_ = 0;
  std::vector<MappedBuffer> buffers_;
  bool streaming_ = false;
  std::string failure_;  // set once the device failed; next() keeps reporting it
  SequenceCounter sequence_;
  std::optional<double> first_timestamp_s_;
  SourceStats stats_;
};

V4l2Source::V4l2Source(const std::string& path, const SourceOptions& options) {
  fd_ = open_v4l2_capture_device(path, info_);
  info_.modes = enumerate_modes(fd_.get(), &info_.other_formats);
  negotiate(options);
  apply_exposure_and_gain(options);
  try {
    start_streaming();
  } catch (...) {
    stop_streaming();  // the destructor does not run for a half-built source
    throw;
  }
}

V4l2Source::~V4l2Source() {
  stop_streaming();
}

void V4l2Source::negotiate(const SourceOptions& options) {
  const ModeRequest request{options.width, options.height, options.fps, options.pixel_format};
  const auto chosen = choose_mode(info_.modes, request);
  if (!chosen) {
    std::string offered;
    for (const auto& mode : info_.modes)
      offered += (offered.empty() ? "" : ", ") + describe_mode(mode);
    throw InputError(fmt::format("{}: no mode matches {} (offered: {})", info_.path,
                                 describe_request(request),
                                 offered.empty() ? "no YUYV or MJPEG mode" : offered));
  }
  mode_ = *chosen;

  v4l2_format format{};
  format.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  format.fmt.pix.width = static_cast<std::uint32_t>(mode_.width);
  format.fmt.pix.height = static_cast<std::uint32_t>(mode_.height);
  format.fmt.pix.pixelformat = mode_.fourcc;
  format.fmt.pix.field = V4L2_FIELD_NONE;
  if (xioctl(fd_.get(), VIDIOC_S_FMT, &format) != 0) {
    const int err = errno;
    if (err == EBUSY)
      throw InputError(info_.path + ": device is busy (another program is using the camera)");
    throw InputError(
        fmt::format("{}: cannot set {}: {}", info_.path, describe_mode(mode_), errno_text(err)));
  }
  // The driver may adjust what it was given; use what it actually set.
  if (format.fmt.pix.pixelformat != mode_.fourcc ||
      static_cast<int>(format.fmt.pix.width) != mode_.width ||
      static_cast<int>(format.fmt.pix.height) != mode_.height) {
    throw InputError(fmt::format("{}: asked for {}, driver set {} {}x{}", info_.path,
                                 describe_mode(mode_), fourcc_to_string(format.fmt.pix.pixelformat),
                                 format.fmt.pix.width, format.fmt.pix.height));
  }
  bytes_per_line_ = format.fmt.pix.bytesperline;

  if (mode_.interval_den != 0) {
    v4l2_streamparm parm{};
    parm.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    if (xioctl(fd_.get(), VIDIOC_G_PARM, &parm) == 0 &&
        (parm.parm.capture.capability & V4L2_CAP_TIMEPERFRAME)) {
      parm.parm.capture.timeperframe.numerator = mode_.interval_num;
      parm.parm.capture.timeperframe.denominator = mode_.interval_den;
      if (xioctl(fd_.get(), VIDIOC_S_PARM, &parm) == 0 &&
          parm.parm.capture.timeperframe.numerator != 0) {
        mode_.interval_num = parm.parm.capture.timeperframe.numerator;
        mode_.interval_den = parm.parm.capture.timeperframe.denominator;
      }
    }
  }
}

void V4l2Source::set_control(std::uint32_t id, std::int32_t value, const char* what) {
  v4l2_queryctrl query{};
  query.id = id;
  if (xioctl(fd_.get(), VIDIOC_QUERYCTRL, &query) != 0 || (query.flags & V4L2_CTRL_FLAG_DISABLED)) {
    throw InputError(fmt::format("{}: '{}' has no {} control", info_.path, info_.card, what));
  }
  if (query.type == V4L2_CTRL_TYPE_INTEGER && (value < query.minimum || value > query.maximum)) {
    throw InputError(fmt::format("{}: {} {} is outside the device's range {}..{}", info_.path, what,
                                 value, query.minimum, query.maximum));
  }
  v4l2_control control{};
  control.id = id;
  control.value = value;
  if (xioctl(fd_.get(), VIDIOC_S_CTRL, &control) != 0) {
    throw InputError(
        fmt::format("{}: cannot set {} to {}: {}", info_.path, what, value, errno_text(errno)));
  }
}

void V4l2Source::apply_exposure_and_gain(const SourceOptions& options) {
  if (options.exposure) {
    // Manual exposure first; some UVC cameras only offer shutter priority, which also
    // fixes the exposure time.
    try {
      set_control(V4L2_CID_EXPOSURE_AUTO, V4L2_EXPOSURE_MANUAL, "manual exposure mode");
    } catch (const InputError&) {
      set_control(V4L2_CID_EXPOSURE_AUTO, V4L2_EXPOSURE_SHUTTER_PRIORITY,
                  "shutter-priority exposure mode");
    }
    set_control(V4L2_CID_EXPOSURE_ABSOLUTE,
                static_cast<std::int32_t>(std::lround(*options.exposure)),
                "absolute exposure (100 us units)");
  }
  if (options.gain) {
    v4l2_control autogain{V4L2_CID_AUTOGAIN, 0};
    xioctl(fd_.get(), VIDIOC_S_CTRL, &autogain);  // absent on most UVC cameras: fine
    set_control(V4L2_CID_GAIN, static_cast<std::int32_t>(std::lround(*options.gain)), "gain");
  }
}

void V4l2Source::start_streaming() {
  v4l2_requestbuffers request{};
  request.count = kBufferCount;
  request.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  request.memory = V4L2_MEMORY_MMAP;
  if (xioctl(fd_.get(), VIDIOC_REQBUFS, &request) != 0) {
    const int err = errno;
    if (err == EBUSY)
      throw InputError(info_.path + ": device is busy (another program is using the camera)");
    throw InputError(info_.path + ": cannot allocate capture buffers: " + errno_text(err));
  }
  if (request.count < 2)
    throw InputError(info_.path + ": driver gave fewer than 2 capture buffers");
  buffers_.resize(request.count);
  for (std::uint32_t i = 0; i < request.count; ++i) {
    v4l2_buffer buffer{};
    buffer.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    buffer.memory = V4L2_MEMORY_MMAP;
    buffer.index = i;
    if (xioctl(fd_.get(), VIDIOC_QUERYBUF, &buffer) != 0) {
      throw InputError(info_.path + ": VIDIOC_QUERYBUF failed: " + errno_text(errno));
    }
    void* start = ::mmap(nullptr, buffer.length, PROT_READ | PROT_WRITE, MAP_SHARED, fd_.get(),
                         buffer.m.offset);
    if (start == MAP_FAILED)
      throw InputError(info_.path + ": cannot map capture buffer: " + errno_text(errno));
    buffers_[i] = {start, buffer.length};
    if (xioctl(fd_.get(), VIDIOC_QBUF, &buffer) != 0) {
      throw InputError(info_.path + ": VIDIOC_QBUF failed: " + errno_text(errno));
    }
  }
  int type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  if (xioctl(fd_.get(), VIDIOC_STREAMON, &type) != 0) {
    const int err = errno;
    if (err == EBUSY)
      throw InputError(info_.path + ": device is busy (another program is using the camera)");
    // ENOSPC: the USB bus has no bandwidth left for this mode (another camera on the hub).
    if (err == ENOSPC)
      throw InputError(info_.path + ": not enough USB bandwidth for " + describe_mode(mode_) +
                       " (try MJPG or a smaller mode)");
    throw InputError(info_.path + ": cannot start streaming: " + errno_text(err));
  }
  streaming_ = true;
}

void V4l2Source::stop_streaming() noexcept {
  if (streaming_) {
    int type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    xioctl(fd_.get(), VIDIOC_STREAMOFF, &type);
    streaming_ = false;
  }
  for (auto& buffer : buffers_) {
    if (buffer.start != MAP_FAILED) ::munmap(buffer.start, buffer.length);
    buffer.start = MAP_FAILED;
  }
  buffers_.clear();
}

void V4l2Source::fail(const std::string& what) {
  failure_ = fmt::format("{}: {} after {} frames (frames already captured are kept)", info_.path,
                         what, stats_.delivered);
  stop_streaming();
  throw InputError(failure_);
}

cv::Mat V4l2Source::convert(const MappedBuffer& buffer, std::size_t bytes_used) const {
  const auto* data = static_cast<const std::uint8_t*>(buffer.start);
  if (bytes_used == 0 || bytes_used > buffer.length) bytes_used = buffer.length;
  if (mode_.fourcc == V4L2_PIX_FMT_YUYV) {
    return yuyv_to_bgr(data, bytes_used, mode_.width, mode_.height, bytes_per_line_);
  }
  return decode_mjpeg(data, bytes_used);
}

std::optional<Frame> V4l2Source::next() {
  if (!failure_.empty()) throw InputError(failure_);
  int bad_in_a_row = 0;
  for (;;) {
    pollfd pfd{fd_.get(), POLLIN, 0};
    const int ready = ::poll(&pfd, 1, kFrameTimeoutMs);
    if (ready < 0) {
      if (errno == EINTR) continue;
      fail("poll failed: " + errno_text(errno));
    }
    if (ready == 0) fail(fmt::format("no frame for {} s", kFrameTimeoutMs / 1000));
    // An unplugged camera wakes poll with POLLERR; DQBUF below tells ENODEV apart.
    const bool poll_error = (pfd.revents & (POLLERR | POLLHUP | POLLNVAL)) != 0;

    v4l2_buffer buffer{};
    buffer.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    buffer.memory = V4L2_MEMORY_MMAP;
    if (xioctl(fd_.get(), VIDIOC_DQBUF, &buffer) != 0) {
      const int err = errno;
      if (err == ENODEV) fail("camera was unplugged");
      if (err == EAGAIN && poll_error) fail("device reported an error while streaming");
      if (err == EAGAIN) continue;
      fail("VIDIOC_DQBUF failed: " + errno_text(err));
    }
    if (buffer.index >= buffers_.size()) fail("driver returned an unknown buffer");

    // Copy out of the driver's buffer before giving it back, so delivered frames own their
    // pixels and stay valid whatever happens to the device afterwards.
    cv::Mat image;
    if (!(buffer.flags & V4L2_BUF_FLAG_ERROR))
      image = convert(buffers_[buffer.index], buffer.bytesused);
    const auto driver_sequence = static_cast<std::int64_t>(buffer.sequence);
    const double stamp = static_cast<double>(buffer.timestamp.tv_sec) +
                         static_cast<double>(buffer.timestamp.tv_usec) * 1e-6;
    if (xioctl(fd_.get(), VIDIOC_QBUF, &buffer) != 0) {
      const int err = errno;
      if (err == ENODEV) fail("camera was unplugged");
      fail("VIDIOC_QBUF failed: " + errno_text(err));
    }

    if (image.empty()) {
      // A torn or undecodable frame is skipped: the gap it leaves in the sequence numbers
      // counts it as dropped. A stream of them means a fault.
      if (++bad_in_a_row >= kMaxBadFramesInARow)
        fail(fmt::format("{} frames in a row did not decode", bad_in_a_row));
      continue;
    }

    sequence_.observe(driver_sequence);
    Frame frame;
    frame.image = std::move(image);
    frame.sequence = sequence_.relative();
    // Driver timestamps are CLOCK_MONOTONIC on current kernels; a driver that leaves them
    // at zero gets the host's monotonic clock instead.
    const double now =
        stamp > 0
            ? stamp
            : std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
                  .count();
    if (!first_timestamp_s_) first_timestamp_s_ = now;
    frame.timestamp_s = now - *first_timestamp_s_;
    stats_.delivered += 1;
    stats_.dropped = sequence_.dropped();
    return frame;
  }
}

}  // namespace

std::unique_ptr<FrameSource> open_v4l2_source(const std::string& path,
                                              const SourceOptions& options) {
  return std::make_unique<V4l2Source>(path, options);
}

}  // namespace rostro::capture

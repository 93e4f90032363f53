#pragma once
// V4L2 devices through their ioctls: which /dev/video* nodes are capture devices, and the
// pixel formats, sizes and frame rates each offers (VIDIOC_ENUM_FMT, VIDIOC_ENUM_FRAMESIZES,
// VIDIOC_ENUM_FRAMEINTERVALS).

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "capture/capture_mode.hpp"

namespace rostro::capture {

struct V4l2DeviceInfo {
  std::string path;                        // /dev/videoN
  std::string card;                        // the driver's name for the camera
  std::string driver;                      // uvcvideo, ...
  std::string bus_info;                    // usb-0000:00:14.0-1, ...
  std::vector<CaptureMode> modes;          // every format x size x rate offered
  std::vector<std::string> other_formats;  // formats offered that rostro cannot decode
};

// An open file descriptor, closed on destruction.
class FileDescriptor {
 public:
  FileDescriptor() = default;
  explicit FileDescriptor(int fd) : fd_(fd) {}
  ~FileDescriptor();
  FileDescriptor(FileDescriptor&& other) noexcept : fd_(std::exchange(other.fd_, -1)) {}
  FileDescriptor& operator=(FileDescriptor&& other) noexcept;
  FileDescriptor(const FileDescriptor&) = delete;
  FileDescriptor& operator=(const FileDescriptor&) = delete;
  int get() const { return fd_; }

 private:
  int fd_ = -1;
};

// ioctl, retried when a signal interrupts it.
int xioctl(int fd, unsigned long request, void* arg);

// Opens `path` and checks that it is a V4L2 video capture device with streaming I/O.
// Throws InputError naming the device when it is missing, not accessible, not a V4L2
// device, or not a capture device. Fills the identity fields of `info` (not the modes).
FileDescriptor open_v4l2_capture_device(const std::string& path, V4l2DeviceInfo& info);

// Every mode the open device offers (discrete sizes and rates as listed; stepwise and
// continuous ranges sampled at common sizes and rates).
std::vector<CaptureMode> enumerate_modes(int fd, std::vector<std::string>* other_formats = nullptr);

// The common sizes (640x480, 1280x720, 1920x1080 ...) that fit a stepwise size range,
// plus its largest size. Pure, for stepwise/continuous VIDIOC_ENUM_FRAMESIZES results.
std::vector<std::pair<int, int>> sample_stepwise_sizes(int min_w, int max_w, int step_w, int min_h,
                                                       int max_h, int step_h);

// /dev/video* node names in `dir`, in natural order (video2 before video10).
std::vector<std::string> list_video_nodes(const std::string& dir = "/dev");

// The capture devices among /dev/video*, with their modes. Nodes that are not capture
// devices (metadata nodes, encoders) are skipped; nodes that cannot be opened are skipped
// and their reason is appended to `problems` when given.
std::vector<V4l2DeviceInfo> list_v4l2_devices(std::vector<std::string>* problems = nullptr);

// One device with its modes; throws InputError like open_v4l2_capture_device.
V4l2DeviceInfo query_v4l2_device(const std::string& path);

}  // namespace rostro::capture

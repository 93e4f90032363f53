#include "capture/v4l2_device.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <linux/videodev2.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <set>

#include "capture/pixel_convert.hpp"
#include "facecore/error.hpp"

namespace rostro::capture {
namespace {

std::string c_string(const std::uint8_t* text, std::size_t max) {
  return std::string(reinterpret_cast<const char*>(text),
                     strnlen(reinterpret_cast<const char*>(text), max));
}

// Rates tried inside a stepwise or continuous interval range.
constexpr double kCommonRates[] = {5, 10, 15, 24, 25, 30, 50, 60, 90, 120};

void add_interval(std::vector<CaptureMode>& modes, std::uint32_t fourcc, int w, int h,
                  std::uint32_t num, std::uint32_t den) {
  if (num == 0 || den == 0) return;
  CaptureMode mode{fourcc, w, h, num, den};
  if (std::find(modes.begin(), modes.end(), mode) == modes.end()) modes.push_back(mode);
}

void enumerate_intervals(int fd, std::uint32_t fourcc, int w, int h,
                         std::vector<CaptureMode>& modes) {
  v4l2_frmivalenum ival{};
  ival.pixel_format = fourcc;
  ival.width = static_cast<std::uint32_t>(w);
  ival.height = static_cast<std::uint32_t>(h);
  bool any = false;
  for (ival.index = 0; xioctl(fd, VIDIOC_ENUM_FRAMEINTERVALS, &ival) == 0; ++ival.index) {
    any = true;
    if (ival.type == V4L2_FRMIVAL_TYPE_DISCRETE) {
      add_interval(modes, fourcc, w, h, ival.discrete.numerator, ival.discrete.denominator);
      continue;
    }
    // Stepwise or continuous: the fastest and slowest rates, and common rates between.
    const auto& sw = ival.stepwise;
    add_interval(modes, fourcc, w, h, sw.min.numerator, sw.min.denominator);
    add_interval(modes, fourcc, w, h, sw.max.numerator, sw.max.denominator);
    if (sw.min.denominator == 0 || sw.max.denominator == 0) break;
    const double max_fps = static_cast<double>(sw.min.denominator) / sw.min.numerator;
    const double min_fps = static_cast<double>(sw.max.denominator) / sw.max.numerator;
    for (double rate : kCommonRates) {
      if (rate > min_fps && rate < max_fps) {
        add_interval(modes, fourcc, w, h, 1, static_cast<std::uint32_t>(rate));
      }
    }
    break;
  }
  // Drivers without VIDIOC_ENUM_FRAMEINTERVALS: report the size with an unknown rate
  // (interval 0/1 -> 0 fps) so it still shows; choose_mode treats it as slow.
  if (!any) modes.push_back(CaptureMode{fourcc, w, h, 1, 0});
}

}  // namespace

FileDescriptor::~FileDescriptor() {
  if (fd_ >= 0) ::close(fd_);
}

FileDescriptor& FileDescriptor::operator=(FileDescriptor&& other) noexcept {
  if (this != &other) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = std::exchange(other.fd_, -1);
  }
  return *this;
}

int xioctl(int fd, unsigned long request, void* arg) {
  int result;
  do {
    result = ::ioctl(fd, request, arg);
  } while (result == -1 && errno == EINTR);
  return result;
}

FileDescriptor open_v4l2_capture_device(const std::string& path, V4l2DeviceInfo& info) {
  FileDescriptor fd(::open(path.c_str(), O_RDWR | O_NONBLOCK | O_CLOEXEC));
  if (fd.get() < 0) {
    const int err = errno;
    switch (err) {
      case ENOENT:
        throw InputError(
            path + ": no such device (is the camera plugged in? 'rostro devices' lists cameras)");
      case EACCES:
      case EPERM:
        throw InputError(path + ": permission denied (add your user to the 'video' group)");
      case EBUSY:
        throw InputError(path + ": device is busy (another program is using the camera)");
      default:
        throw InputError(path + ": cannot open device: " + std::strerror(err));
    }
  }
  v4l2_capability cap{};
  if (xioctl(fd.get(), VIDIOC_QUERYCAP, &cap) != 0) {
    const int err = errno;
    if (err == ENODEV) throw InputError(path + ": device was unplugged");
    throw InputError(path + ": not a V4L2 device (VIDIOC_QUERYCAP failed: " + std::strerror(err) +
                     ")");
  }
  info.path = path;
  info.card = c_string(cap.card, sizeof cap.card);
  info.driver = c_string(cap.driver, sizeof cap.driver);
  info.bus_info = c_string(cap.bus_info, sizeof cap.bus_info);
  const std::uint32_t caps =
      (cap.capabilities & V4L2_CAP_DEVICE_CAPS) ? cap.device_caps : cap.capabilities;
  if (!(caps & V4L2_CAP_VIDEO_CAPTURE)) {
    throw InputError(fmt::format(
        "{}: V4L2 device '{}' is not a video capture device (a camera's metadata or output node? "
        "'rostro devices' lists the capture nodes)",
        path, info.card));
  }
  if (!(caps & V4L2_CAP_STREAMING)) {
    throw InputError(
        fmt::format("{}: V4L2 device '{}' does not support streaming I/O (mmap)", path, info.card));
  }
  return fd;
}

std::vector<std::pair<int, int>> sample_stepwise_sizes(int min_w, int max_w, int step_w, int min_h,
                                                       int max_h, int step_h) {
  static constexpr std::pair<int, int> kCommonSizes[] = {
      {320, 240},  {640, 360},  {640, 480},   {800, 600},   {960, 540},   {1024, 768},
      {1280, 720}, {1280, 960}, {1600, 1200}, {1920, 1080}, {2560, 1440}, {3840, 2160}};
  auto fits = [](int v, int lo, int hi, int step) {
    return v >= lo && v <= hi && (step <= 1 || (v - lo) % step == 0);
  };
  std::vector<std::pair<int, int>> sizes;
  for (const auto& [w, h] : kCommonSizes) {
    if (fits(w, min_w, max_w, step_w) && fits(h, min_h, max_h, step_h)) sizes.emplace_back(w, h);
  }
  if (max_w > 0 && max_h > 0 &&
      std::find(sizes.begin(), sizes.end(), std::pair{max_w, max_h}) == sizes.end()) {
    sizes.emplace_back(max_w, max_h);
  }
  return sizes;
}

std::vector<CaptureMode> enumerate_modes(int fd, std::vector<std::string>* other_formats) {
  std::vector<CaptureMode> modes;
  v4l2_fmtdesc desc{};
  desc.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  for (desc.index = 0; xioctl(fd, VIDIOC_ENUM_FMT, &desc) == 0; ++desc.index) {
    const std::uint32_t fourcc = desc.pixelformat;
    if (!is_decodable_format(fourcc)) {
      if (other_formats) other_formats->push_back(fourcc_to_string(fourcc));
      continue;
    }
    v4l2_frmsizeenum size{};
    size.pixel_format = fourcc;
    for (size.index = 0; xioctl(fd, VIDIOC_ENUM_FRAMESIZES, &size) == 0; ++size.index) {
      if (size.type == V4L2_FRMSIZE_TYPE_DISCRETE) {
        enumerate_intervals(fd, fourcc, static_cast<int>(size.discrete.width),
                            static_cast<int>(size.discrete.height), modes);
        continue;
      }
      const auto& sw = size.stepwise;
      for (const auto& [w, h] : sample_stepwise_sizes(
               static_cast<int>(sw.min_width), static_cast<int>(sw.max_width),
               static_cast<int>(sw.step_width), static_cast<int>(sw.min_height),
               static_cast<int>(sw.max_height), static_cast<int>(sw.step_height))) {
        enumerate_intervals(fd, fourcc, w, h, modes);
      }
      break;
    }
  }
  return modes;
}

std::vector<std::string> list_video_nodes(const std::string& dir) {
  std::vector<std::pair<long, std::string>> nodes;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("video", 0) != 0 || name.size() == 5) continue;
    const std::string digits = name.substr(5);
    if (!std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; }))
      continue;
    nodes.emplace_back(std::stol(digits), entry.path().string());
  }
  std::sort(nodes.begin(), nodes.end());
  std::vector<std::string> paths;
  for (auto& node : nodes) paths.push_back(std::move(node.second));
  return paths;
}

V4l2DeviceInfo query_v4l2_device(const std::string& path) {
  V4l2DeviceInfo info;
  const FileDescriptor fd = open_v4l2_capture_device(path, info);
  info.modes = enumerate_modes(fd.get(), &info.other_formats);
  return info;
}

std::vector<V4l2DeviceInfo> list_v4l2_devices(std::vector<std::string>* problems) {
  std::vector<V4l2DeviceInfo> devices;
  for (const auto& path : list_video_nodes()) {
    V4l2DeviceInfo info;
    try {
      const FileDescriptor fd = open_v4l2_capture_device(path, info);
      info.modes = enumerate_modes(fd.get(), &info.other_formats);
      devices.push_back(std::move(info));
    } catch (const InputError& e) {
      // Metadata and output nodes are not cameras: leave them out quietly.
      const std::string what = e.what();
      if (problems && what.find("not a video capture device") == std::string::npos)
        problems->push_back(what);
    }
  }
  return devices;
}

}  // namespace rostro::capture

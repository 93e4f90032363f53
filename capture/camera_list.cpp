#include "capture/camera_list.hpp"

#include <fmt/format.h>

#include <cmath>
#include <map>

#include "capture/pixel_convert.hpp"

namespace rostro::capture {

CameraList list_cameras() {
  CameraList list;
  list.v4l2 = list_v4l2_devices(&list.problems);
  list.libcamera_built = libcamera_built();
  if (list.libcamera_built) {
    try {
      list.libcamera = list_libcamera_cameras();
    } catch (const std::exception& e) {
      list.problems.push_back(e.what());
    }
  }
  return list;
}

namespace {

std::string format_rate(double fps) {
  if (fps <= 0) return "?";
  return fmt::format("{:g}", std::round(fps * 100.0) / 100.0);
}

void format_v4l2(std::string& out, const V4l2DeviceInfo& device) {
  out += fmt::format("{}  {} ({}, {})\n", device.path, device.card, device.driver, device.bus_info);
  // pixel format -> size -> rates, in the order the driver listed them
  std::vector<std::uint32_t> format_order;
  std::map<std::uint32_t, std::vector<std::pair<std::pair<int, int>, std::vector<double>>>>
      by_format;
  for (const auto& mode : device.modes) {
    auto& sizes = by_format[mode.fourcc];
    if (sizes.empty()) format_order.push_back(mode.fourcc);
    const std::pair<int, int> size{mode.width, mode.height};
    auto it =
        std::find_if(sizes.begin(), sizes.end(), [&](const auto& s) { return s.first == size; });
    if (it == sizes.end()) it = sizes.insert(sizes.end(), {size, {}});
    it->second.push_back(mode.fps());
  }
  for (const auto fourcc : format_order) {
    out += fmt::format("    {}:\n", fourcc_to_string(fourcc));
    for (const auto& [size, rates] : by_format[fourcc]) {
      std::string rate_text;
      for (const double r : rates) rate_text += (rate_text.empty() ? "" : ", ") + format_rate(r);
      out += fmt::format("      {}x{} @ {} fps\n", size.first, size.second, rate_text);
    }
  }
  if (device.modes.empty()) out += "    (no YUYV or MJPEG mode: rostro cannot read this device)\n";
  if (!device.other_formats.empty()) {
    std::string names;
    for (const auto& name : device.other_formats) names += (names.empty() ? "" : ", ") + name;
    out += fmt::format("    also offers {} (not used by rostro)\n", names);
  }
}

void format_libcamera(std::string& out, std::size_t index, const LibcameraCameraInfo& camera) {
  out +=
      fmt::format("libcamera:{}  {}{}{}\n", index, camera.model.empty() ? "camera" : camera.model,
                  camera.location.empty() ? "" : " (" + camera.location + ")", "");
  out += fmt::format("    id: {}\n", camera.id);
  if (camera.max_fps > 0) {
    out += fmt::format("    frame rate {}..{} fps\n", format_rate(camera.min_fps),
                       format_rate(camera.max_fps));
  }
  std::vector<std::string> format_order;
  std::map<std::string, std::string> sizes;
  for (const auto& mode : camera.modes) {
    if (!sizes.count(mode.pixel_format)) format_order.push_back(mode.pixel_format);
    auto& text = sizes[mode.pixel_format];
    text += fmt::format("{}{}x{}", text.empty() ? "" : ", ", mode.width, mode.height);
  }
  for (const auto& format : format_order) out += fmt::format("    {}: {}\n", format, sizes[format]);
}

}  // namespace

std::string format_camera_list(const CameraList& list) {
  std::string out;
  if (list.v4l2.empty()) {
    out += "V4L2: no video capture devices found (/dev/video*)\n";
  } else {
    out += "V4L2 cameras (open with the path):\n";
    for (const auto& device : list.v4l2) format_v4l2(out, device);
  }
  if (!list.libcamera_built) {
    out += "libcamera: not built into this rostro\n";
  } else if (list.libcamera.empty()) {
    out += "libcamera: no cameras found\n";
  } else {
    out += "libcamera cameras (open with libcamera:<index> or libcamera:<id>):\n";
    for (std::size_t i = 0; i < list.libcamera.size(); ++i)
      format_libcamera(out, i, list.libcamera[i]);
  }
  for (const auto& problem : list.problems) out += "note: " + problem + "\n";
  if (list.empty())
    out += "No cameras found. Video files and image folders can still be used as sources.\n";
  return out;
}

}  // namespace rostro::capture

#include "capture/capture_mode.hpp"

#include <fmt/format.h>
#include <linux/videodev2.h>

#include <algorithm>
#include <cmath>
#include <tuple>

#include "capture/pixel_convert.hpp"

namespace rostro::capture {
namespace {

constexpr double kDefaultMinFps = 25.0;
constexpr long kDefaultMaxArea = 1920L * 1080L;

bool fps_matches(double offered, double requested) {
  return std::abs(offered - requested) <= 0.01 * requested;
}

// Lower is better; compared lexicographically.
struct ModeScore {
  int misses_rate;    // 0 when the mode reaches the wanted rate
  int over_area_cap;  // 0 when within the default size cap (or a size was requested)
  long area_key;      // -area within the cap (largest first), +area above it
  double rate_key;    // -fps, or distance to the requested fps
  int format_rank;    // YUYV before MJPEG

  auto tie() const { return std::tie(misses_rate, over_area_cap, area_key, rate_key, format_rank); }
};

ModeScore score(const CaptureMode& mode, const ModeRequest& request) {
  const double wanted_fps = request.fps > 0 ? request.fps : kDefaultMinFps;
  const bool size_requested = request.width > 0 || request.height > 0;
  const long area = static_cast<long>(mode.width) * mode.height;
  ModeScore s{};
  s.misses_rate = mode.fps() >= wanted_fps * 0.99 ? 0 : 1;
  s.over_area_cap = (!size_requested && area > kDefaultMaxArea) ? 1 : 0;
  s.area_key = s.over_area_cap ? area : -area;
  s.rate_key = request.fps > 0 ? std::abs(mode.fps() - request.fps) : -mode.fps();
  s.format_rank = mode.fourcc == V4L2_PIX_FMT_YUYV ? 0 : 1;
  return s;
}

}  // namespace

bool is_decodable_format(std::uint32_t fourcc) {
  return fourcc == V4L2_PIX_FMT_YUYV || fourcc == V4L2_PIX_FMT_MJPEG || fourcc == V4L2_PIX_FMT_JPEG;
}

std::optional<CaptureMode> choose_mode(const std::vector<CaptureMode>& modes,
                                       const ModeRequest& request) {
  std::optional<std::uint32_t> wanted_format;
  if (!request.pixel_format.empty()) {
    wanted_format = fourcc_from_string(request.pixel_format);
  }
  std::optional<CaptureMode> best;
  ModeScore best_score{};
  for (const auto& mode : modes) {
    if (!is_decodable_format(mode.fourcc)) continue;
    if (wanted_format && mode.fourcc != *wanted_format &&
        !(*wanted_format == V4L2_PIX_FMT_MJPEG && mode.fourcc == V4L2_PIX_FMT_JPEG)) {
      continue;
    }
    if (request.width > 0 && mode.width != request.width) continue;
    if (request.height > 0 && mode.height != request.height) continue;
    if (request.fps > 0 && !fps_matches(mode.fps(), request.fps)) continue;
    const ModeScore s = score(mode, request);
    if (!best || s.tie() < best_score.tie()) {
      best = mode;
      best_score = s;
    }
  }
  return best;
}

std::string describe_mode(const CaptureMode& mode) {
  return fmt::format("{} {}x{} @ {:g} fps", fourcc_to_string(mode.fourcc), mode.width, mode.height,
                     std::round(mode.fps() * 100.0) / 100.0);
}

std::string describe_request(const ModeRequest& request) {
  std::string text;
  if (!request.pixel_format.empty()) text += request.pixel_format + " ";
  if (request.width > 0 || request.height > 0) {
    text += fmt::format("{}x{} ", request.width > 0 ? std::to_string(request.width) : "*",
                        request.height > 0 ? std::to_string(request.height) : "*");
  }
  if (request.fps > 0) text += fmt::format("@ {:g} fps ", request.fps);
  if (text.empty()) return "any mode";
  text.pop_back();
  return text;
}

}  // namespace rostro::capture

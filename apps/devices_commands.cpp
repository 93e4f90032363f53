// `rostro devices`: the cameras rostro can open (V4L2 and libcamera) and their modes, and
// an optional short test read from any source.

#include <fmt/format.h>

#include <cstdio>
#include <optional>
#include <string>

#include "apps/commands.hpp"
#include "capture/camera_list.hpp"
#include "capture/open_source.hpp"
#include "capture/v4l2_device.hpp"

namespace rostro::app {
namespace {

struct DevicesArgs {
  std::string device;  // list only this V4L2 device
  std::string probe;   // read frames from this source spec
  long frames = 60;
  capture::SourceOptions options;
  std::optional<double> exposure, gain;
};

void list(const DevicesArgs& args) {
  capture::CameraList cameras;
  if (!args.device.empty()) {
    cameras.v4l2.push_back(capture::query_v4l2_device(args.device));  // throws InputError
    cameras.libcamera_built = capture::libcamera_built();
    cameras.libcamera = capture::list_libcamera_cameras();
  } else {
    cameras = capture::list_cameras();
  }
  std::fputs(capture::format_camera_list(cameras).c_str(), stdout);
}

// Opens a source, reads a few frames and reports what came out: the quickest check that
// a camera, its mode and its exposure settings work.
void probe(const DevicesArgs& args) {
  capture::SourceOptions options = args.options;
  options.exposure = args.exposure;
  options.gain = args.gain;
  auto source = capture::open_frame_source(args.probe, options);
  std::printf("%s\n", source->description().c_str());
  long read = 0;
  double first = 0, last = 0;
  while (read < args.frames) {
    auto frame = source->next();
    if (!frame) break;
    if (read == 0) first = frame->timestamp_s;
    last = frame->timestamp_s;
    ++read;
  }
  const auto stats = source->stats();
  const double span = last - first;
  std::printf("%ld frames, %ld dropped, %dx%d, %.3f s of timestamps (%.2f fps measured)\n",
              static_cast<long>(stats.delivered), static_cast<long>(stats.dropped),
              source->frame_size().width, source->frame_size().height, span,
              read > 1 && span > 0 ? static_cast<double>(read - 1) / span : 0.0);
}

}  // namespace

void add_devices_commands(CLI::App& app) {
  static DevicesArgs args;
  CLI::App* cmd = app.add_subcommand(
      "devices",
      "List cameras (V4L2 and libcamera) with their pixel formats, sizes and frame rates");
  cmd->add_option("--device", args.device, "List only this V4L2 device (/dev/videoN)");
  cmd->add_option("--probe", args.probe,
                  "Open this source (/dev/videoN, libcamera:N, a video file or an image folder), "
                  "read frames and report count, drops and rate");
  cmd->add_option("--frames", args.frames, "Frames to read with --probe")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--width", args.options.width, "With --probe: frame width")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--height", args.options.height, "With --probe: frame height")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--fps", args.options.fps, "With --probe: frame rate")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--pixel-format", args.options.pixel_format, "With --probe: MJPG or YUYV");
  cmd->add_option("--exposure", args.exposure, "With --probe: fixed exposure (V4L2 units, 100 us)");
  cmd->add_option("--gain", args.gain, "With --probe: fixed gain (driver units)");
  cmd->footer(
      "With no camera it says so and exits 0.\n\n"
      "Example:\n  rostro devices\n  rostro devices --probe /dev/video0 --width 1280 --height 720 "
      "--fps 30 "
      "--exposure 80");
  cmd->callback([] {
    if (!args.probe.empty()) {
      probe(args);
    } else {
      list(args);
    }
  });
}

}  // namespace rostro::app

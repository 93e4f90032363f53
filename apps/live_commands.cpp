// `rostro live`: the webcam (or a video played in real time) -> tracking -> fit -> FAPs, sent
// to VMC receivers and as raw FAP frames, with a window showing the camera and the head.
// Wiring only: the pipeline lives in live/.

#include <atomic>
#include <chrono>
#include <cstdio>
#include <optional>
#include <string>
#include <thread>

#include "apps/checks.hpp"
#include "apps/commands.hpp"
#include "apps/face_trackers.hpp"
#include "apps/interrupt.hpp"
#include "calib/camera_intrinsics.hpp"
#include "facecore/error.hpp"
#include "live/live_window.hpp"
#include "live/pipeline.hpp"
#include "mapping/fap_mapper.hpp"
#include "tracking/layout.hpp"

namespace rostro::app {
namespace {

struct LiveArgs {
  FaceTrackerArgs face;
  std::string camera, actor, intrinsics, vmc, fap_udp, record, method = "ceres";
  std::string vmc_names = "apple";
  bool headless = false;
  bool no_hierarchy = false;
  double calibration_seconds = 1.0;
};

void run_live(const LiveArgs& a) {
  check_seconds(a.calibration_seconds, "--calibration-seconds");
  live::PipelineOptions o;
  o.camera = a.camera;
  o.layout = a.face.make_layout();
  o.make_tracker = [&a] { return a.face.make(); };
  if (!a.actor.empty()) o.actor = calib::read_actor_profile(a.actor);
  if (!a.intrinsics.empty()) o.intrinsics = calib::read_intrinsics(a.intrinsics);
  o.calibration_seconds = a.calibration_seconds;
  o.mapper.method = mapping::parse_method(a.method);
  if (!a.no_hierarchy) o.mapper.hierarchy = mapping::default_hierarchy();
  if (!a.vmc.empty()) {
    const live::UdpTarget t = live::parse_host_port(a.vmc, "--vmc");
    live::VmcOptions vmc;
    vmc.host = t.host;
    vmc.port = t.port;
    if (a.vmc_names != "apple" && a.vmc_names != "perfect-sync")
      throw InputError("--vmc-names " + a.vmc_names + ": expected 'apple' or 'perfect-sync'");
    vmc.pascal_case_names = a.vmc_names == "perfect-sync";
    o.vmc = vmc;
  }
  if (!a.fap_udp.empty()) o.fap_udp = live::parse_host_port(a.fap_udp, "--fap-udp");
  o.record = a.record;

  live::Pipeline pipeline(std::move(o));
  // The window first: without a display, that is the one line the user sees.
  std::optional<live::LiveWindow> window;
  if (!a.headless) window.emplace(pipeline, "rostro live: " + a.camera);
  if (a.actor.empty())
    std::fprintf(stderr,
                 "rostro live: no --actor given: the first %.1f s calibrate the actor; hold a "
                 "neutral face\n",
                 a.calibration_seconds);
  // Ctrl-C ends the run cleanly: a watcher polls the flag the signal handler sets and
  // stops the pipeline, which then prints its figures and closes any recording.
  InterruptScope interrupt;
  std::atomic<bool> finished{false};
  std::thread watcher([&] {
    while (!finished) {
      if (interrupt.requested()) {
        pipeline.stop();
        break;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
  });
  live::PipelineReport report;
  try {
    report = pipeline.run(window ? &*window : nullptr);
  } catch (...) {
    finished = true;
    watcher.join();
    throw;
  }
  finished = true;
  watcher.join();
  std::printf("%s", report.summary().c_str());
  for (const auto& take : report.recordings) std::printf("recorded %s\n", take.c_str());
  if (report.failure) throw InputError(*report.failure);
}

}  // namespace

void add_live_commands(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "live", "Live puppetry: track a webcam, animate the head, stream VMC and FAPs");
  static LiveArgs a;
  cmd->add_option("--camera", a.camera,
                  "/dev/videoN, libcamera:N, or a video file (played at its frame rate)")
      ->required();
  a.face.add_options(cmd, true);
  cmd->add_option("--actor", a.actor,
                  "Actor profile (default: calibrate from the first second, held neutral)");
  cmd->add_option("--intrinsics", a.intrinsics, "Camera intrinsics (OpenCV FileStorage)");
  cmd->add_option("--vmc", a.vmc, "Send VMC (OSC) to host:port, e.g. 127.0.0.1:39539");
  cmd->add_option("--vmc-names", a.vmc_names,
                  "blend shape names: 'apple' (eyeBlinkLeft) or 'perfect-sync' (EyeBlinkLeft)")
      ->capture_default_str();
  cmd->add_option("--fap-udp", a.fap_udp, "Send raw FAP frames over UDP to host:port");
  cmd->add_option("--record", a.record, "Record the FAPs to this .fap (R toggles in the window)");
  cmd->add_flag("--headless", a.headless, "No window: run until the source ends or Ctrl-C");
  cmd->add_option("--method", a.method, "ceres or seed2d")->capture_default_str();
  cmd->add_flag("--no-hierarchy", a.no_hierarchy, "Send only the measured FAPs");
  cmd->add_option("--calibration-seconds", a.calibration_seconds,
                  "Neutral seconds used when no --actor is given")
      ->capture_default_str();
  cmd->footer(
      "Window keys: C calibrate neutral now, R start/stop recording, T reset tracking, Q quit.\n"
      "Per-stage p50/p99 times and the capture-to-output delay are printed at exit.\n\n"
      "Example:\n  rostro live --camera /dev/video0 --layout data/layouts/default.json "
      "--vmc 127.0.0.1:39539\n  rostro live --camera take.mp4 --layout "
      "data/layouts/default.json --headless --fap-udp :9000 --record live.fap\n"
      "  rostro live --camera /dev/video0 --markerless --vmc 127.0.0.1:39539");
  cmd->callback([] { run_live(a); });
}

}  // namespace rostro::app

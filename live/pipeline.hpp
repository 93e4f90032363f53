#pragma once
// The live path in threads, newest frame wins at every hand-off (live/latest_slot.hpp):
//
//   capture thread      source -> frame (a video file is played at its own frame rate)
//        | LatestSlot
//   processing thread   tracking -> (calibration while there is no profile) -> Ceres fit
//                       -> hierarchy -> FAPs -> VMC, raw FAP UDP, .fap recording
//        | LatestSlot
//   the caller's thread (run)   deformation -> offscreen head render -> view (the window)
//
// The outputs go out on the processing thread, right after the fit, so the delay from a
// frame's capture to its FAP leaving rostro never waits for rendering. Rendering runs only
// with a view or `render_head`; a slow window skips frames instead of delaying the outputs.

#include <atomic>
#include <filesystem>
#include <functional>
#include <memory>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "calib/actor_profile.hpp"
#include "capture/open_source.hpp"
#include "live/latency_stats.hpp"
#include "live/vmc_sender.hpp"
#include "mapping/fap_mapper.hpp"
#include "tracking/face_tracker.hpp"
#include "tracking/layout.hpp"

namespace rostro::live {

struct UdpTarget {
  std::string host = "127.0.0.1";
  int port = 0;
};

// "host:port" or ":port" (host 127.0.0.1); throws InputError naming `what` otherwise.
UdpTarget parse_host_port(const std::string& text, const std::string& what);

struct PipelineOptions {
  std::string camera;  // /dev/videoN, libcamera:N, a video file or an image folder
  capture::SourceOptions source;
  tracking::MarkerLayout layout;
  // Makes the face tracker (again after a reset); empty: a MarkerTracker on `layout`. A
  // LandmarkTracker here tracks a bare face; its layout() then replaces `layout`.
  std::function<std::unique_ptr<tracking::FaceTracker>()> make_tracker;
  std::optional<calib::ActorProfile> actor;           // none: calibrate from the first frames
  std::optional<calib::CameraIntrinsics> intrinsics;  // none: the profile's, else a default
  double calibration_seconds = 1.0;
  mapping::MapperOptions mapper;
  std::optional<VmcOptions> vmc;
  std::optional<UdpTarget> fap_udp;
  std::filesystem::path record;  // a .fap recorded from the start; empty: none until asked
  // Play a file source at its frame rate (as a camera would deliver it). Unset: files and
  // image folders are paced, devices are not (they pace themselves).
  std::optional<bool> real_time;
  bool render_head = false;                     // render the head even without a view (benchmarks)
  int view_height = 480;                        // the head image's size in the view, square
  std::function<void(const std::string&)> log;  // progress notes; default: stderr
};

// One shown frame: the camera image with its markers beside the animated head, and the
// stage figures and key help written on it.
struct ViewFrame {
  cv::Mat image;  // BGR
  long frame = 0;
};

// Where the composited view goes (the window). Called on run()'s thread.
class LiveView {
 public:
  virtual ~LiveView() = default;
  virtual void show(const ViewFrame& frame) = 0;
  // Handles window events; false once the user asked to quit.
  virtual bool poll() = 0;
};

struct StageStats {
  LatencyStats capture, tracking, fit, deformation, render;
  LatencyStats processing;  // tracking + fit + sending, per frame
  LatencyStats delay;       // capture timestamp -> FAP sent
};

struct PipelineReport {
  long frames_captured = 0;
  long frames_calibration = 0;  // used for calibration, not output
  long frames_output = 0;       // FAP frames sent (one VMC bundle and one datagram each)
  long frames_rendered = 0;
  long skipped_processing = 0;  // newest-wins drops before processing
  long skipped_render = 0;
  long dropped_by_source = 0;
  std::vector<std::filesystem::path> recordings;
  std::string source;
  std::optional<std::string> failure;  // a device lost mid-run, a network error
  StageStats stats;
  // "capture p50 .. p99 .." lines and the frame counts, for printing at exit.
  std::string summary() const;
};

class Pipeline {
 public:
  // Opens the source and the outputs; throws InputError for a bad source, address or file.
  explicit Pipeline(PipelineOptions options);
  ~Pipeline();
  Pipeline(const Pipeline&) = delete;
  Pipeline& operator=(const Pipeline&) = delete;

  // Runs until the source ends, stop() or the view's quit; renders on this thread.
  PipelineReport run(LiveView* view = nullptr);

  // Thread-safe controls (the window's keys).
  void stop();
  void calibrate_now();     // the next calibration_seconds of frames are the new neutral
  void toggle_recording();  // starts a new .fap or finishes the current one
  void reset_tracking();    // re-identify the markers from the next frame

  std::string status() const;  // "calibrating", "recording take.fap", ...

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rostro::live

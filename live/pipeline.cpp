#include "live/pipeline.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cstdio>
#include <mutex>
#include <opencv2/imgproc.hpp>
#include <thread>

#include "calib/actor_calibration.hpp"
#include "calib/actor_prior.hpp"
#include "calib/neutral_motion.hpp"
#include "facecore/error.hpp"
#include "facecore/expression_library.hpp"
#include "facecore/face_model.hpp"
#include "facecore/fap_io.hpp"
#include "live/fap_udp_sender.hpp"
#include "live/latest_slot.hpp"
#include "render/face_renderer.hpp"
#include "render/preview.hpp"
#include "render/render_error.hpp"
#include "tracking/marker_tracker.hpp"
#include "tracking/overlay.hpp"

namespace rostro::live {

namespace {

using Clock = std::chrono::steady_clock;

double ms_between(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}

struct Captured {
  cv::Mat image;
  double timestamp_s = 0;
  std::int64_t sequence = 0;
  Clock::time_point captured;  // when the frame became available to rostro
};

struct Shown {
  cv::Mat image;
  tracking::TrackedFrame tracked;
  FapFrame faps;
};

// take.fap, take-2.fap, take-3.fap, ...
std::filesystem::path take_path(const std::filesystem::path& first, int take) {
  if (take <= 1) return first;
  std::filesystem::path p = first;
  p.replace_filename(first.stem().string() + "-" + std::to_string(take) +
                     first.extension().string());
  return p;
}

}  // namespace

UdpTarget parse_host_port(const std::string& text, const std::string& what) {
  const auto colon = text.rfind(':');
  UdpTarget t;
  if (colon == std::string::npos)
    throw InputError(what + " '" + text + "': expected host:port, e.g. 127.0.0.1:39539");
  if (colon > 0) t.host = text.substr(0, colon);
  try {
    std::size_t used = 0;
    t.port = std::stoi(text.substr(colon + 1), &used);
    if (used != text.size() - colon - 1) t.port = -1;
  } catch (const std::exception&) {
    t.port = -1;
  }
  if (t.port <= 0 || t.port > 65535)
    throw InputError(what + " '" + text + "': the port must be a number in 1..65535");
  return t;
}

std::string PipelineReport::summary() const {
  std::string s;
  for (const auto& [name, stat] :
       {std::pair<const char*, const LatencyStats*>{"capture", &stats.capture},
        {"tracking", &stats.tracking},
        {"fit", &stats.fit},
        {"deformation", &stats.deformation},
        {"render", &stats.render},
        {"processing", &stats.processing},
        {"capture->output", &stats.delay}}) {
    if (stat->count() > 0) s += stat->summary(name) + "\n";
  }
  s += fmt::format(
      "frames: {} captured, {} for calibration, {} sent, {} rendered; skipped {} before "
      "processing, {} before rendering; {} dropped by the source\n",
      frames_captured, frames_calibration, frames_output, frames_rendered, skipped_processing,
      skipped_render, dropped_by_source);
  return s;
}

struct Pipeline::Impl {
  PipelineOptions o;
  std::unique_ptr<capture::FrameSource> source;
  double fps = 25;
  cv::Size size;
  bool paced = false;
  std::unique_ptr<VmcSender> vmc;
  std::unique_ptr<FapUdpSender> udp;

  LatestSlot<Captured> frames;
  LatestSlot<Shown> shown;
  bool rendering = false;

  std::atomic<bool> stopping{false};
  std::atomic<bool> want_calibration{false};
  std::atomic<bool> want_record_toggle{false};
  std::atomic<bool> want_reset{false};

  mutable std::mutex mutex;  // guards report (and its stats) and status_text
  PipelineReport report;
  std::string status_text;

  // Processing thread state.
  calib::ActorPrior prior;
  std::unique_ptr<tracking::FaceTracker> tracker;
  std::unique_ptr<tracking::FaceTracker> new_tracker() const {
    return o.make_tracker ? o.make_tracker() : std::make_unique<tracking::MarkerTracker>(o.layout);
  }
  std::unique_ptr<mapping::FapMapper> mapper;
  std::vector<tracking::TrackedFrame> neutral;
  bool calibrating = false;
  std::unique_ptr<FapSink> recording;
  std::filesystem::path recording_path;
  std::int64_t take_first_sequence = 0;
  long take_written = 0;
  FapFrame last_recorded;
  int takes = 0;

  void log(const std::string& text) const {
    if (o.log)
      o.log(text);
    else
      std::fprintf(stderr, "rostro live: %s\n", text.c_str());
  }
  void set_status(std::string text) {
    std::lock_guard lock(mutex);
    status_text = std::move(text);
  }
  void fail(const std::string& what) {
    std::lock_guard lock(mutex);
    if (!report.failure) report.failure = what;
  }

  void capture_loop();
  void processing_loop();
  void process(Captured& c);
  void finish_calibration();
  void start_recording();
  // After a failure (a full disk, a lost network) the take so far is kept as
  // NAME.partial.fap, so that a failed run is never mistaken for a finished take.
  void stop_recording(bool failed = false);
  void record(const FapFrame& faps, std::int64_t sequence);
  void render_loop(LiveView* view);
};

void Pipeline::Impl::capture_loop() {
  try {
    std::optional<Clock::time_point> start;
    double first_ts = 0;
    while (!stopping) {
      const auto before = Clock::now();
      auto f = source->next();
      const auto after = Clock::now();
      if (!f) break;
      if (paced) {
        // A file plays as a camera would deliver it: frame k at its container time.
        if (!start) {
          start = after;
          first_ts = f->timestamp_s;
        }
        std::this_thread::sleep_until(
            *start + std::chrono::duration_cast<Clock::duration>(
                         std::chrono::duration<double>(f->timestamp_s - first_ts)));
      }
      {
        std::lock_guard lock(mutex);
        report.stats.capture.add(ms_between(before, after));
        ++report.frames_captured;
      }
      frames.put(Captured{std::move(f->image), f->timestamp_s, f->sequence, Clock::now()});
    }
  } catch (const InputError& e) {
    fail(e.what());  // a camera unplugged: stop cleanly, keeping what was recorded
  }
  frames.close();
}

void Pipeline::Impl::finish_calibration() {
  const calib::CameraIntrinsics camera =
      o.intrinsics ? *o.intrinsics : calib::default_intrinsics(size);
  try {
    calib::ActorProfile profile = calib::calibrate_actor(
        neutral, camera, calib::actor_calibration_options(tracker->layout(), prior, "live actor"));
    mapper = mapping::make_fap_mapper(profile, o.mapper);
    calibrating = false;
    if (const std::string moving =
            calib::neutral_motion_warning(calib::measure_neutral_motion(neutral));
        !moving.empty())
      log("warning: " + moving + " (press C to calibrate again)");
    log(fmt::format("calibrated the actor from {} frames ({:.1f} s), assumed neutral{}",
                    neutral.size(), o.calibration_seconds,
                    o.intrinsics ? "" : ", with default camera intrinsics"));
    set_status("tracking");
  } catch (const InputError& e) {
    // Live: the actor may simply not be in view yet. Try again with the next frames.
    log(std::string("calibration failed, trying again: ") + e.what());
  }
  neutral.clear();
}

void Pipeline::Impl::start_recording() {
  ++takes;
  const std::filesystem::path first = o.record.empty() ? "live-take.fap" : o.record;
  recording_path = take_path(first, takes);
  FapHeader header;
  header.name = "rostro-live";
  header.fps = fps;
  recording = open_fap_sink(recording_path, header);
  take_written = 0;
  log("recording " + recording_path.string());
}

void Pipeline::Impl::stop_recording(bool failed) {
  if (!recording) return;
  std::filesystem::path kept = recording_path;
  if (failed) {
    kept = recording_path.parent_path() /
           (recording_path.stem().string() + ".partial" + recording_path.extension().string());
    recording->finish_as(kept);
  } else {
    recording->finish();
  }
  log(fmt::format("{}: {} frames", kept.string(), recording->frames_written()));
  if (const std::string why = recording->xface_warning(); !why.empty())
    log("warning: " + kept.string() + ": " + why);
  std::lock_guard lock(mutex);
  report.recordings.push_back(kept);
  recording.reset();
}

void Pipeline::Impl::record(const FapFrame& faps, std::int64_t sequence) {
  // Frames skipped by the newest-wins hand-off are filled with the previous frame, so the
  // take keeps the camera's timing at its nominal frame rate.
  if (take_written == 0) take_first_sequence = sequence;
  const long due = static_cast<long>(sequence - take_first_sequence);
  while (take_written > 0 && take_written < due) {
    FapFrame fill = last_recorded;
    fill.index = take_written;
    fill.time_s = static_cast<double>(take_written) / fps;
    recording->write(fill);
    ++take_written;
  }
  last_recorded = faps;
  last_recorded.index = take_written;
  last_recorded.time_s = static_cast<double>(take_written) / fps;
  recording->write(last_recorded);
  ++take_written;
}

void Pipeline::Impl::process(Captured& c) {
  if (want_reset.exchange(false)) {
    tracker = new_tracker();
    log("tracking reset: identifying the markers again");
  }
  if (want_calibration.exchange(false)) {
    calibrating = true;
    neutral.clear();
    set_status("calibrating: hold a neutral face");
  }
  if (want_record_toggle.exchange(false)) {
    if (recording)
      stop_recording();
    else if (mapper)
      start_recording();
  }

  const auto t0 = Clock::now();
  tracking::TrackedFrame tracked =
      tracker->track(c.image, static_cast<long>(c.sequence), c.timestamp_s);
  const auto t1 = Clock::now();
  {
    std::lock_guard lock(mutex);
    report.stats.tracking.add(ms_between(t0, t1));
  }

  FapFrame faps;
  faps.index = static_cast<long>(c.sequence);
  faps.time_s = c.timestamp_s;
  if (calibrating || !mapper) {
    neutral.push_back(std::move(tracked));
    {
      std::lock_guard lock(mutex);
      ++report.frames_calibration;
    }
    const auto wanted = static_cast<std::size_t>(std::max(1.0, o.calibration_seconds * fps + 0.5));
    if (neutral.size() >= wanted) {
      finish_calibration();
      if (mapper && !o.record.empty() && takes == 0) start_recording();
    }
    if (rendering && !neutral.empty()) shown.put(Shown{c.image, neutral.back(), faps});
    return;
  }

  const long index = faps.index;
  const double time = faps.time_s;
  faps = mapper->map(tracked);
  faps.index = index;
  faps.time_s = time;
  const auto t2 = Clock::now();
  if (vmc) vmc->send(faps, c.timestamp_s);
  if (udp) udp->send(faps);
  const auto t3 = Clock::now();
  if (recording) record(faps, c.sequence);
  {
    std::lock_guard lock(mutex);
    report.stats.fit.add(ms_between(t1, t2));
    report.stats.processing.add(ms_between(t0, t3));
    report.stats.delay.add(ms_between(c.captured, t3));
    ++report.frames_output;
  }
  if (rendering) shown.put(Shown{std::move(c.image), std::move(tracked), faps});
}

void Pipeline::Impl::processing_loop() {
  bool failed = false;
  try {
    while (auto c = frames.take()) {
      if (stopping) break;
      process(*c);
    }
  } catch (const InputError& e) {
    fail(e.what());  // the network went away, the disk is full
    failed = true;
  } catch (const std::exception& e) {
    fail(std::string("processing: ") + e.what());
    failed = true;
  }
  stopping = true;  // the capture thread stops too
  try {
    stop_recording(failed);
  } catch (const std::exception& e) {
    fail(e.what());
  }
  shown.close();
}

// The camera image with markers (left), the head (right), figures and keys below.
cv::Mat compose_view(const Shown& s, const cv::Mat& head, const std::vector<std::string>& lines) {
  cv::Mat camera = s.image.clone();
  tracking::draw_tracked_frame(camera, s.tracked);
  return render::compose_preview(camera, head, lines);
}

void Pipeline::Impl::render_loop(LiveView* view) {
  std::unique_ptr<FaceModel> model;
  std::unique_ptr<ExpressionLibrary> library;
  std::unique_ptr<render::FaceRenderer> face;
  try {
    model = std::make_unique<FaceModel>(load_default_face_model());
    library = std::make_unique<ExpressionLibrary>(ExpressionLibrary::load_default());
    render::RenderOptions ro;
    ro.width = ro.height = o.view_height;
    face = std::make_unique<render::FaceRenderer>(*model, library.get(), ro);
  } catch (const std::exception& e) {
    if (view) throw;
    log(std::string("no head rendering: ") + e.what());
  }
  DeformedMesh mesh;
  std::vector<float> flat;
  cv::Mat head(o.view_height, o.view_height, CV_8UC3, cv::Scalar(40, 40, 40));
  std::vector<std::string> lines;
  long rendered = 0;
  while (!shown.closed()) {
    if (view && !view->poll()) {
      stopping = true;
      frames.close();
    }
    auto s = shown.take_for(std::chrono::milliseconds(view ? 15 : 200));
    if (!s) continue;
    if (face) {
      const auto t0 = Clock::now();
      face->deformer().deform(s->faps, mesh);
      const auto t1 = Clock::now();
      render::flatten(mesh.positions(), flat);
      face->renderer().update_positions(flat);
      face->renderer().render_into(render::CameraPose::front(), face->framing(), head);
      const auto t2 = Clock::now();
      std::lock_guard lock(mutex);
      report.stats.deformation.add(ms_between(t0, t1));
      report.stats.render.add(ms_between(t1, t2));
      ++report.frames_rendered;
    }
    if (!view) continue;
    if (rendered++ % 10 == 0) {  // the figures change slowly; text every frame is wasted work
      std::lock_guard lock(mutex);
      const StageStats& st = report.stats;
      lines = {
          fmt::format("p50/p99 ms  capture {:.1f}/{:.1f}  tracking {:.1f}/{:.1f}  fit "
                      "{:.1f}/{:.1f}  deform {:.1f}/{:.1f}  render {:.1f}/{:.1f}",
                      st.capture.quantile(.5), st.capture.quantile(.99), st.tracking.quantile(.5),
                      st.tracking.quantile(.99), st.fit.quantile(.5), st.fit.quantile(.99),
                      st.deformation.quantile(.5), st.deformation.quantile(.99),
                      st.render.quantile(.5), st.render.quantile(.99)),
          fmt::format("capture->output p50 {:.1f} ms p99 {:.1f} ms   skipped {}   {}",
                      st.delay.quantile(.5), st.delay.quantile(.99), frames.skipped(), status_text),
          "[C] calibrate neutral now   [R] start/stop recording .fap   [T] reset tracking   "
          "[Q]/[Esc] quit"};
    }
    view->show(ViewFrame{compose_view(*s, head, lines), s->faps.index});
  }
}

Pipeline::Pipeline(PipelineOptions options) : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.o = std::move(options);
  m.source = capture::open_frame_source(m.o.camera, m.o.source);
  m.fps = m.source->nominal_fps() > 0 ? m.source->nominal_fps() : 25.0;
  m.size = m.source->frame_size();
  if (m.o.intrinsics) {
    std::string note;
    m.o.intrinsics = calib::intrinsics_for_frames(*m.o.intrinsics, m.size, "intrinsics", &note);
    if (!note.empty()) m.log(note);
  }
  m.paced = m.o.real_time.value_or(m.source->frame_count() >= 0);
  if (m.o.vmc) m.vmc = std::make_unique<VmcSender>(ArkitMapping::load_default(), *m.o.vmc);
  if (m.o.fap_udp)
    m.udp = std::make_unique<FapUdpSender>(m.o.fap_udp->host, m.o.fap_udp->port, m.fps);
  m.tracker = m.new_tracker();
  m.report.source = m.source->description();
  if (m.o.actor) {
    calib::ActorProfile profile = *m.o.actor;
    if (m.o.intrinsics) profile.camera = *m.o.intrinsics;
    m.mapper = mapping::make_fap_mapper(profile, m.o.mapper);
    m.status_text = "tracking";
  } else {
    m.prior = calib::load_actor_prior();
    m.calibrating = true;
    m.status_text = "calibrating: hold a neutral face";
  }
}

Pipeline::~Pipeline() = default;

PipelineReport Pipeline::run(LiveView* view) {
  Impl& m = *impl_;
  m.rendering = view != nullptr || m.o.render_head;
  if (m.mapper && !m.o.record.empty()) m.start_recording();
  std::thread capture([&] { m.capture_loop(); });
  std::thread processing([&] { m.processing_loop(); });
  std::optional<std::string> render_failure;
  try {
    if (m.rendering) m.render_loop(view);
  } catch (const std::exception& e) {
    render_failure = std::string("rendering: ") + e.what();
    m.stopping = true;
    m.frames.close();
  }
  processing.join();
  capture.join();
  if (render_failure) m.fail(*render_failure);
  std::lock_guard lock(m.mutex);
  m.report.skipped_processing = m.frames.skipped();
  m.report.skipped_render = m.shown.skipped();
  m.report.dropped_by_source = m.source->stats().dropped;
  return m.report;
}

void Pipeline::stop() {
  impl_->stopping = true;
  impl_->frames.close();
}
void Pipeline::calibrate_now() {
  impl_->want_calibration = true;
}
void Pipeline::toggle_recording() {
  impl_->want_record_toggle = true;
}
void Pipeline::reset_tracking() {
  impl_->want_reset = true;
}

std::string Pipeline::status() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->status_text;
}

}  // namespace rostro::live

// `rostro play` and `rostro pose`: FAP streams and single poses rendered on the 3D head.

#include <fmt/format.h>

#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>

#include "apps/checks.hpp"
#include "apps/commands.hpp"
#include "apps/interrupt.hpp"
#include "apps/progress.hpp"
#include "facecore/data_path.hpp"
#include "facecore/error.hpp"
#include "facecore/expression_library.hpp"
#include "facecore/face_model.hpp"
#include "facecore/fap_io.hpp"
#include "render/camera.hpp"
#include "render/contact_sheet.hpp"
#include "render/expression_clip.hpp"
#include "render/face_renderer.hpp"
#include "render/fap_assignments.hpp"
#include "render/fap_editor.hpp"
#include "render/fap_stream_source.hpp"
#include "render/frame_sink.hpp"
#include "render/player.hpp"
#include "render/render_error.hpp"
#include "render/sdl_audio_clock.hpp"
#include "render/video_writer.hpp"
#include "render/window_player.hpp"
#include "render/window_renderer.hpp"
#include "speech/audio.hpp"

namespace rostro::app {
namespace {
namespace fs = std::filesystem;

struct ViewOptions {
  int width = 640;
  int height = 480;
  std::string camera = "front";
  std::string head;                  // a face model description; empty: the default head
  std::string expressions, visemes;  // libraries; empty: data/expressions.json, visemes.json
  int samples = 4;
};

struct PlayOptions {
  std::string input;
  std::string output;
  std::string frames;
  std::string audio;
  std::string expression;
  int intensity = 63;
  double fps = 25.0;
  bool window = false;
  ViewOptions view;
};

struct EditOptions {
  std::string entry = "neutral";
  std::string select;
  std::string export_prefix = "pose";
  ViewOptions view;
};

struct PoseOptions {
  std::string faps;
  std::string output;
  std::string expression;
  int intensity = 63;
  std::string viseme;
  bool sheet = false;
  ViewOptions view;
};

void add_view_options(CLI::App* cmd, ViewOptions& view) {
  cmd->add_option("--width", view.width, "image width in pixels")->capture_default_str();
  cmd->add_option("--height", view.height, "image height in pixels")->capture_default_str();
  cmd->add_option("--camera", view.camera,
                  "front, three-quarter, or yaw,pitch,roll[,distance[,fov]] in degrees")
      ->capture_default_str();
  cmd->add_option("--head", view.head, "face model description (.json beside an .obj)");
  cmd->add_option("--samples", view.samples, "multisampling (1 = off)")->capture_default_str();
  cmd->add_option("--expressions", view.expressions,
                  "expression library (default data/expressions.json), e.g. from rostro edit");
  cmd->add_option("--visemes", view.visemes, "viseme library (default data/visemes.json)");
}

ExpressionLibrary load_library(const ViewOptions& view) {
  return ExpressionLibrary::load(
      view.expressions.empty() ? data_file("expressions.json") : fs::path(view.expressions),
      view.visemes.empty() ? data_file("visemes.json") : fs::path(view.visemes));
}

FaceModel load_model(const ViewOptions& view) {
  return load_face_model_or_default(view.head);
}

render::RenderOptions render_options(const ViewOptions& view) {
  if (view.width < 16 || view.height < 16 || view.width > 8192 || view.height > 8192) {
    throw InputError(fmt::format("image size {}x{} is outside 16..8192", view.width, view.height));
  }
  render::RenderOptions options;
  options.width = view.width;
  options.height = view.height;
  options.samples = view.samples;
  return options;
}

int expression_select(const std::string& name) {
  if (const auto select = ExpressionLibrary::expression_index(name); select && *select >= 1) {
    return *select;
  }
  throw InputError(fmt::format(
      "expression '{}': expected joy, sadness, anger, fear, disgust or surprise", name));
}

int viseme_index(const std::string& name) {
  for (int i = 0; i < kVisemeCount; ++i) {
    if (ExpressionLibrary::viseme_name(i) == name || std::to_string(i) == name) return i;
  }
  std::string names;
  for (int i = 0; i < kVisemeCount; ++i) {
    names += (i ? ", " : "") + std::string(ExpressionLibrary::viseme_name(i));
  }
  throw InputError(fmt::format("viseme '{}': expected 0..14 or one of {}", name, names));
}

// The stream the user asked for, checked before any output exists.
std::unique_ptr<FapSource> open_play_source(const PlayOptions& o) {
  if (o.input.empty() == o.expression.empty()) {
    throw InputError("play: give either a FAP file or --expression NAME");
  }
  if (!o.expression.empty()) check_fps(o.fps, "--fps");
  if (!o.input.empty()) {
    if (!fs::exists(o.input)) throw InputError(o.input + ": no such file");
    if (fap_format_for(o.input) == FapFormat::Fap) {
      const auto problems = validate_fap_file(o.input, 1);
      if (!problems.empty()) throw InputError(problems.front());
    }
    return open_fap_source(o.input);
  }
  render::ClipTiming timing;
  timing.fps = o.fps;
  return std::make_unique<render::FapStreamSource>(
      render::expression_clip(expression_select(o.expression), o.intensity, timing));
}

// Passes the window's commands on, and a Ctrl-C as Quit.
struct InterruptibleView : render::PlayerView {
  render::PlayerView& view;
  const InterruptScope& interrupt;
  InterruptibleView(render::PlayerView& v, const InterruptScope& i) : view(v), interrupt(i) {}
  void show(long frame, double clock_s) override { view.show(frame, clock_s); }
  std::vector<render::PlayerCommand> poll() override {
    auto commands = view.poll();
    if (interrupt.requested()) commands.push_back(render::PlayerCommand::Quit);
    return commands;
  }
  void wait() override { view.wait(); }
};

// `play --window`: real time on the audio clock (or the system clock without --audio).
void play_window(const PlayOptions& o) {
  if (!o.output.empty() || !o.frames.empty())
    throw InputError("play: --window shows the stream; leave out -o and --frames");
  const render::CameraPose pose = render::parse_camera(o.view.camera);
  render_options(o.view);  // checks the size
  FapStream stream;
  {
    auto source = open_play_source(o);
    stream.header = source->header();
    FapFrame frame;
    while (source->next(frame)) stream.frames.push_back(frame);
  }
  if (stream.frames.empty()) throw InputError("play: the stream has no frames");
  speech::Audio audio;
  if (!o.audio.empty()) audio = speech::read_wav(o.audio);
  const FaceModel model = load_model(o.view);
  const ExpressionLibrary library = load_library(o.view);
  const Deformer deformer(model, &library);

  render::WindowOptions wo;
  wo.width = o.view.width;
  wo.height = o.view.height;
  wo.samples = o.view.samples;
  wo.title = "rostro play: " + (o.input.empty() ? o.expression : o.input);
  wo.no_display = "no display for the playback window; render a video with -o OUT.mp4 instead";
  render::WindowRenderer window(wo);
  window.set_mesh(render::to_render_mesh(model));

  std::unique_ptr<render::PlaybackClock> clock;
  if (!o.audio.empty()) {
    try {
      auto sdl = std::make_unique<render::SdlAudioClock>(audio.samples, audio.sample_rate);
      std::fprintf(stderr, "rostro play: sound through %s\n", sdl->description().c_str());
      clock = std::move(sdl);
    } catch (const render::RenderUnavailable& e) {
      std::fprintf(stderr, "rostro play: %s; playing without sound\n", e.what());
    }
  }
  if (!clock) clock = std::make_unique<render::SteadyPlaybackClock>();

  render::WindowPlayerView window_view(window, deformer, stream, pose,
                                       render::portrait_bounds(model, window.mesh_bounds()),
                                       wo.title);
  InterruptScope interrupt;
  InterruptibleView view(window_view, interrupt);
  render::PlayerOptions po;
  po.fps = stream.header.fps;
  po.frame_count = static_cast<long>(stream.frames.size());
  po.duration_s = audio.duration_s();
  const render::PlayerReport report = render::play_on_clock(po, *clock, view);
  std::printf("played %ld of %zu frames (%ld skipped) to %.2f s%s\n", report.frames_shown,
              stream.frames.size(), report.frames_skipped, report.end_s,
              report.quit ? ", stopped by the user" : "");
}

void play(const PlayOptions& o) {
  if (o.window) return play_window(o);
  if (o.output.empty() && o.frames.empty()) {
    throw InputError("play: give -o OUT.mp4, --frames DIR or --window");
  }
  check_not_an_input({{o.output, "-o"}, {o.frames, "--frames"}}, {o.input, o.audio});
  const render::CameraPose pose = render::parse_camera(o.view.camera);
  const render::RenderOptions options = render_options(o.view);
  std::unique_ptr<FapSource> source = open_play_source(o);
  const FapHeader header = source->header();
  const FaceModel model = load_model(o.view);
  const ExpressionLibrary library = load_library(o.view);

  std::unique_ptr<render::FrameSink> video;
  if (!o.output.empty()) {
    render::VideoOptions video_options;
    video_options.fps = header.fps;
    video_options.audio = o.audio;
    video = std::make_unique<render::VideoWriter>(o.output, video_options);
  } else if (!o.audio.empty()) {
    throw InputError("--audio needs a video output (-o OUT.mp4) or --window");
  }
  std::unique_ptr<render::FrameSink> frames;
  if (!o.frames.empty()) frames = std::make_unique<render::FrameFolderWriter>(o.frames);

  // One sink that feeds both outputs, finishing them together.
  struct Tee : render::FrameSink {
    render::FrameSink* a;
    render::FrameSink* b;
    long n = 0;
    void write(const cv::Mat& bgr) override {
      if (a) a->write(bgr);
      if (b) b->write(bgr);
      ++n;
    }
    void finish() override {
      if (a) a->finish();
      if (b) b->finish();
    }
    long frames_written() const override { return n; }
  } tee;
  tee.a = video.get();
  tee.b = frames.get();

  render::FaceRenderer face(model, &library, options);
  Progress progress("rendering", header.frame_count);
  // A signal abandons the video and the frames: written whole or not at all.
  InterruptScope interrupt;
  const long count = render::render_stream(*source, face, pose, tee, [&](long done) {
    interrupt.throw_if_requested();
    progress.update(done);
  });
  progress.finish();
  if (!o.output.empty()) {
    std::printf("%s: %ld frames at %g fps, %dx%d%s\n", o.output.c_str(), count, header.fps,
                options.width, options.height, o.audio.empty() ? "" : ", with audio");
  }
  if (!o.frames.empty()) std::printf("%s: %ld PNG frames\n", o.frames.c_str(), count);
}

FapFrame pose_frame(const PoseOptions& o) {
  FapFrame frame = render::parse_fap_assignments(o.faps);
  if (!o.expression.empty()) {
    if (o.intensity < 0 || o.intensity > 63) throw InputError("--intensity must be 0..63");
    ExpressionParams e;
    e.select1 = expression_select(o.expression);
    e.intensity1 = o.intensity;
    frame.set_expression(e);
  }
  if (!o.viseme.empty()) {
    VisemeParams v;
    v.select1 = viseme_index(o.viseme);
    v.select2 = v.select1;
    v.blend = 63;
    frame.set_viseme(v);
  }
  return frame;
}

// Neutral, the six expressions, visemes that shape the mouth in different ways, a
// three-quarter view and a profile: a page that shows at a glance what the head can do.
cv::Mat make_sheet(const FaceModel& model, render::FaceRenderer& face,
                   const render::CameraPose& pose) {
  std::vector<render::SheetTile> tiles;
  Progress progress("contact sheet", 16);
  tiles.push_back({face.render(FapFrame{}, pose), "neutral"});
  for (int select = 1; select <= 6; ++select) {
    FapFrame frame;
    ExpressionParams e;
    e.select1 = select;
    e.intensity1 = 63;
    frame.set_expression(e);
    tiles.push_back(
        {face.render(frame, pose), std::string(ExpressionLibrary::expression_name(select))});
    progress.update(static_cast<long>(tiles.size()));
  }
  for (const int viseme : {1, 2, 3, 7, 10, 13, 14}) {
    FapFrame frame;
    VisemeParams v;
    v.select1 = viseme;
    v.select2 = viseme;
    v.blend = 63;
    frame.set_viseme(v);
    tiles.push_back({face.render(frame, pose),
                     "viseme " + std::string(ExpressionLibrary::viseme_name(viseme))});
    progress.update(static_cast<long>(tiles.size()));
  }
  FapFrame joy;
  ExpressionParams e;
  e.select1 = 1;
  e.intensity1 = 63;
  joy.set_expression(e);
  tiles.push_back({face.render(joy, render::CameraPose::three_quarter()), "joy, 3/4 view"});
  // The profile takes in the neck and the top of the shoulders.
  const render::Bounds portrait = face.framing();
  face.set_framing(render::portrait_bounds(model, face.renderer().mesh_bounds(), 0.6f));
  render::CameraPose profile;
  profile.yaw_deg = 90;
  profile.margin = 1.2;
  tiles.push_back({face.render(FapFrame{}, profile), "neutral, profile"});
  face.set_framing(portrait);
  progress.finish();
  return render::contact_sheet(tiles, 4);
}

void pose_command(const PoseOptions& o) {
  const render::CameraPose pose = render::parse_camera(o.view.camera);
  const render::RenderOptions options = render_options(o.view);
  const FapFrame frame = o.sheet ? FapFrame{} : pose_frame(o);
  if (o.sheet && (!o.faps.empty() || !o.expression.empty() || !o.viseme.empty())) {
    throw InputError("--sheet draws its own poses; leave out FAPs, --expression and --viseme");
  }
  const FaceModel model = load_model(o.view);
  const ExpressionLibrary library = load_library(o.view);
  render::FaceRenderer face(model, &library, options);
  const cv::Mat image = o.sheet ? make_sheet(model, face, pose) : face.render(frame, pose);
  render::write_image(o.output, image);
  std::printf("%s: %dx%d\n", o.output.c_str(), image.cols, image.rows);
}

void edit_command(const EditOptions& o) {
  render::EditorOptions eo;
  eo.expressions =
      o.view.expressions.empty() ? data_file("expressions.json") : fs::path(o.view.expressions);
  eo.visemes = o.view.visemes.empty() ? data_file("visemes.json") : fs::path(o.view.visemes);
  eo.entry = o.entry;
  eo.select = o.select;
  eo.export_prefix = o.export_prefix;
  eo.camera = render::parse_camera(o.view.camera);
  render_options(o.view);  // checks the size
  eo.width = o.view.width;
  eo.height = o.view.height;
  eo.log = [](const std::string& text) {
    std::printf("%s\n", text.c_str());
    std::fflush(stdout);  // seen as it happens, also when stdout is a file
  };
  render::editor_entry(o.entry);  // an unknown entry is one line before any window opens
  const FaceModel model = load_model(o.view);
  ExpressionLibrary library = ExpressionLibrary::load(eo.expressions, eo.visemes);
  if (render::run_fap_editor(model, library, eo)) std::printf("edits not saved (Ctrl+S saves)\n");
}

}  // namespace

void add_play_commands(CLI::App& app) {
  static PlayOptions play_options;
  CLI::App* play_cmd = app.add_subcommand(
      "play", "Render a FAP stream (or an expression clip) on the 3D head to a video or PNGs");
  play_cmd->add_option("FILE", play_options.input, "a .fap, .csv or .json FAP stream");
  play_cmd->add_option("-o,--output", play_options.output,
                       "video file (.mp4); written whole or not at all");
  play_cmd->add_option("--frames", play_options.frames, "also (or instead) write PNGs here");
  play_cmd->add_option("--audio", play_options.audio,
                       "WAV to mux into the video, or to play with --window; frame k plays at "
                       "audio time k/fps");
  play_cmd->add_flag("--window", play_options.window,
                     "play in real time in a window, on the audio clock with --audio (Space "
                     "pauses, Left/Right seek 5 s, Home restarts, Q quits)");
  play_cmd->add_option("--expression", play_options.expression,
                       "instead of FILE: a short neutral-to-expression clip (joy, sadness, "
                       "anger, fear, disgust, surprise)");
  play_cmd->add_option("--intensity", play_options.intensity, "expression intensity 0..63")
      ->capture_default_str();
  play_cmd->add_option("--fps", play_options.fps, "frame rate of an --expression clip")
      ->capture_default_str();
  add_view_options(play_cmd, play_options.view);
  play_cmd->footer(
      "The frame rate comes from the file; one video frame per FAP frame.\n\n"
      "Example:\n"
      "  rostro play ../shared/fixtures/xface/joy.fap -o joy.mp4 --camera three-quarter\n"
      "  rostro play hola.fap --audio hola.wav -o hola.mp4\n"
      "  rostro play hola.fap --audio hola.wav --window\n"
      "  rostro play --expression surprise --frames surprise/");
  play_cmd->callback([] { play(play_options); });

  static PoseOptions pose_options;
  CLI::App* pose_cmd =
      app.add_subcommand("pose", "Render one frame of FAPs (or a contact sheet) to an image");
  pose_cmd->add_option("FAPS", pose_options.faps,
                       "FAP=VALUE list, ids or names, e.g. 3=400,12=150 or open_jaw=400");
  pose_cmd->add_option("-o,--output", pose_options.output, "image file (.png, .jpg)")->required();
  pose_cmd->add_option("--expression", pose_options.expression,
                       "add an expression (joy, sadness, anger, fear, disgust, surprise)");
  pose_cmd->add_option("--intensity", pose_options.intensity, "expression intensity 0..63")
      ->capture_default_str();
  pose_cmd->add_option("--viseme", pose_options.viseme,
                       "add a viseme (0..14 or a name: p_b_m, aa, ...)");
  pose_cmd->add_flag(
      "--sheet", pose_options.sheet,
      "a contact sheet: neutral, the six expressions, visemes, a 3/4 view, a profile");
  add_view_options(pose_cmd, pose_options.view);
  pose_cmd->footer(
      "Example:\n"
      "  rostro pose 3=400,12=150 -o face.png\n"
      "  rostro pose --expression joy --camera three-quarter -o joy.png\n"
      "  rostro pose --sheet --width 320 --height 320 -o docs/images/contact-sheet.png");
  pose_cmd->callback([] { pose_command(pose_options); });

  static EditOptions edit_options;
  edit_options.view.width = 1280;
  edit_options.view.height = 800;
  CLI::App* edit_cmd = app.add_subcommand(
      "edit", "Edit the expression and viseme libraries on the head, in a window");
  edit_cmd
      ->add_option("--entry", edit_options.entry,
                   "entry to edit first: neutral, joy, ..., or a viseme (aa, p_b_m, ...)")
      ->capture_default_str();
  edit_cmd->add_option("--select", edit_options.select,
                       "FAP that PageUp/PageDown nudge first (a name, e.g. open_jaw)");
  edit_cmd
      ->add_option("--export", edit_options.export_prefix,
                   "prefix of the pose export: PREFIX.fap and PREFIX.png")
      ->capture_default_str();
  add_view_options(edit_cmd, edit_options.view);
  edit_cmd->footer(
      "A slider per FAP, grouped as in MPEG-4; drag on the head to orbit. PageUp/PageDown\n"
      "nudge the selected FAP, Ctrl+S saves both libraries (each file whole or not at all) to\n"
      "--expressions/--visemes (default: data/), Escape quits. Needs a display.\n\n"
      "Example:\n"
      "  cp data/expressions.json data/visemes.json /tmp/\n"
      "  rostro edit --expressions /tmp/expressions.json --visemes /tmp/visemes.json --entry joy\n"
      "  rostro pose --expression joy --expressions /tmp/expressions.json -o joy.png");
  edit_cmd->callback([] { edit_command(edit_options); });
}

}  // namespace rostro::app

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <opencv2/core/utils/logger.hpp>

#include "apps/commands.hpp"
#include "apps/interrupt.hpp"
#include "facecore/error.hpp"

namespace {

constexpr const char* kFooter =
    R"(Exit codes: 0 success, 1 bad input (a file, device or value that is
not what rostro expects), 2 bad usage (unknown option, missing argument),
128+N stopped by signal N (130 Ctrl-C, 143 SIGTERM, 129 SIGHUP) before the
output was complete: nothing written. capture, live and track stopped by a
signal keep every frame so far and exit 0.

Example:
  rostro fap info data/samples/wave.fap
Run 'rostro COMMAND --help' for a command's options and an example.)";

// Bad input is one line from rostro: FFmpeg's and OpenCV's own log lines (a truncated video
// prints several) are silenced unless the user asks for them through these variables.
void quiet_libraries() {
  setenv("OPENCV_FFMPEG_LOGLEVEL", "-8", 0);  // AV_LOG_QUIET, read when videoio loads FFmpeg
  if (std::getenv("OPENCV_LOG_LEVEL") == nullptr)
    cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_SILENT);
}

}  // namespace

int main(int argc, char** argv) {
  quiet_libraries();
  rostro::app::install_signal_cleanup();
  CLI::App app{"rostro: facial performance capture to MPEG-4 facial animation parameters"};
  app.set_version_flag("--version", "rostro " ROSTRO_VERSION);
  app.footer(kFooter);
  app.require_subcommand(1);
  // In the order a user meets them: sources, tracking, capture, the head, speech, evaluation.
  rostro::app::add_devices_commands(app);
  rostro::app::add_track_commands(app);
  rostro::app::add_calibrate_commands(app);
  rostro::app::add_capture_commands(app);
  rostro::app::add_shoot_commands(app);
  rostro::app::add_live_commands(app);
  rostro::app::add_head_commands(app);
  rostro::app::add_play_commands(app);
  rostro::app::add_speech_commands(app);
  rostro::app::add_script_commands(app);
  rostro::app::add_synth_commands(app);
  rostro::app::add_eval_commands(app);
  rostro::app::add_fap_commands(app);

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);
    return 2;
  } catch (const rostro::app::Interrupted& e) {
    std::fprintf(stderr, "rostro: %s\n", e.what());
    return 128 + e.signal();
  } catch (const rostro::InputError& e) {
    std::fprintf(stderr, "rostro: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "rostro: error: %s\n", e.what());
    return 1;
  }
  return 0;
}

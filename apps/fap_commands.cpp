// `rostro fap ...`: inspect, check and convert FAP files.

#include <fmt/format.h>

#include <cstdio>

#include "apps/checks.hpp"
#include "apps/commands.hpp"
#include "apps/progress.hpp"
#include "facecore/atomic_file.hpp"
#include "facecore/error.hpp"
#include "facecore/fap_io.hpp"
#include "facecore/fap_summary.hpp"
#include "live/live_link_face_csv.hpp"

namespace rostro::app {
namespace {

void info(const std::string& path) {
  auto source = open_fap_source(path);
  FapSummary summary;
  summary.header = source->header();
  FapFrame frame;
  while (source->next(frame)) summary.add(frame);
  std::fputs(summary.to_text().c_str(), stdout);
}

void validate(const std::string& path) {
  const auto problems = validate_fap_file(path);
  for (const std::string& p : problems) std::printf("%s\n", p.c_str());
  if (!problems.empty())
    throw InputError(fmt::format("{}: {} problem{} found", path, problems.size(),
                                 problems.size() == 1 ? "" : "s"));
  std::printf("%s: valid\n", path.c_str());
}

// NAME.arkit.csv: ARKit blend-shape curves in Live Link Face's CSV layout.
bool is_arkit_csv(const std::string& path) {
  return path.ends_with(".arkit.csv");
}

void convert_to_live_link_face(FapSource& source, const std::string& out) {
  live::LiveLinkFaceCsv csv(live::ArkitMapping::load_default(), source.header().fps);
  AtomicFile file(out);
  file.write(live::LiveLinkFaceCsv::header());
  Progress progress("converting", source.header().frame_count);
  FapFrame frame;
  long frames = 0;
  while (source.next(frame)) {
    file.write(csv.row(frame));
    progress.update(++frames);
  }
  file.commit();
  progress.finish();
  std::printf("%s: %ld frames of the 52 ARKit blend shapes (Live Link Face CSV)\n", out.c_str(),
              frames);
}

void convert(const std::string& in, const std::string& out) {
  if (!is_arkit_csv(out))
    fap_format_for(out);  // reject an unknown output extension before reading anything
  check_not_an_input({{out, "OUTPUT"}}, {in});
  auto source = open_fap_source(in);
  if (is_arkit_csv(out)) return convert_to_live_link_face(*source, out);
  auto sink = open_fap_sink(out, source->header());
  Progress progress("converting", source->header().frame_count);
  FapFrame frame;
  while (source->next(frame)) {
    sink->write(frame);
    progress.update(sink->frames_written());
  }
  sink->finish();
  progress.finish();
  std::printf("%s: %ld frames\n", out.c_str(), sink->frames_written());
  warn_if_xface_cannot_read(*sink, out);
}

// A killed writer's temporary NAME.fap.tmp-PID: the default output is NAME.fap.
std::string recovered_name(const std::string& temporary) {
  const auto mark = temporary.rfind(".tmp-");
  if (mark == std::string::npos || mark + 5 == temporary.size() ||
      temporary.find_first_not_of("0123456789", mark + 5) != std::string::npos)
    throw InputError(temporary + ": not a temporary NAME.fap.tmp-PID; give the output with -o");
  return temporary.substr(0, mark);
}

void recover(const std::string& in, std::string out) {
  if (out.empty()) out = recovered_name(in);
  if (std::filesystem::exists(out))
    throw InputError(out + ": exists; give another name with -o (nothing was replaced)");
  const RecoveredTake take = recover_fap_file(in, out);
  std::printf("%s: %ld frames recovered from %s (%ld checkpointed by the writer)\n", out.c_str(),
              take.frames, in.c_str(), take.vouched);
  if (!take.stopped.empty())
    std::fprintf(stderr, "rostro fap recover: stopped at the first damaged frame: %s\n",
                 take.stopped.c_str());
}

void generate(const std::string& out, double seconds, double fps, const std::string& which,
              unsigned seed) {
  check_seconds(seconds, "--seconds");
  check_fps(fps, "--fps");
  std::array<bool, kFapCount> ids{};
  if (which == "all") {
    ids.fill(true);
  } else if (which == "face") {
    // What a face shows without moving the head or the tongue: lips, jaw, brows, eyelids.
    for (int id = 3; id <= kFapCount; ++id) {
      const int group = fap_info(id).group;
      ids[static_cast<std::size_t>(id - 1)] =
          group == 2 || group == 4 || group == 8 || (id >= 19 && id <= 22) || group == 5;
    }
  } else {
    throw InputError("--faps must be 'all' or 'face', not '" + which + "'");
  }
  FapHeader header;
  header.name = std::filesystem::path(out).stem().string();
  header.fps = fps;
  auto sink = open_fap_sink(out, header);
  const long frames = std::lround(seconds * fps);
  Progress progress("generating", frames);
  for (long i = 0; i < frames; ++i) {
    sink->write(synthetic_fap_frame(i, fps, ids, seed));
    progress.update(i + 1);
  }
  sink->finish();
  progress.finish();
  std::printf("%s: %ld frames at %g fps\n", out.c_str(), frames, fps);
  warn_if_xface_cannot_read(*sink, out);
}

}  // namespace

void add_fap_commands(CLI::App& app) {
  CLI::App* fap = app.add_subcommand("fap", "Inspect, validate, convert and generate FAP files");
  fap->require_subcommand(1);
  fap->footer("Example:\n  rostro fap info data/samples/wave.fap");

  static std::string in, out;
  CLI::App* info_cmd = fap->add_subcommand(
      "info", "Frame rate, frame count, duration and the range of every FAP used");
  info_cmd->add_option("FILE", in, "a .fap, .csv or .json FAP stream")->required();
  info_cmd->footer("Example:\n  rostro fap info data/samples/wave.fap");
  info_cmd->callback([] { info(in); });

  CLI::App* validate_cmd = fap->add_subcommand(
      "validate", "Check a .fap file; prints one line per problem (exit 1) or 'valid' (exit 0)");
  validate_cmd->add_option("FILE", in, "the .fap file")->required();
  validate_cmd->footer("Example:\n  rostro fap validate take.fap");
  validate_cmd->callback([] { validate(in); });

  CLI::App* convert_cmd =
      fap->add_subcommand("convert",
                          "Convert between .fap, .csv and .json (chosen by extension), or to "
                          "ARKit blend-shape curves (NAME.arkit.csv, Live Link Face's layout)");
  convert_cmd->add_option("IN", in, "input stream")->required();
  convert_cmd->add_option("OUT", out, "output file; written whole or not at all")->required();
  convert_cmd->footer(
      "Examples:\n  rostro fap convert data/samples/wave.fap wave.csv\n"
      "  rostro fap convert data/samples/wave.fap wave.arkit.csv   # for Unreal, Blender");
  convert_cmd->callback([] { convert(in, out); });

  static std::string recovered;
  CLI::App* recover_cmd = fap->add_subcommand(
      "recover", "Turn the temporary of a killed capture (NAME.fap.tmp-PID) into a valid .fap");
  recover_cmd->add_option("TEMPORARY", in, "the NAME.fap.tmp-PID a killed process left")
      ->required();
  recover_cmd->add_option("-o,--output", recovered,
                          "where to write (default: NAME.fap, which must not exist)");
  recover_cmd->footer(
      "Keeps every whole frame: at least those up to the writer's last checkpoint, a second\n"
      "before it stopped. The temporary is left as it was.\n\n"
      "Example:\n  rostro fap recover interview.fap.tmp-4242\n"
      "  rostro fap recover interview.fap.tmp-4242 -o interview-rescued.fap");
  recover_cmd->callback([] { recover(in, recovered); });

  static double seconds = 4.0, fps = 25.0;
  static std::string which = "face";
  static unsigned seed = 1;
  CLI::App* generate_cmd = fap->add_subcommand(
      "generate", "Write a smooth synthetic FAP stream (for demos, players and benchmarks)");
  generate_cmd->add_option("-o,--output", out, "output .fap/.csv/.json")->required();
  generate_cmd->add_option("--seconds", seconds, "duration")->capture_default_str();
  generate_cmd->add_option("--fps", fps, "frame rate")->capture_default_str();
  generate_cmd->add_option("--faps", which, "'face' (lips, jaw, brows, lids, cheeks) or 'all'")
      ->capture_default_str();
  generate_cmd->add_option("--seed", seed, "phase seed")->capture_default_str();
  generate_cmd->footer(
      "Example:\n  rostro fap generate --seconds 10 --fps 60 --faps all -o wave.fap");
  generate_cmd->callback([] { generate(out, seconds, fps, which, seed); });
}

}  // namespace rostro::app

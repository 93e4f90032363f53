// `rostro script`: a storyboard (sandboxed Lua, docs/script.md) to a FAP stream and its audio.
// All the work is in script/; this file maps options onto it.

#include <fmt/format.h>

#include <cstdio>
#include <filesystem>

#include "apps/checks.hpp"
#include "apps/commands.hpp"
#include "apps/interrupt.hpp"
#include "apps/progress.hpp"
#include "facecore/error.hpp"
#include "facecore/expression_library.hpp"
#include "facecore/fap_io.hpp"
#include "script/scene.hpp"
#include "script/storyboard_reader.hpp"
#include "speech/mouth_cues.hpp"

namespace rostro::app {
namespace {

struct ScriptArgs {
  std::string story;
  std::string output;
  std::string wav;
  std::string cues;
  double cue_fps = 24.0;
  double fps = 25.0;
  unsigned long long seed = 1;
  bool allow_outside = false;
};

void run_script(const ScriptArgs& a, const CLI::App& cmd) {
  check_not_an_input({{a.output, "-o"}, {a.wav, "--wav"}, {a.cues, "--cues"}}, {a.story});
  // A signal abandons the run: the .fap and the WAV are written whole or not at all.
  InterruptScope interrupt;
  const bool fps_given = cmd.count("--fps") > 0, seed_given = cmd.count("--seed") > 0;
  if (fps_given) check_fps(a.fps, "--fps");

  script::SandboxOptions sandbox;
  sandbox.allow_outside = a.allow_outside;
  sandbox.stop_requested = [&interrupt] { return interrupt.requested(); };
  const script::Storyboard board = [&] {
    try {
      return script::read_storyboard(a.story, a.seed, sandbox);
    } catch (const InputError&) {
      interrupt.throw_if_requested();  // a script stopped by Ctrl-C exits 130, not 1
      throw;
    }
  }();
  const std::filesystem::path output =
      !a.output.empty() ? std::filesystem::path(a.output) : board.output;
  if (output.empty())
    throw InputError("no output: give -o OUT.fap (or output = \"x.fap\" in the storyboard)");
  fap_format_for(output);  // reject unknown extensions before any work
  if (!a.cues.empty()) speech::cue_format_for(a.cues);

  const auto behaviour = speech::BehaviourSettings::load_default();
  std::vector<std::string> warnings;
  auto speech = script::resolve_speech(board, behaviour, warnings);
  for (const std::string& w : warnings)
    std::fprintf(stderr, "rostro script: warning: %s\n", w.c_str());
  interrupt.throw_if_requested();

  const ExpressionLibrary library = ExpressionLibrary::load_default();
  const speech::KeyShapes shapes = speech::KeyShapes::load_default(library);
  script::SceneOptions options;
  options.fps = fps_given ? a.fps : board.fps;
  options.seed = seed_given || !board.seed_set ? a.seed : board.seed;
  const script::Scene scene(board, std::move(speech), library, shapes, behaviour, options);

  FapHeader header;
  header.name = "rostro-script";
  header.fps = options.fps;
  header.frame_count = scene.frame_count();
  auto sink = open_fap_sink(output, header);
  Progress progress("script", scene.frame_count());
  for (long k = 0; k < scene.frame_count(); ++k) {
    interrupt.throw_if_requested();
    sink->write(scene.frame(k));
    progress.update(k + 1);
  }
  interrupt.throw_if_requested();
  sink->finish();
  progress.finish();
  warn_if_xface_cannot_read(*sink, output);
  if (!a.wav.empty()) speech::write_wav(a.wav, scene.audio());
  if (!a.cues.empty())
    speech::write_cues(a.cues, speech::mouth_cues(scene.phonemes(), scene.duration_s()), a.wav,
                       scene.duration_s(), a.cue_fps);

  std::printf(
      "%s: %ld frames at %g fps (%.2f s; %zu utterance(s), %zu expression(s), %zu eye and "
      "%zu head action(s))\n",
      output.c_str(), scene.frame_count(), options.fps, scene.duration_s(),
      scene.utterances().size(), board.expressions.size(), board.eyes.size(), board.head.size());
  if (!a.wav.empty()) std::printf("%s: %.2f s of audio\n", a.wav.c_str(), scene.duration_s());
}

}  // namespace

void add_script_commands(CLI::App& app) {
  auto args = std::make_shared<ScriptArgs>();
  CLI::App* cmd = app.add_subcommand(
      "script",
      "Run a storyboard (Lua: speech, expressions, gaze, head over time) to a .fap and its audio");
  cmd->add_option("story", args->story, "The storyboard script (docs/script.md)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", args->output,
                  "Output FAP stream (.fap, .csv or .json); default: the storyboard's output");
  cmd->add_option("--wav", args->wav, "Write the scene's audio here (16-bit PCM WAV)");
  cmd->add_option("--cues", args->cues,
                  "Also write the scene's Rhubarb Lip Sync mouth cues here: .tsv, .json, .xml "
                  "or .dat (docs/speech.md)");
  cmd->add_option("--cue-fps", args->cue_fps, "Frame rate of .dat mouth cues")
      ->check(CLI::Range(24.0, 100.0))
      ->capture_default_str();
  cmd->add_option("--fps", args->fps, "Frames per second (default: the storyboard's fps, or 25)");
  cmd->add_option("--seed", args->seed,
                  "Seed for math.random, blinks, saccades and head noise (default: the "
                  "storyboard's seed, or 1)");
  cmd->add_flag("--allow-outside", args->allow_outside,
                "Let require() and the files a storyboard names reach outside its folder");
  cmd->footer(R"(Example:
  rostro script data/scripts/greeting.lua -o greeting.fap --wav greeting.wav
  rostro play greeting.fap --audio greeting.wav -o greeting.mp4)");
  cmd->callback([args, cmd] { run_script(*args, *cmd); });
}

}  // namespace rostro::app

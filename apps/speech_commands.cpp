// `rostro speak`: text, a recording with or without its transcript, or an MBROLA .pho to a
// lip-synced FAP stream, the speech audio and mouth cues. All the work is in speech/; this
// file maps options onto it.

#include <fmt/format.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "apps/checks.hpp"
#include "apps/commands.hpp"
#include "apps/interrupt.hpp"
#include "apps/progress.hpp"
#include "facecore/error.hpp"
#include "facecore/expression_library.hpp"
#include "facecore/fap_io.hpp"
#include "script/viseme_script.hpp"
#include "speech/animator.hpp"
#include "speech/emotion_markup.hpp"
#include "speech/mouth_cues.hpp"
#include "speech/pipeline.hpp"

namespace rostro::app {
namespace {

struct SpeakArgs {
  std::string text;
  std::string text_file;
  std::string language = "es";
  std::string voice;
  std::string pho;
  std::string audio;
  std::string output;
  std::string wav;
  std::string cues;
  double cue_fps = 24.0;
  std::string emotion;
  std::string viseme_script;
  double fps = 25.0;
  int rate = 0;
  unsigned long long seed = 1;
  bool no_blinks = false;
  bool no_saccades = false;
  bool no_head = false;
  bool high_level = false;
  bool strict = false;
};

// Speech is prepared whole (phonemes, audio, keys), so memory grows with the text: about
// 7 kB a character. Longer texts are refused; split them into several takes.
constexpr std::size_t kMaxTextBytes = 20000;

void check_text_length(std::size_t bytes, const std::string& what) {
  if (bytes > kMaxTextBytes)
    throw InputError(
        fmt::format("{}: {} bytes of text, more than the {} a take may hold "
                    "(about 20 minutes of speech); split it into several takes",
                    what, bytes, kMaxTextBytes));
}

std::string read_text_file(const std::string& path) {
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  if (!ec) check_text_length(static_cast<std::size_t>(size), path);
  std::ifstream in(path);
  if (!in) throw InputError(where(path, 0, "cannot open the text file"));
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Where the phoneme times came from, for the summary line.
std::string recognition_note(const speech::PreparedSpeech& p) {
  switch (p.recognition) {
    case speech::Recognition::Synthesis:
      return "voice " + p.voice;
    case speech::Recognition::Pho:
      return "times from the .pho";
    case speech::Recognition::Alignment:
      return fmt::format("aligned to the transcript through voice {}, match ratio {:.2f}", p.voice,
                         p.match_ratio);
    case speech::Recognition::PhoneRecognition:
      return "phones recognised by PocketSphinx";
  }
  return {};
}

void speak(const SpeakArgs& a) {
  check_fps(a.fps, "--fps");
  check_not_an_input({{a.output, "-o"},
                      {a.wav, "--wav"},
                      {a.cues, "--cues"},
                      {a.viseme_script, "--viseme-script"}},
                     {a.audio, a.text_file, a.pho});
  // A signal abandons the run: the .fap and the WAV are written whole or not at all.
  InterruptScope interrupt;
  const int sources = !a.text.empty() + !a.text_file.empty() + !a.pho.empty();
  if (sources > 1 || (sources == 0 && a.audio.empty()))
    throw InputError("give one of: TEXT, --text-file F, --pho F, or a recording with --audio F");
  if (!a.wav.empty() && !a.pho.empty() && a.audio.empty())
    throw InputError("--wav with --pho needs the speech audio (--audio F)");
  fap_format_for(a.output);  // reject unknown extensions before any work
  if (!a.cues.empty()) speech::cue_format_for(a.cues);
  if (!a.viseme_script.empty() && a.high_level)
    throw InputError("--viseme-script does not record --high-level; leave one out");

  speech::SpeechRequest request;
  request.language = a.language;
  request.voice = a.voice;
  request.rate_wpm = a.rate;
  request.pho = a.pho;
  request.audio = a.audio;
  request.text = !a.text_file.empty() ? read_text_file(a.text_file) : a.text;
  check_text_length(request.text.size(), !a.text_file.empty() ? a.text_file : "TEXT");

  const auto behaviour = speech::BehaviourSettings::load_default();
  speech::AnimationOptions options;
  options.fps = a.fps;
  options.blinks = !a.no_blinks;
  options.saccades = !a.no_saccades;
  options.head_motion = !a.no_head;
  options.high_level = a.high_level;
  options.seed = a.seed;
  if (!a.emotion.empty()) {
    const auto colon = a.emotion.find(':');
    options.base_expression = speech::emotion_from_name(a.emotion.substr(0, colon));
    if (options.base_expression < 0)
      throw InputError("--emotion: unknown emotion '" + a.emotion.substr(0, colon) +
                       "' (expected " + speech::known_emotion_names() + ")");
    if (colon != std::string::npos) {
      try {
        options.base_intensity = std::stod(a.emotion.substr(colon + 1));
      } catch (const std::exception&) {
        options.base_intensity = -1.0;
      }
      if (options.base_intensity < 0.0 || options.base_intensity > 1.0)
        throw InputError("--emotion: intensity after ':' must be in 0..1");
    }
  }

  speech::PreparedSpeech prepared = speech::prepare_speech(request, behaviour.default_ramp_s);
  for (const std::string& w : prepared.warnings)
    std::fprintf(stderr, "rostro speak: warning: %s\n", w.c_str());
  if (a.strict && !prepared.resolution.unknown.empty())
    throw InputError("--strict: unknown phonemes: " +
                     speech::describe_unknown(prepared.resolution.unknown));

  const ExpressionLibrary library = ExpressionLibrary::load_default();
  const speech::KeyShapes shapes = speech::KeyShapes::load_default(library);
  const speech::Animator animator(prepared.resolution.phonemes, prepared.duration_s,
                                  prepared.emotions, library, shapes, behaviour, options);

  FapHeader header;
  header.name = "rostro-speak";
  header.fps = a.fps;
  header.frame_count = animator.frame_count();
  auto sink = open_fap_sink(a.output, header);
  Progress progress("speak", animator.frame_count());
  for (long k = 0; k < animator.frame_count(); ++k) {
    interrupt.throw_if_requested();
    sink->write(animator.frame(k));
    progress.update(k + 1);
  }
  interrupt.throw_if_requested();
  sink->finish();
  progress.finish();
  warn_if_xface_cannot_read(*sink, a.output);
  if (!a.wav.empty()) speech::write_wav(a.wav, prepared.audio);
  if (!a.cues.empty())
    speech::write_cues(a.cues,
                       speech::mouth_cues(prepared.resolution.phonemes, prepared.duration_s),
                       !a.audio.empty() ? a.audio : a.wav, prepared.duration_s, a.cue_fps);
  if (!a.viseme_script.empty())
    script::write_viseme_script(
        a.viseme_script,
        script::viseme_script_for(prepared, options, a.language, "rostro speak -o " + a.output,
                                  !a.wav.empty() ? a.wav : a.audio));

  std::printf("%s: %ld frames at %g fps (%.2f s of speech, %zu phonemes, %zu keys, %s)\n",
              a.output.c_str(), animator.frame_count(), a.fps, prepared.duration_s,
              prepared.resolution.phonemes.size(), animator.keys().size(),
              recognition_note(prepared).c_str());
  if (!a.wav.empty())
    std::printf("%s: %.2f s at %d Hz\n", a.wav.c_str(), prepared.audio.duration_s(),
                prepared.audio.sample_rate);
}

}  // namespace

void add_speech_commands(CLI::App& app) {
  auto args = std::make_shared<SpeakArgs>();
  CLI::App* cmd = app.add_subcommand("speak",
                                     "Text (es, pt, en; emotion markup allowed) or a .pho + WAV to "
                                     "a lip-synced .fap and the speech audio");
  cmd->add_option("text", args->text,
                  "What to say; emotion markup such as {joy 0.7} or <Emo_Reír> (docs/speech.md)");
  cmd->add_option("--text-file", args->text_file,
                  "Read the text from a UTF-8 file (at most 20000 bytes)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--lang", args->language,
                  "Language: es, es-419, pt (Brazil), pt-pt (Portugal), en, en-us, en-gb")
      ->capture_default_str();
  cmd->add_option("--voice", args->voice, "espeak-ng voice name, overriding the one --lang picks");
  cmd->add_option("--rate", args->rate, "Speaking rate in words per minute (espeak-ng default 175)")
      ->check(CLI::Range(80, 450));
  cmd->add_option("--pho", args->pho, "MBROLA .pho file (phoneme, duration ms) instead of text")
      ->check(CLI::ExistingFile);
  cmd->add_option("--audio", args->audio,
                  "A recording (WAV, FLAC, MP3, Ogg, M4A...): with TEXT or --text-file, aligned "
                  "to that transcript; alone, English phones recognised (PocketSphinx); with "
                  "--pho, its audio")
      ->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", args->output, "Output FAP stream (.fap, .csv or .json)")
      ->required();
  cmd->add_option("--wav", args->wav, "Write the speech audio here (16-bit PCM WAV)");
  cmd->add_option("--cues", args->cues,
                  "Also write Rhubarb Lip Sync mouth cues (shapes A-H, X) here: .tsv, .json, "
                  ".xml or .dat (Moho switch data)");
  cmd->add_option("--cue-fps", args->cue_fps, "Frame rate of .dat mouth cues")
      ->check(CLI::Range(24.0, 100.0))
      ->capture_default_str();
  cmd->add_option("--viseme-script", args->viseme_script,
                  "Also write the timed visemes as a storyboard that `rostro script` runs to the "
                  "same .fap (docs/script.md)");
  cmd->add_option("--fps", args->fps, "Frames per second; frame k is audio time k/fps")
      ->capture_default_str();
  cmd->add_option("--emotion", args->emotion,
                  "Emotion for the whole clip before any tag, NAME[:INTENSITY]");
  cmd->add_option("--seed", args->seed, "Seed for blinks, saccades and head motion")
      ->capture_default_str();
  cmd->add_flag("--no-blinks", args->no_blinks, "No blinking");
  cmd->add_flag("--no-saccades", args->no_saccades, "No eye saccades");
  cmd->add_flag("--no-head-motion", args->no_head, "No idle head motion");
  cmd->add_flag("--high-level", args->high_level,
                "Also write FAP 1 (viseme blend) and FAP 2 (expression)");
  cmd->add_flag("--strict", args->strict, "Fail on phonemes the language table does not know");
  cmd->footer(R"(Example:
  rostro speak "Hola, {joy 0.8} buenos días" --lang es -o hola.fap --wav hola.wav
  rostro speak --text-file poema.txt --lang pt-pt -o poema.fap --wav poema.wav --fps 30
  rostro speak --pho hola.pho --audio hola.wav --lang es -o hola.fap
  rostro play hola.fap --audio hola.wav -o hola.mp4
  rostro speak "Hola, buenos días" --audio hola.wav --lang es -o aligned.fap --cues hola.tsv
  rostro speak --audio data/speech/samples/hello.flac --lang en -o hello.fap --cues hello.json)");
  cmd->callback([args] { speak(*args); });
}

}  // namespace rostro::app

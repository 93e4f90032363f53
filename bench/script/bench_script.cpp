// Script control cost: a 10-minute storyboard with speech, run the way `rostro script` runs
// a generated viseme script (so without synthesis): the Lua storyboard read in the sandbox,
// the scene planned (ten one-minute utterances, an expression every 5 s, a look every 7 s, a
// nod every 11 s, natural blinks and saccades, head noise) and, in the second benchmark,
// every FAP frame generated in memory. Issue 19 asks for "well under a second".

#include <benchmark/benchmark.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "facecore/expression_library.hpp"
#include "script/scene.hpp"
#include "script/storyboard_reader.hpp"
#include "script/viseme_script.hpp"
#include "speech/pipeline.hpp"

namespace {

using namespace rostro;
using namespace rostro::script;

constexpr int kMinutes = 10;

// One minute of Spanish speech, synthesised once, outside every timing.
const speech::PreparedSpeech& minute() {
  static const speech::PreparedSpeech p = [] {
    std::ifstream in(std::filesystem::path(ROSTRO_SPEECH_TEXTS) / "es.txt");
    std::stringstream ss;
    ss << in.rdbuf();
    std::string text;
    while (text.size() < 900) text += ss.str();
    speech::SpeechRequest r;
    r.text = text.substr(0, text.find(' ', 905));
    r.language = "es";
    return speech::prepare_speech(r, 0.3);
  }();
  return p;
}

// The storyboard: ten utterances of the minute's visemes, one a minute, plus the other layers.
std::filesystem::path ten_minute_story() {
  const speech::PreparedSpeech& p = minute();
  std::ostringstream lua;
  lua << "local visemes = {\n";
  for (const auto& ph : p.resolution.phonemes) {
    lua << "  {" << exact_number(ph.start_s) << ", " << exact_number(ph.end_s) << ", \""
        << ExpressionLibrary::viseme_name(ph.viseme) << "\", \""
        << (ph.cls == speech::PhonemeClass::Vowel       ? "vowel"
            : ph.cls == speech::PhonemeClass::Consonant ? "consonant"
                                                        : "silence")
        << "\"" << (ph.word >= 0 ? ", word = " + std::to_string(ph.word) : "")
        << (ph.closes_lips ? ", closes = true" : "") << "},\n";
  }
  lua << "}\n"
      << "local speech, expressions, eyes, head = {}, {}, {{'blinks'}, {'saccades'}}, {}\n"
      << "local names = {'joy', 'surprise', 'sadness', 'neutral'}\n"
      << "for m = 0, " << kMinutes - 1 << " do\n"
      << "  speech[#speech + 1] = { at = 60 * m, duration = " << exact_number(p.duration_s)
      << ", visemes = visemes }\n"
      << "end\n"
      << "for t = 0, " << kMinutes * 60 - 5 << ", 5 do\n"
      << "  expressions[#expressions + 1] = { names[t // 5 % 4 + 1], at = t, duration = 3,"
         " intensity = 0.7 }\n"
      << "end\n"
      << "for t = 1, " << kMinutes * 60 - 7 << ", 7 do\n"
      << "  eyes[#eyes + 1] = { 'look', t % 2 == 0 and 'left' or 'down_right', at = t,"
         " duration = 1.5 }\n"
      << "end\n"
      << "for t = 2, " << kMinutes * 60 - 11 << ", 11 do\n"
      << "  head[#head + 1] = { 'nod', at = t }\n"
      << "end\n"
      << "storyboard = { speech = speech, expressions = expressions, eyes = eyes, head = head }\n";
  const auto path = std::filesystem::temp_directory_path() / "rostro-bench-script.lua";
  std::ofstream(path) << lua.str();
  return path;
}

struct Libraries {
  ExpressionLibrary library = ExpressionLibrary::load_default();
  speech::KeyShapes shapes = speech::KeyShapes::load_default(library);
  speech::BehaviourSettings behaviour = speech::BehaviourSettings::load_default();
};

void run(benchmark::State& state, bool frames) {
  const auto story = ten_minute_story();
  const Libraries l;
  long count = 0;
  double seconds = 0;
  for (auto _ : state) {
    const Storyboard board = read_storyboard(story, 1);
    std::vector<std::string> warnings;
    const Scene scene(board, resolve_speech(board, l.behaviour, warnings), l.library, l.shapes,
                      l.behaviour, SceneOptions{});
    count = scene.frame_count();
    seconds = scene.duration_s();
    if (frames) {
      double sum = 0;
      for (long k = 0; k < scene.frame_count(); ++k) sum += scene.frame(k).get(3);
      benchmark::DoNotOptimize(sum);
    }
  }
  state.counters["scene_s"] = seconds;
  state.counters["frames"] = static_cast<double>(count);
}

void BM_ReadAndPlanTenMinutes(benchmark::State& state) {
  run(state, false);
}
BENCHMARK(BM_ReadAndPlanTenMinutes)->Unit(benchmark::kMillisecond);

void BM_ReadPlanAndGenerateTenMinutes(benchmark::State& state) {
  run(state, true);
}
BENCHMARK(BM_ReadPlanAndGenerateTenMinutes)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();

// Speech driver cost: planning and FAP generation for one minute of speech (synthesis
// excluded), the whole `rostro speak` path (synthesis, planning, frames, .fap and WAV
// written) as a real-time factor = processing time / audio duration, and aligning a
// minute-long recording to its transcript (`rostro speak --audio --text`).

#include <benchmark/benchmark.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "facecore/expression_library.hpp"
#include "facecore/fap_io.hpp"
#include "speech/animator.hpp"
#include "speech/espeak_synth.hpp"
#include "speech/forced_align.hpp"
#include "speech/pipeline.hpp"

namespace {

using namespace rostro;
using namespace rostro::speech;

std::string minute_of_text() {
  std::ifstream in(std::filesystem::path(ROSTRO_SPEECH_TEXTS) / "es.txt");
  std::stringstream ss;
  ss << in.rdbuf();
  std::string text;
  while (text.size() < 900) text += ss.str();
  // About 13.7 characters a second at espeak-ng's default 175 wpm: 905 characters ~ 60 s.
  return text.substr(0, text.find(' ', 905));
}

const PreparedSpeech& minute() {
  static const PreparedSpeech p = [] {
    SpeechRequest r;
    r.text = minute_of_text();
    r.language = "es";
    return prepare_speech(r, 0.3);
  }();
  return p;
}

void BM_PlanAndGenerateOneMinute(benchmark::State& state) {
  const PreparedSpeech& p = minute();
  const auto library = ExpressionLibrary::load_default();
  const auto shapes = KeyShapes::load_default(library);
  const auto behaviour = BehaviourSettings::load_default();
  AnimationOptions o;
  o.fps = static_cast<double>(state.range(0));
  const std::vector<EmotionEvent> emotions{
      {5.0, 1, 0.8, 0.3}, {20.0, 2, 0.6, 0.5}, {40.0, 0, 1.0, 0.3}};
  long frames = 0;
  for (auto _ : state) {
    const Resolution r = resolve(p.raw, LanguageTable::for_language("es"));
    const Animator a(r.phonemes, p.duration_s, emotions, library, shapes, behaviour, o);
    const FapStream s = a.stream("bench");
    frames = static_cast<long>(s.frames.size());
    benchmark::DoNotOptimize(s.frames.back().values[2]);
  }
  state.counters["audio_s"] = p.duration_s;
  state.counters["frames"] = static_cast<double>(frames);
  state.counters["frames_per_s"] = benchmark::Counter(
      static_cast<double>(frames), benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_PlanAndGenerateOneMinute)->Arg(25)->Arg(60)->Unit(benchmark::kMillisecond);

void BM_WholeSpeakCommand(benchmark::State& state) {
  const std::string text = minute_of_text().substr(0, static_cast<std::size_t>(state.range(0)));
  const auto dir = std::filesystem::temp_directory_path();
  double audio_s = 0.0, seconds = 0.0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    SpeechRequest r;
    r.text = text;
    r.language = "es";
    const PreparedSpeech p = prepare_speech(r, 0.3);
    const auto library = ExpressionLibrary::load_default();
    const auto shapes = KeyShapes::load_default(library);
    const Animator a(p.resolution.phonemes, p.duration_s, p.emotions, library, shapes,
                     BehaviourSettings::load_default(), AnimationOptions{});
    FapHeader header;
    header.fps = 25.0;
    auto sink = open_fap_sink(dir / "bench_speech.fap", header);
    for (long k = 0; k < a.frame_count(); ++k) sink->write(a.frame(k));
    sink->finish();
    write_wav(dir / "bench_speech.wav", p.audio);
    seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    audio_s += p.duration_s;
  }
  state.counters["audio_s"] = benchmark::Counter(audio_s, benchmark::Counter::kAvgIterations);
  state.counters["real_time_factor"] = seconds / audio_s;
  std::filesystem::remove(dir / "bench_speech.fap");
  std::filesystem::remove(dir / "bench_speech.wav");
}
BENCHMARK(BM_WholeSpeakCommand)->Arg(905)->Arg(100)->Unit(benchmark::kMillisecond)->Iterations(2);

// A minute-long "recording" the alignment's reference did not make: another espeak-ng voice
// at another rate, so the warping has real work to do.
const Synthesis& minute_recording() {
  static const Synthesis s = [] {
    SynthOptions o;
    o.voice = "es+f3";
    o.rate_wpm = 160;
    return synthesize(minute_of_text(), o);
  }();
  return s;
}

// Everything `rostro speak --audio --text` adds: the reference synthesis, features of both
// signals, the warping, the transcript check and the carried boundaries.
void BM_AlignOneMinute(benchmark::State& state) {
  const Synthesis& recording = minute_recording();
  const std::string text = minute_of_text();
  AlignmentOptions o;
  o.reference.voice = "es";
  for (auto _ : state) {
    const Alignment a = align_transcript(recording.audio, text, o);
    benchmark::DoNotOptimize(a.phonemes.back().start_s);
  }
  state.counters["audio_s"] = recording.audio.duration_s();
}
BENCHMARK(BM_AlignOneMinute)->Unit(benchmark::kMillisecond)->Iterations(3);

// The same without the reference synthesis (espeak-ng's share).
void BM_WarpOneMinute(benchmark::State& state) {
  const Synthesis& recording = minute_recording();
  SynthOptions voice;
  voice.voice = "es";
  const Synthesis reference = synthesize(minute_of_text(), voice);
  const AlignmentOptions o;
  for (auto _ : state) {
    const Alignment a = align_reference(recording.audio, reference.audio, reference.phonemes, o);
    benchmark::DoNotOptimize(a.phonemes.back().start_s);
  }
  state.counters["audio_s"] = recording.audio.duration_s();
}
BENCHMARK(BM_WarpOneMinute)->Unit(benchmark::kMillisecond)->Iterations(3);

}  // namespace

BENCHMARK_MAIN();

#include "speech/phone_recognizer.hpp"

#include <pocketsphinx.h>

#include <map>
#include <memory>
#include <mutex>
#include <stdexcept>

#include "facecore/error.hpp"
#include "speech/audio_file.hpp"

namespace rostro::speech {
namespace {

constexpr int kModelRate = 16000;  // the en-us acoustic model's sample rate
constexpr double kFrameS = 0.01;   // PocketSphinx's frame rate is 100 per second

struct DecoderFreer {
  void operator()(ps_decoder_t* d) const { ps_free(d); }
};

// PocketSphinx's global logging and its configuration are not documented as thread-safe.
std::mutex g_sphinx_mutex;

}  // namespace

std::string espeak_symbol_for_arpabet(const std::string& phone) {
  static const std::
      map<std::string, std::string>
          table = {{"AA", "A:"}, {"AE", "a"},  {"AH", "V"},  {"AO", "O:"}, {"AW", "aU"},
                   {"AY", "aI"}, {"B", "b"},   {"CH", "tS"}, {"D", "d"},   {"DH", "D"},
                   {"EH", "E"},  {"ER", "3:"}, {"EY", "eI"}, {"F", "f"},   {"G", "g"},
                   {"HH", "h"},  {"IH", "I"},  {"IY", "i:"}, {"JH", "dZ"}, {"K", "k"},
                   {"L", "l"},   {"M", "m"},   {"N", "n"},   {"NG", "N"},  {"OW", "oU"},
                   {"OY", "OI"}, {"P", "p"},   {"R", "r"},   {"S", "s"},   {"SH", "S"},
                   {"T", "t"},   {"TH", "T"},  {"UH", "U"},  {"UW", "u:"}, {"V", "v"},
                   {"W", "w"},   {"Y", "j"},   {"Z", "z"},   {"ZH", "Z"},  {"SIL", "_"},
                   {"AX", "@"}};  // flite's schwa; PocketSphinx says AH
  if (const auto it = table.find(phone); it != table.end()) return it->second;
  // Fillers: +NSN+ (noise), +SPN+ (spoken noise), +BREATH+... and <s>, </s>.
  if (!phone.empty() && (phone.front() == '+' || phone.front() == '<')) return "_";
  return {};
}

std::vector<RawPhoneme> recognize_phones(const Audio& recording,
                                         const PhoneRecognizerOptions& options) {
  const auto hmm = options.model_dir / "en-us";
  const auto phone_lm = options.model_dir / "en-us-phone.lm.bin";
  std::error_code ec;
  if (!std::filesystem::exists(hmm / "mdef", ec) || !std::filesystem::exists(phone_lm, ec))
    throw InputError(where(options.model_dir.string(), 0,
                           "no PocketSphinx en-us model (install pocketsphinx-en-us)"));
  const Audio audio = resample(recording, kModelRate);

  std::lock_guard lock(g_sphinx_mutex);
  // CMU's recommended phone-recognition beams; a language weight below 1 so the acoustics
  // decide more than the phone n-grams; a little dither so digital silence does not
  // confuse the models; cepstral mean over the whole recording; no silence removal (the
  // timeline must cover everything).
  cmd_ln_t* config = cmd_ln_init(
      nullptr, ps_args(), TRUE, "-hmm", hmm.c_str(), "-allphone", phone_lm.c_str(), "-allphone_ci",
      "yes", "-lw", "0.8", "-beam", "1e-20", "-pbeam", "1e-20", "-dither", "yes", "-remove_silence",
      "no", "-cmn", "batch", "-logfn", "/dev/null", "-samprate", "16000", nullptr);
  if (!config) throw std::runtime_error("PocketSphinx rejected its configuration");
  std::unique_ptr<ps_decoder_t, DecoderFreer> decoder(ps_init(config));
  cmd_ln_free_r(config);  // the decoder keeps its own reference
  if (!decoder) throw std::runtime_error("PocketSphinx could not load " + hmm.string());

  if (ps_start_utt(decoder.get()) < 0 ||
      ps_process_raw(decoder.get(), audio.samples.data(), audio.samples.size(), FALSE, TRUE) < 0 ||
      ps_end_utt(decoder.get()) < 0)
    throw std::runtime_error("PocketSphinx failed to decode the recording");

  std::vector<RawPhoneme> phones;
  for (ps_seg_t* seg = ps_seg_iter(decoder.get()); seg; seg = ps_seg_next(seg)) {
    int first = 0, last = 0;
    ps_seg_frames(seg, &first, &last);
    std::string symbol = espeak_symbol_for_arpabet(ps_seg_word(seg));
    if (symbol.empty()) symbol = "_";
    const double start = first * kFrameS;
    if (!phones.empty() && phones.back().symbol == "_" && symbol == "_") {
      phones.back().end_s = (last + 1) * kFrameS;  // one silence, not several fillers
      continue;
    }
    phones.push_back({symbol, start, (last + 1) * kFrameS, -1});
  }
  // Contiguous from 0 to the recording's end, as every recognition stage delivers.
  const double end = recording.duration_s();
  if (phones.empty()) return {{"_", 0.0, end, -1}};
  phones.front().start_s = 0.0;
  for (std::size_t k = 1; k < phones.size(); ++k) phones[k].start_s = phones[k - 1].end_s;
  phones.back().end_s = end;
  std::erase_if(phones, [&](const RawPhoneme& p) { return p.start_s >= end; });
  phones.back().end_s = end;
  return phones;
}

}  // namespace rostro::speech

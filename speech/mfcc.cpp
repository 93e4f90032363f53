#include "speech/mfcc.hpp"

#include <algorithm>
#include <cmath>
#include <complex>

#include "speech/audio_file.hpp"

namespace rostro::speech {
namespace {

constexpr double kPi = 3.14159265358979323846;
// Mean square of a -60 dBFS signal: energies are floored there, so digital silence looks like
// a quiet room rather than minus infinity (which would swamp the normalisation).
constexpr double kFloorPower = 1e-6;

double hz_to_mel(double hz) {
  return 2595.0 * std::log10(1.0 + hz / 700.0);
}
double mel_to_hz(double mel) {
  return 700.0 * (std::pow(10.0, mel / 2595.0) - 1.0);
}

// In-place iterative radix-2 FFT; `data.size()` is a power of two.
void fft(std::vector<std::complex<double>>& data) {
  const std::size_t n = data.size();
  for (std::size_t i = 1, j = 0; i < n; ++i) {
    std::size_t bit = n >> 1;
    for (; j & bit; bit >>= 1) j ^= bit;
    j ^= bit;
    if (i < j) std::swap(data[i], data[j]);
  }
  for (std::size_t len = 2; len <= n; len <<= 1) {
    const std::complex<double> step = std::polar(1.0, -2.0 * kPi / static_cast<double>(len));
    for (std::size_t i = 0; i < n; i += len) {
      std::complex<double> w(1.0, 0.0);
      for (std::size_t k = 0; k < len / 2; ++k) {
        const std::complex<double> u = data[i + k];
        const std::complex<double> v = data[i + k + len / 2] * w;
        data[i + k] = u + v;
        data[i + k + len / 2] = u - v;
        w *= step;
      }
    }
  }
}

// Triangular mel filters over the FFT bins of one frame: filters x (fft_size/2 + 1).
std::vector<std::vector<double>> mel_filters(const MfccOptions& o, int fft_size) {
  const int bins = fft_size / 2 + 1;
  const double top = std::min(o.high_hz, o.analysis_rate / 2.0);
  const double lo = hz_to_mel(o.low_hz), hi = hz_to_mel(top);
  std::vector<double> edges(o.filters + 2);
  for (int i = 0; i < o.filters + 2; ++i)
    edges[i] =
        std::min(o.warp * mel_to_hz(lo + (hi - lo) * i / (o.filters + 1)), o.analysis_rate / 2.0) *
        fft_size / o.analysis_rate;
  std::vector<std::vector<double>> bank(o.filters, std::vector<double>(bins, 0.0));
  for (int f = 0; f < o.filters; ++f)
    for (int b = 0; b < bins; ++b) {
      const double rise = (b - edges[f]) / (edges[f + 1] - edges[f]);
      const double fall = (edges[f + 2] - b) / (edges[f + 2] - edges[f + 1]);
      bank[f][b] = std::max(0.0, std::min(rise, fall));
    }
  return bank;
}

struct Framing {
  int window = 0;
  int hop = 0;
  int frames = 0;
};

Framing framing(std::size_t samples, const MfccOptions& o) {
  Framing f;
  f.window = static_cast<int>(std::lround(o.window_s * o.analysis_rate));
  f.hop = static_cast<int>(std::lround(o.hop_s * o.analysis_rate));
  // One frame per hop that starts inside the audio, so frame i is time i*hop.
  f.frames = static_cast<int>((samples + f.hop - 1) / f.hop);
  return f;
}

// Samples of frame `i`, zero past the end, scaled to [-1, 1).
void frame_samples(const std::vector<std::int16_t>& s, const Framing& f, int i,
                   std::vector<double>& out) {
  out.assign(f.window, 0.0);
  const std::size_t start = static_cast<std::size_t>(i) * f.hop;
  for (int k = 0; k < f.window && start + k < s.size(); ++k) out[k] = s[start + k] / 32768.0;
}

void normalise_columns(Features& f) {
  for (int d = 0; d < f.dims; ++d) {
    double sum = 0, sq = 0;
    for (int i = 0; i < f.frames; ++i) sum += f.row(i)[d];
    const double mean = sum / std::max(1, f.frames);
    for (int i = 0; i < f.frames; ++i) sq += (f.row(i)[d] - mean) * (f.row(i)[d] - mean);
    const double sd = std::sqrt(sq / std::max(1, f.frames)) + 1e-6;
    for (int i = 0; i < f.frames; ++i) f.row(i)[d] = static_cast<float>((f.row(i)[d] - mean) / sd);
  }
}

}  // namespace

double band_top(const Audio& a, const Audio& b, double limit_hz) {
  // 95 % of Nyquist: resamplers and codecs roll off just below it.
  return std::min({limit_hz, 0.475 * a.sample_rate, 0.475 * b.sample_rate});
}

std::vector<float> frame_energy_db(const Audio& audio, const MfccOptions& o) {
  const Audio a = resample(audio, o.analysis_rate);
  const Framing f = framing(a.samples.size(), o);
  std::vector<float> out(f.frames);
  std::vector<double> x;
  for (int i = 0; i < f.frames; ++i) {
    frame_samples(a.samples, f, i, x);
    double e = 0;
    for (double v : x) e += v * v;
    out[i] = static_cast<float>(10.0 * std::log10(e / f.window + 1e-12));
  }
  return out;
}

Features mfcc(const Audio& audio, const MfccOptions& o) {
  const Audio a = resample(audio, o.analysis_rate);
  const Framing f = framing(a.samples.size(), o);
  int fft_size = 1;
  while (fft_size < f.window) fft_size <<= 1;
  const auto bank = mel_filters(o, fft_size);
  std::vector<double> hamming(f.window);
  for (int k = 0; k < f.window; ++k)
    hamming[k] = 0.54 - 0.46 * std::cos(2.0 * kPi * k / (f.window - 1));

  Features out;
  out.frames = f.frames;
  out.dims = 2 * o.cepstra;
  out.hop_s = o.hop_s;
  out.values.assign(static_cast<std::size_t>(out.frames) * out.dims, 0.0f);
  std::vector<double> x, log_mel(o.filters);
  std::vector<std::complex<double>> spectrum(fft_size);
  for (int i = 0; i < f.frames; ++i) {
    frame_samples(a.samples, f, i, x);
    double energy = 0;
    for (double v : x) energy += v * v;
    std::fill(spectrum.begin(), spectrum.end(), 0.0);
    for (int k = f.window - 1; k > 0; --k) x[k] -= 0.97 * x[k - 1];  // pre-emphasis
    for (int k = 0; k < f.window; ++k) spectrum[k] = x[k] * hamming[k];
    fft(spectrum);
    for (int m = 0; m < o.filters; ++m) {
      double e = 0;
      for (std::size_t b = 0; b < bank[m].size(); ++b)
        if (bank[m][b] > 0) e += bank[m][b] * std::norm(spectrum[b]);
      log_mel[m] = std::log(e + f.window * kFloorPower);
    }
    float* row = out.row(i);
    row[0] = static_cast<float>(std::log(energy + f.window * kFloorPower));
    for (int c = 1; c < o.cepstra; ++c) {
      double sum = 0;
      for (int m = 0; m < o.filters; ++m)
        sum += log_mel[m] * std::cos(kPi * c * (m + 0.5) / o.filters);
      row[c] = static_cast<float>(sum);
    }
  }
  // Deltas by linear regression over +-2 frames.
  for (int i = 0; i < out.frames; ++i)
    for (int c = 0; c < o.cepstra; ++c) {
      double num = 0;
      for (int t = 1; t <= 2; ++t) {
        const int ahead = std::min(out.frames - 1, i + t), behind = std::max(0, i - t);
        num += t * static_cast<double>(out.row(ahead)[c] - out.row(behind)[c]);
      }
      out.row(i)[o.cepstra + c] = static_cast<float>(num / 10.0);
    }
  if (o.normalise) normalise_columns(out);
  if (o.delta_weight != 1.0)
    for (int i = 0; i < out.frames; ++i)
      for (int c = 0; c < o.cepstra; ++c)
        out.row(i)[o.cepstra + c] *= static_cast<float>(o.delta_weight);
  return out;
}

}  // namespace rostro::speech

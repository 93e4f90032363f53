#include "facecore/fap_summary.hpp"

#include <fmt/format.h>

#include <cmath>

namespace rostro {

void FapSummary::add(const FapFrame& frame) {
  if (frames == 0) first_index = frame.index;
  last_index = frame.index;
  ++frames;
  for (int id = 1; id <= kFapCount; ++id) {
    if (!frame.has(id)) continue;
    FapRange& r = ranges[static_cast<std::size_t>(id - 1)];
    const double v = id == kVisemeFap       ? frame.viseme.select1
                     : id == kExpressionFap ? frame.expression.select1
                                            : frame.get(id);
    ++r.frames_set;
    r.min = std::min(r.min, v);
    r.max = std::max(r.max, v);
  }
}

double FapSummary::duration_s() const {
  if (frames == 0 || header.fps <= 0) return 0.0;
  return static_cast<double>(last_index - first_index + 1) / header.fps;
}

std::string FapSummary::to_text() const {
  std::string out;
  out += fmt::format("name        {}\nversion     {}\nfps         {:g}\n", header.name,
                     header.version, header.fps);
  out += fmt::format("frames      {} (header says {})\n", frames, header.frame_count);
  out += fmt::format("duration    {:.3f} s\n", duration_s());
  int used = 0;
  for (const FapRange& r : ranges) used += r.frames_set > 0 ? 1 : 0;
  out += fmt::format("FAPs used   {}\n", used);
  if (used == 0) return out;
  out += fmt::format("\n{:>3}  {:<22} {:<6} {:>7} {:>9} {:>9}\n", "FAP", "name", "unit", "frames",
                     "min", "max");
  for (int id = 1; id <= kFapCount; ++id) {
    const FapRange& r = ranges[static_cast<std::size_t>(id - 1)];
    if (r.frames_set == 0) continue;
    const FapInfo& info = fap_info(id);
    out += fmt::format("{:>3}  {:<22} {:<6} {:>7} {:>9g} {:>9g}\n", id, info.name,
                       unit_name(info.unit), r.frames_set, r.min, r.max);
  }
  return out;
}

FapFrame synthetic_fap_frame(long index, double fps, const std::array<bool, kFapCount>& ids,
                             unsigned seed) {
  FapFrame frame;
  frame.index = index;
  frame.time_s = static_cast<double>(index) / fps;
  for (int id = 3; id <= kFapCount; ++id) {
    if (!ids[static_cast<std::size_t>(id - 1)]) continue;
    const FapInfo& info = fap_info(id);
    // Rotations in AU are a few degrees; eyelids close over a full IRISD; the rest move a
    // few hundred units, as expressions do.
    const double amplitude = info.unit == FapUnit::AU      ? 8000.0
                             : info.unit == FapUnit::IRISD ? 600.0
                                                           : 250.0;
    const double phase =
        static_cast<double>((static_cast<unsigned>(id) * 2654435761u + seed) % 628u) / 100.0;
    const double hz = 0.2 + 0.05 * static_cast<double>(id % 7);
    double v = amplitude * std::sin(2.0 * M_PI * hz * frame.time_s + phase);
    if (!info.bidirectional) v = std::abs(v);  // unidirectional FAPs never go negative
    frame.set(id, std::round(v));
  }
  return frame;
}

}  // namespace rostro

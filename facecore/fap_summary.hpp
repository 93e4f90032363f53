#pragma once
// What `rostro fap info` reports: a single pass over a stream of any length.

#include <array>
#include <limits>
#include <string>

#include "facecore/fap_frame.hpp"

namespace rostro {

struct FapRange {
  long frames_set = 0;  // frames in which the FAP is present
  double min = std::numeric_limits<double>::infinity();
  double max = -std::numeric_limits<double>::infinity();
};

struct FapSummary {
  FapHeader header;
  long frames = 0;
  long first_index = 0;
  long last_index = 0;
  std::array<FapRange, kFapCount> ranges{};  // FAPs 1 and 2: select1 values

  void add(const FapFrame& frame);
  double duration_s() const;
  std::string to_text() const;
};

// A smooth synthetic stream for demos and benchmarks: every FAP in `ids` follows its own
// sine wave of plausible amplitude. Deterministic for a given `seed`.
FapFrame synthetic_fap_frame(long index, double fps, const std::array<bool, kFapCount>& ids,
                             unsigned seed);

}  // namespace rostro

#pragma once
// One frame of facial animation: the 68 FAP values with a mask of which are set, and the
// high-level FAPs 1 (viseme) and 2 (expression) as structured fields.

#include <array>
#include <bitset>
#include <string>
#include <vector>

#include "facecore/fap_table.hpp"

namespace rostro {

// FAP 1: two of the 15 MPEG-4 visemes and a blend (0..63) between them.
struct VisemeParams {
  int select1 = 0;
  int select2 = 0;
  int blend = 0;
  int def = 0;
  bool operator==(const VisemeParams&) const = default;
};

// FAP 2: two of the six MPEG-4 expressions with intensities (0..63).
struct ExpressionParams {
  int select1 = 0;
  int intensity1 = 0;
  int select2 = 0;
  int intensity2 = 0;
  int init_face = 0;
  int def = 0;
  bool operator==(const ExpressionParams&) const = default;
};

struct FapFrame {
  long index = 0;       // frame number
  double time_s = 0.0;  // presentation time from the start of the stream
  std::bitset<kFapCount> mask;
  std::array<double, kFapCount> values{};  // values[id - 1], in the FAP's unit
  VisemeParams viseme;                     // meaningful when FAP 1 is set
  ExpressionParams expression;             // meaningful when FAP 2 is set

  bool has(int id) const { return mask.test(static_cast<std::size_t>(id - 1)); }
  // The value of a low-level FAP, 0 when it is not set (the neutral position).
  double get(int id) const { return has(id) ? values[static_cast<std::size_t>(id - 1)] : 0.0; }
  void set(int id, double value);
  void clear(int id);
  // Marks FAP 1 or 2 as present with these parameters.
  void set_viseme(const VisemeParams& v);
  void set_expression(const ExpressionParams& e);

  bool operator==(const FapFrame&) const = default;
};

// What the readers accept, so that a number never wraps on its way into a frame: a
// low-level FAP value within +-kMaxFapValue of its unit (a full head turn is 628319 AU),
// and each field of FAP 1 and 2 a whole number in 0..max.
inline constexpr double kMaxFapValue = 1e6;
struct HighLevelField {
  const char* name;
  int max;
};
inline constexpr HighLevelField kVisemeFields[4] = {
    {"select1", 14}, {"select2", 14}, {"blend", 63}, {"def", 1}};
inline constexpr HighLevelField kExpressionFields[6] = {{"select1", 6},   {"intensity1", 63},
                                                        {"select2", 6},   {"intensity2", 63},
                                                        {"init_face", 1}, {"def", 1}};
// The stream header's frame rate: finite and in (0, kMaxFps].
inline constexpr double kMaxFps = 1000.0;
inline bool valid_fps(double fps) {
  return fps > 0.0 && fps <= kMaxFps;
}

// The stream header of a .fap file.
struct FapHeader {
  std::string version = "2.1";
  std::string name = "rostro";
  double fps = 25.0;
  long frame_count = 0;
};

// A whole stream in memory; use FapReader/FapWriter for streams too long to hold.
struct FapStream {
  FapHeader header;
  std::vector<FapFrame> frames;
};

}  // namespace rostro

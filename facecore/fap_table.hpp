#pragma once
// The 68 MPEG-4 Facial Animation Parameters (ISO/IEC 14496-2), as listed in
// shared/reference/mpeg4_faps.csv: name, unit, direction and the feature point each moves.

#include <array>
#include <optional>
#include <span>
#include <string_view>

namespace rostro {

inline constexpr int kFapCount = 68;
inline constexpr int kVisemeFap = 1;
inline constexpr int kExpressionFap = 2;

// The facial animation parameter unit a FAP value is expressed in.
enum class FapUnit { None, MNS, MW, ES, ENS, IRISD, AU };

// Direction of a positive value in the face's own frame: x toward the face's left,
// y up, z out of the face.
enum class FapDirection { None, Up, Down, Left, Right, Forward, Growing, ConcaveUpward };

struct FapInfo {
  int id;                 // 1..68
  std::string_view name;  // e.g. "open_jaw"
  FapUnit unit;
  bool bidirectional;
  FapDirection positive;
  std::string_view feature_point;  // "2.1"; empty when the FAP moves no single point
  int group;                       // MPEG-4 FAP group 1..10
};

std::span<const FapInfo> fap_table();

// Throws std::out_of_range for an id outside 1..68.
const FapInfo& fap_info(int id);

bool is_fap_id(int id);
std::optional<int> find_fap(std::string_view name);

std::string_view unit_name(FapUnit unit);

// Unit vector (face frame) along which a positive value moves the FAP's feature point, or
// zero for FAPs that rotate (AU) or scale rather than translate.
std::array<double, 3> fap_axis(const FapInfo& fap);

}  // namespace rostro

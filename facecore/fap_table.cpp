#include "facecore/fap_table.hpp"

#include <stdexcept>
#include <string>

namespace rostro {
namespace {

constexpr std::array<FapInfo, kFapCount> kTable = {{
    {1, "viseme", FapUnit::None, false, FapDirection::None, "", 1},
    {2, "expression", FapUnit::None, false, FapDirection::None, "", 1},
    {3, "open_jaw", FapUnit::MNS, false, FapDirection::Down, "2.1", 2},
    {4, "lower_t_midlip", FapUnit::MNS, true, FapDirection::Down, "2.2", 2},
    {5, "raise_b_midlip", FapUnit::MNS, true, FapDirection::Up, "2.3", 2},
    {6, "stretch_l_cornerlip", FapUnit::MW, true, FapDirection::Left, "2.4", 2},
    {7, "stretch_r_cornerlip", FapUnit::MW, true, FapDirection::Right, "2.5", 2},
    {8, "lower_t_lip_lm", FapUnit::MNS, true, FapDirection::Down, "2.6", 2},
    {9, "lower_t_lip_rm", FapUnit::MNS, true, FapDirection::Down, "2.7", 2},
    {10, "raise_b_lip_lm", FapUnit::MNS, true, FapDirection::Up, "2.8", 2},
    {11, "raise_b_lip_rm", FapUnit::MNS, true, FapDirection::Up, "2.9", 2},
    {12, "raise_l_cornerlip", FapUnit::MNS, true, FapDirection::Up, "2.4", 2},
    {13, "raise_r_cornerlip", FapUnit::MNS, true, FapDirection::Up, "2.5", 2},
    {14, "thrust_jaw", FapUnit::MNS, false, FapDirection::Forward, "2.1", 2},
    {15, "shift_jaw", FapUnit::MW, true, FapDirection::Right, "2.1", 2},
    {16, "push_b_lip", FapUnit::MNS, true, FapDirection::Forward, "2.3", 2},
    {17, "push_t_lip", FapUnit::MNS, true, FapDirection::Forward, "2.2", 2},
    {18, "depress_chin", FapUnit::MNS, true, FapDirection::Up, "2.10", 2},
    {19, "close_t_l_eyelid", FapUnit::IRISD, true, FapDirection::Down, "3.1", 3},
    {20, "close_t_r_eyelid", FapUnit::IRISD, true, FapDirection::Down, "3.2", 3},
    {21, "close_b_l_eyelid", FapUnit::IRISD, true, FapDirection::Up, "3.3", 3},
    {22, "close_b_r_eyelid", FapUnit::IRISD, true, FapDirection::Up, "3.4", 3},
    {23, "yaw_l_eyeball", FapUnit::AU, true, FapDirection::Left, "", 3},
    {24, "yaw_r_eyeball", FapUnit::AU, true, FapDirection::Left, "", 3},
    {25, "pitch_l_eyeball", FapUnit::AU, true, FapDirection::Down, "", 3},
    {26, "pitch_r_eyeball", FapUnit::AU, true, FapDirection::Down, "", 3},
    {27, "thrust_l_eyeball", FapUnit::ES, true, FapDirection::Forward, "", 3},
    {28, "thrust_r_eyeball", FapUnit::ES, true, FapDirection::Forward, "", 3},
    {29, "dilate_l_pupil", FapUnit::IRISD, true, FapDirection::Growing, "3.5", 3},
    {30, "dilate_r_pupil", FapUnit::IRISD, true, FapDirection::Growing, "3.6", 3},
    {31, "raise_l_i_eyebrow", FapUnit::ENS, true, FapDirection::Up, "4.1", 4},
    {32, "raise_r_i_eyebrow", FapUnit::ENS, true, FapDirection::Up, "4.2", 4},
    {33, "raise_l_m_eyebrow", FapUnit::ENS, true, FapDirection::Up, "4.3", 4},
    {34, "raise_r_m_eyebrow", FapUnit::ENS, true, FapDirection::Up, "4.4", 4},
    {35, "raise_l_o_eyebrow", FapUnit::ENS, true, FapDirection::Up, "4.5", 4},
    {36, "raise_r_o_eyebrow", FapUnit::ENS, true, FapDirection::Up, "4.6", 4},
    {37, "squeeze_l_eyebrow", FapUnit::ES, true, FapDirection::Right, "4.1", 4},
    {38, "squeeze_r_eyebrow", FapUnit::ES, true, FapDirection::Left, "4.2", 4},
    {39, "puff_l_cheek", FapUnit::ES, true, FapDirection::Left, "5.1", 5},
    {40, "puff_r_cheek", FapUnit::ES, true, FapDirection::Right, "5.2", 5},
    {41, "lift_l_cheek", FapUnit::ENS, false, FapDirection::Up, "5.3", 5},
    {42, "lift_r_cheek", FapUnit::ENS, false, FapDirection::Up, "5.4", 5},
    {43, "shift_tongue_tip", FapUnit::MW, true, FapDirection::Right, "6.1", 6},
    {44, "raise_tongue_tip", FapUnit::MNS, true, FapDirection::Up, "6.1", 6},
    {45, "thrust_tongue_tip", FapUnit::MW, true, FapDirection::Forward, "6.1", 6},
    {46, "raise_tongue", FapUnit::MNS, true, FapDirection::Up, "6.2", 6},
    {47, "tongue_roll", FapUnit::AU, false, FapDirection::ConcaveUpward, "6.3 6.4", 6},
    {48, "head_pitch", FapUnit::AU, true, FapDirection::Down, "", 7},
    {49, "head_yaw", FapUnit::AU, true, FapDirection::Left, "", 7},
    {50, "head_roll", FapUnit::AU, true, FapDirection::Right, "", 7},
    {51, "lower_t_midlip_o", FapUnit::MNS, true, FapDirection::Down, "8.1", 8},
    {52, "raise_b_midlip_o", FapUnit::MNS, true, FapDirection::Up, "8.2", 8},
    {53, "stretch_l_cornerlip_o", FapUnit::MW, true, FapDirection::Left, "8.3", 8},
    {54, "stretch_r_cornerlip_o", FapUnit::MW, true, FapDirection::Right, "8.4", 8},
    {55, "lower_t_lip_lm_o", FapUnit::MNS, true, FapDirection::Down, "8.5", 8},
    {56, "lower_t_lip_rm_o", FapUnit::MNS, true, FapDirection::Down, "8.6", 8},
    {57, "raise_b_lip_lm_o", FapUnit::MNS, true, FapDirection::Up, "8.7", 8},
    {58, "raise_b_lip_rm_o", FapUnit::MNS, true, FapDirection::Up, "8.8", 8},
    {59, "raise_l_cornerlip_o", FapUnit::MNS, true, FapDirection::Up, "8.3", 8},
    {60, "raise_r_cornerlip_o", FapUnit::MNS, true, FapDirection::Up, "8.4", 8},
    {61, "stretch_l_nose", FapUnit::ENS, true, FapDirection::Left, "9.1", 9},
    {62, "stretch_r_nose", FapUnit::ENS, true, FapDirection::Right, "9.2", 9},
    {63, "raise_nose", FapUnit::ENS, true, FapDirection::Up, "9.3", 9},
    {64, "bend_nose", FapUnit::ENS, true, FapDirection::Right, "9.3", 9},
    {65, "raise_l_ear", FapUnit::ENS, true, FapDirection::Up, "10.1", 10},
    {66, "raise_r_ear", FapUnit::ENS, true, FapDirection::Up, "10.2", 10},
    {67, "pull_l_ear", FapUnit::ENS, true, FapDirection::Left, "10.3", 10},
    {68, "pull_r_ear", FapUnit::ENS, true, FapDirection::Right, "10.4", 10},
}};

}  // namespace

std::span<const FapInfo> fap_table() {
  return kTable;
}

bool is_fap_id(int id) {
  return id >= 1 && id <= kFapCount;
}

const FapInfo& fap_info(int id) {
  if (!is_fap_id(id)) throw std::out_of_range("FAP id " + std::to_string(id) + " is not in 1..68");
  return kTable[static_cast<std::size_t>(id - 1)];
}

std::optional<int> find_fap(std::string_view name) {
  for (const FapInfo& fap : kTable)
    if (fap.name == name) return fap.id;
  return std::nullopt;
}

std::string_view unit_name(FapUnit unit) {
  switch (unit) {
    case FapUnit::MNS:
      return "MNS";
    case FapUnit::MW:
      return "MW";
    case FapUnit::ES:
      return "ES";
    case FapUnit::ENS:
      return "ENS";
    case FapUnit::IRISD:
      return "IRISD";
    case FapUnit::AU:
      return "AU";
    case FapUnit::None:
      break;
  }
  return "-";
}

std::array<double, 3> fap_axis(const FapInfo& fap) {
  if (fap.unit == FapUnit::AU || fap.unit == FapUnit::None) return {0, 0, 0};
  switch (fap.positive) {
    case FapDirection::Up:
      return {0, 1, 0};
    case FapDirection::Down:
      return {0, -1, 0};
    case FapDirection::Left:
      return {1, 0, 0};
    case FapDirection::Right:
      return {-1, 0, 0};
    case FapDirection::Forward:
      return {0, 0, 1};
    case FapDirection::Growing:
    case FapDirection::ConcaveUpward:
    case FapDirection::None:
      break;
  }
  return {0, 0, 0};
}

}  // namespace rostro

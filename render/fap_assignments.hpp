#pragma once
// The one-frame FAP notation of `rostro pose`: "3=400,12=150" or "open_jaw=400,
// raise_l_cornerlip=150" (ids or names from the FAP table, values in the FAP's unit).

#include <string_view>

#include "facecore/fap_frame.hpp"

namespace rostro::render {

// Throws rostro::InputError naming the item for an unknown FAP, a missing or non-numeric
// value, FAP 1 or 2 (use --viseme/--expression), or a FAP given twice.
FapFrame parse_fap_assignments(std::string_view text);

}  // namespace rostro::render

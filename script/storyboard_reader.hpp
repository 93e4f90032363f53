#pragma once
// Runs a storyboard script in the sandbox and reads what it set up (docs/script.md):
//   storyboard = { fps = 25, speech = {...}, expressions = {...} or "expressions.sb",
//                  eyes = {...} or "eyes.sb", head = {...}, duration = S, output = "x.fap" }
// (or the same table returned by the chunk). Each part may be absent or "none". Entries are
// checked as they are read: an unknown expression, behaviour, voice option or field, a
// negative duration, a time running backwards: InputError naming the file and the entry.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

#include "script/lua_sandbox.hpp"
#include "script/storyboard.hpp"

namespace rostro::script {

// `seed` seeds math.random while the script runs (storyboard.seed cannot: it is read after).
Storyboard read_storyboard(const std::filesystem::path& file, std::uint64_t seed,
                           const SandboxOptions& options = {});

// Target names shared with head turns: camera, left, right, up, down and pairs such as
// "up_left"; a table {yaw=, pitch=} in degrees or {x=, y=, z=} a point in metres in the head's
// frame (x to the character's left, y up, z toward the camera). Empty on an unknown name.
std::optional<Direction> named_direction(const std::string& name, double sideways_deg,
                                         double vertical_deg);

}  // namespace rostro::script

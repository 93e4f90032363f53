#pragma once
// Where rostro's data/ folder is: $ROSTRO_DATA if set, else the source tree's data/ that the
// build recorded. Stages resolve their default files (head, layouts, tables) through it.

#include <filesystem>
#include <string_view>

namespace rostro {

std::filesystem::path data_dir();
// data_dir() / relative, throwing InputError when that file does not exist.
std::filesystem::path data_file(std::string_view relative);

}  // namespace rostro

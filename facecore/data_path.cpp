#include "facecore/data_path.hpp"

#include <cstdlib>

#include "facecore/error.hpp"

namespace rostro {

std::filesystem::path data_dir() {
  if (const char* env = std::getenv("ROSTRO_DATA"); env != nullptr && *env != '\0') return env;
  return ROSTRO_DEFAULT_DATA_DIR;
}

std::filesystem::path data_file(std::string_view relative) {
  std::filesystem::path path = data_dir() / relative;
  if (!std::filesystem::exists(path))
    throw InputError(path.string() +
                     ": rostro data file not found (set ROSTRO_DATA to the data/ folder)");
  return path;
}

}  // namespace rostro

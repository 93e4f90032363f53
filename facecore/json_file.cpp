#include "facecore/json_file.hpp"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <string>

#include "facecore/error.hpp"

namespace rostro {

nlohmann::json read_json_file(const std::filesystem::path& path, std::string_view what) {
  if (std::filesystem::is_directory(path))
    throw InputError(path.string() + ": is a folder, expected " + std::string(what));
  std::ifstream in(path);
  if (!in)
    throw InputError(path.string() + ": cannot open " + std::string(what) + ": " +
                     std::strerror(errno));
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::parse_error& e) {
    throw InputError(path.string() + ": " + std::string(what) + " is not valid JSON: " + e.what());
  }
}

}  // namespace rostro

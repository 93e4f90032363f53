#pragma once
// Small helpers for the .fap tests: write text to a file, expect an InputError mentioning
// given fragments.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "facecore/error.hpp"
#include "facecore/fap_io.hpp"

namespace rostro::test {

inline std::filesystem::path write_text(const std::filesystem::path& path,
                                        const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

// A mask line with the given FAPs set.
inline std::string mask_line(std::initializer_list<int> ids) {
  std::vector<int> mask(68, 0);
  for (int id : ids) mask[static_cast<std::size_t>(id - 1)] = 1;
  std::string line;
  for (std::size_t i = 0; i < mask.size(); ++i) line += (i ? " " : "") + std::to_string(mask[i]);
  return line;
}

// Reads the whole stream and returns the InputError message, or "" when it read cleanly.
inline std::string read_error(const std::filesystem::path& path) {
  try {
    read_fap_stream(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace rostro::test

#pragma once
// Where the tests find ../shared fixtures and scratch space.

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace rostro::test {

inline std::filesystem::path shared_dir() {
  return ROSTRO_SHARED_DIR;
}

// The Xface fixtures folder, or an empty path when ../shared is absent (callers skip).
inline std::filesystem::path xface_dir() {
  const auto dir = shared_dir() / "fixtures" / "xface";
  return std::filesystem::is_directory(dir) ? dir : std::filesystem::path();
}

// A fresh folder for one test's files, removed and recreated on each call.
inline std::filesystem::path scratch_dir(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / ("rostro-test-" + name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace rostro::test

#pragma once
// Internal to facecore: the per-format sources and sinks behind fap_io.hpp's factories.

#include <filesystem>
#include <memory>

#include "facecore/fap_io.hpp"

namespace rostro::detail {

std::unique_ptr<FapSource> open_fap_text_source(const std::filesystem::path& path);
std::unique_ptr<FapSource> open_fap_text_source(std::string name, std::string_view text);
std::unique_ptr<FapSource> open_fap_csv_source(std::string name, std::string_view text);
std::unique_ptr<FapSource> open_fap_json_source(std::string name, std::string_view text);
std::unique_ptr<FapSink> open_fap_text_sink(const std::filesystem::path& path, const FapHeader& h);
std::unique_ptr<FapSource> open_fap_csv_source(const std::filesystem::path& path);
std::unique_ptr<FapSink> open_fap_csv_sink(const std::filesystem::path& path, const FapHeader& h);
std::unique_ptr<FapSource> open_fap_json_source(const std::filesystem::path& path);
std::unique_ptr<FapSink> open_fap_json_sink(const std::filesystem::path& path, const FapHeader& h);

// Appends `value` to `out` as the shortest text that reads back to the same double.
void append_number(std::string& out, double value);

}  // namespace rostro::detail

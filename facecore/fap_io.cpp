#include "facecore/fap_io.hpp"

#include <algorithm>

#include "facecore/error.hpp"
#include "facecore/fap_formats.hpp"

namespace rostro {

FapFormat fap_format_for(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  if (ext == ".fap") return FapFormat::Fap;
  if (ext == ".csv") return FapFormat::Csv;
  if (ext == ".json") return FapFormat::Json;
  throw InputError(path.string() + ": unknown extension '" + ext +
                   "', expected .fap, .csv or .json");
}

std::unique_ptr<FapSource> open_fap_source(const std::filesystem::path& path) {
  switch (fap_format_for(path)) {
    case FapFormat::Fap:
      return detail::open_fap_text_source(path);
    case FapFormat::Csv:
      return detail::open_fap_csv_source(path);
    case FapFormat::Json:
      return detail::open_fap_json_source(path);
  }
  return nullptr;
}

std::unique_ptr<FapSource> open_fap_source(std::string name, std::string_view text,
                                           FapFormat format) {
  switch (format) {
    case FapFormat::Fap:
      return detail::open_fap_text_source(std::move(name), text);
    case FapFormat::Csv:
      return detail::open_fap_csv_source(std::move(name), text);
    case FapFormat::Json:
      return detail::open_fap_json_source(std::move(name), text);
  }
  return nullptr;
}

std::unique_ptr<FapSink> open_fap_sink(const std::filesystem::path& path, const FapHeader& header) {
  switch (fap_format_for(path)) {
    case FapFormat::Fap:
      return detail::open_fap_text_sink(path, header);
    case FapFormat::Csv:
      return detail::open_fap_csv_sink(path, header);
    case FapFormat::Json:
      return detail::open_fap_json_sink(path, header);
  }
  return nullptr;
}

FapStream read_fap_stream(const std::filesystem::path& path) {
  auto source = open_fap_source(path);
  FapStream stream;
  stream.header = source->header();
  FapFrame frame;
  while (source->next(frame)) stream.frames.push_back(frame);
  stream.header.frame_count = static_cast<long>(stream.frames.size());
  return stream;
}

void write_fap_stream(const std::filesystem::path& path, const FapStream& stream) {
  auto sink = open_fap_sink(path, stream.header);
  for (const FapFrame& frame : stream.frames) sink->write(frame);
  sink->finish();
}

}  // namespace rostro

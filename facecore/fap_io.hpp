#pragma once
// Streaming access to FAP streams in any of the formats rostro reads and writes.
// A source hands out one frame at a time; a sink writes one frame at a time to a
// temporary file and only puts it in place on finish(), so a failure never leaves half a
// file where the user asked for one.

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "facecore/fap_frame.hpp"

namespace rostro {

class FapSource {
 public:
  virtual ~FapSource() = default;
  virtual const FapHeader& header() const = 0;
  // Fills `frame` with the next frame; false at the end. Throws InputError naming the
  // file, the line and what was expected.
  virtual bool next(FapFrame& frame) = 0;
};

class FapSink {
 public:
  virtual ~FapSink() = default;
  virtual void write(const FapFrame& frame) = 0;
  // Completes the file and moves it into place. Without it the output is discarded.
  virtual void finish() = 0;
  virtual long frames_written() const = 0;
};

enum class FapFormat { Fap, Csv, Json };

// By extension: .fap, .csv, .json. Throws InputError for anything else.
FapFormat fap_format_for(const std::filesystem::path& path);

std::unique_ptr<FapSource> open_fap_source(const std::filesystem::path& path);
// `header.frame_count` need not be known in advance: sinks count what they write.
std::unique_ptr<FapSink> open_fap_sink(const std::filesystem::path& path, const FapHeader& header);

// Whole-stream conveniences for short streams (tests, expressions, speech clips).
FapStream read_fap_stream(const std::filesystem::path& path);
void write_fap_stream(const std::filesystem::path& path, const FapStream& stream);

// Reads a .fap file to the end and lists every problem found (at most `max_problems`),
// each as "path:line: what", instead of stopping at the first.
std::vector<std::string> validate_fap_file(const std::filesystem::path& path,
                                           std::size_t max_problems = 100);

// The number of values a value line carries for FAP `id` (4 for FAP 1, 6 for FAP 2, else 1).
int fap_value_count(int id);

}  // namespace rostro

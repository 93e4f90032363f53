#pragma once
// Streaming access to FAP streams in any of the formats rostro reads and writes.
// A source hands out one frame at a time; a sink writes one frame at a time to a
// temporary file and only puts it in place on finish(), so a failure never leaves half a
// file where the user asked for one.

#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
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
  // The same under another name: a take kept after a failure (NAME.partial.fap). Also after
  // write() failed (a full disk): the file then holds the frames that reached the disk whole.
  virtual void finish_as(const std::filesystem::path& destination) = 0;
  // The frames written so far; after a failed write(), the frames kept.
  virtual long frames_written() const = 0;
  // Why the 2004 Xface reader cannot load the .fap written so far, or empty (always empty for
  // CSV and JSON, which Xface does not read): it reads the frame rate as a whole number and
  // FAP 1 and FAP 2 as one number each, so a rate of 29.97 loads nothing and the high-level
  // FAPs' 4 and 6 fields shift every later value.
  virtual std::string xface_warning() const { return {}; }
};

enum class FapFormat { Fap, Csv, Json };

// By extension: .fap, .csv, .json. Throws InputError for anything else.
FapFormat fap_format_for(const std::filesystem::path& path);

std::unique_ptr<FapSource> open_fap_source(const std::filesystem::path& path);
// The same from memory (`text` must outlive the source); `name` stands for the path in
// messages. For tests and fuzzing.
std::unique_ptr<FapSource> open_fap_source(std::string name, std::string_view text,
                                           FapFormat format);
// `header.frame_count` need not be known in advance: sinks count what they write.
std::unique_ptr<FapSink> open_fap_sink(const std::filesystem::path& path, const FapHeader& header);

// Whole-stream conveniences for short streams (tests, expressions, speech clips).
FapStream read_fap_stream(const std::filesystem::path& path);
void write_fap_stream(const std::filesystem::path& path, const FapStream& stream);

// Reads a .fap file to the end and lists every problem found (at most `max_problems`),
// each as "path:line: what", instead of stopping at the first.
std::vector<std::string> validate_fap_file(const std::filesystem::path& path,
                                           std::size_t max_problems = 100);

// Turns the temporary a killed writer left (NAME.fap.tmp-PID) into a valid stream at
// `output`: every frame whose lines are whole, up to the first line that is not (the
// writer's last bytes). `vouched` is the header's count, the frames the writer had
// checkpointed (at most a second before it stopped); `stopped` says why reading ended early,
// empty when it reached the end of the file.
struct RecoveredTake {
  long frames = 0;
  long vouched = 0;
  std::string stopped;
};
RecoveredTake recover_fap_file(const std::filesystem::path& input,
                               const std::filesystem::path& output);

// The number of values a value line carries for FAP `id` (4 for FAP 1, 6 for FAP 2, else 1).
int fap_value_count(int id);

}  // namespace rostro

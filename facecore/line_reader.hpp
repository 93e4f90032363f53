#pragma once
// A fast buffered line reader for the text formats rostro parses (.fap, CSV). It hands out
// each line without its line ending (CRLF or LF) and counts lines for error messages.

#include <cstdio>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace rostro {

class LineReader {
 public:
  // Throws InputError when the file cannot be opened.
  explicit LineReader(const std::filesystem::path& path);
  // Reads `text`, which must outlive the reader; `name` stands for the path in messages.
  LineReader(std::string name, std::string_view text);
  ~LineReader();
  LineReader(const LineReader&) = delete;
  LineReader& operator=(const LineReader&) = delete;

  // The next line, valid until the following call; false at the end of the file.
  bool next(std::string_view& line);
  long line_number() const { return line_number_; }
  // False when the line last handed out ended the file without a line ending (a writer
  // stopped in the middle of it).
  bool last_line_terminated() const { return terminated_; }
  const std::string& path() const { return path_; }

 private:
  bool refill();
  std::string path_;
  std::FILE* file_ = nullptr;
  std::vector<char> buffer_;
  std::size_t begin_ = 0;
  std::size_t end_ = 0;
  bool eof_ = false;
  std::string carry_;  // a line longer than the buffer
  long line_number_ = 0;
  bool terminated_ = true;
};

// Splits on spaces and tabs; empty tokens are skipped.
void split_whitespace(std::string_view line, std::vector<std::string_view>& tokens);

// Strict number parsing: the whole token must be the number.
bool parse_long(std::string_view token, long& out);
bool parse_double(std::string_view token, double& out);

}  // namespace rostro

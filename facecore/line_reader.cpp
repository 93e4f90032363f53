#include "facecore/line_reader.hpp"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>

#include "facecore/error.hpp"

namespace rostro {

LineReader::LineReader(const std::filesystem::path& path) : path_(path.string()), buffer_(1 << 20) {
  if (std::filesystem::is_directory(path)) throw InputError(path_ + ": is a folder, not a file");
  file_ = std::fopen(path_.c_str(), "rb");
  if (file_ == nullptr) throw InputError(path_ + ": cannot open: " + std::strerror(errno));
}

LineReader::LineReader(std::string name, std::string_view text)
    : path_(std::move(name)), buffer_(std::min<std::size_t>(1 << 20, text.size() + 1)) {
  // fmemopen refuses an empty buffer: an empty text is a reader at its end.
  if (text.empty()) {
    eof_ = true;
    return;
  }
  file_ = ::fmemopen(const_cast<char*>(text.data()), text.size(), "rb");
  if (file_ == nullptr) throw InputError(path_ + ": cannot read from memory");
}

LineReader::~LineReader() {
  if (file_ != nullptr) std::fclose(file_);
}

bool LineReader::refill() {
  if (eof_) return false;
  begin_ = 0;
  end_ = std::fread(buffer_.data(), 1, buffer_.size(), file_);
  if (end_ == 0) eof_ = true;
  return end_ > 0;
}

bool LineReader::next(std::string_view& line) {
  carry_.clear();
  bool have_carry = false;
  for (;;) {
    if (begin_ == end_ && !refill()) {
      if (!have_carry) return false;
      terminated_ = false;
      break;  // last line without a newline
    }
    const char* start = buffer_.data() + begin_;
    const auto* newline = static_cast<const char*>(std::memchr(start, '\n', end_ - begin_));
    if (newline == nullptr) {
      carry_.append(start, end_ - begin_);
      have_carry = true;
      begin_ = end_;
      continue;
    }
    const std::size_t length = static_cast<std::size_t>(newline - start);
    begin_ += length + 1;
    if (have_carry) {
      carry_.append(start, length);
      terminated_ = true;
      break;
    }
    line = std::string_view(start, length);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    ++line_number_;
    terminated_ = true;
    return true;
  }
  line = carry_;
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  ++line_number_;
  return true;
}

void split_whitespace(std::string_view line, std::vector<std::string_view>& tokens) {
  tokens.clear();
  std::size_t i = 0;
  const std::size_t n = line.size();
  while (i < n) {
    while (i < n && (line[i] == ' ' || line[i] == '\t')) ++i;
    const std::size_t start = i;
    while (i < n && line[i] != ' ' && line[i] != '\t') ++i;
    if (i > start) tokens.push_back(line.substr(start, i - start));
  }
}

bool parse_long(std::string_view token, long& out) {
  if (!token.empty() && token.front() == '+') token.remove_prefix(1);
  auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), out);
  return ec == std::errc() && end == token.data() + token.size() && !token.empty();
}

bool parse_double(std::string_view token, double& out) {
  if (!token.empty() && token.front() == '+') token.remove_prefix(1);
  auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), out);
  return ec == std::errc() && end == token.data() + token.size() && !token.empty() &&
         std::isfinite(out);
}

}  // namespace rostro

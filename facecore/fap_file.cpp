// The MPEG-4 ASCII FAP format as Xface reads and writes it:
//   <version> <name> <fps> <frame count>
//   then per frame a mask line of 68 0/1 values and a value line: the frame number, then
//   the values of the masked FAPs in order (FAP 1 takes 4, FAP 2 takes 6, others 1).
// Lines starting with '#' are comments. Read as the 2004 Xface reader reads it too: FAP 1
// and FAP 2 as one number each, and value lines wrapped over several lines.

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "facecore/atomic_file.hpp"
#include "facecore/error.hpp"
#include "facecore/fap_formats.hpp"
#include "facecore/line_reader.hpp"

namespace rostro {

int fap_value_count(int id) {
  if (id == kVisemeFap) return 4;
  if (id == kExpressionFap) return 6;
  return 1;
}

namespace {

// Reads a .fap file frame by frame. Problems are reported through `report`; in strict use
// it throws, while the validator records them and resynchronises at the next line.
class FapTextParser {
 public:
  explicit FapTextParser(const std::filesystem::path& path) : lines_(path) {}
  FapTextParser(std::string name, std::string_view text) : lines_(std::move(name), text) {}

  // For the temporary of a killed writer: the header's count is a lower bound, and a line
  // cut short by the end of the file ends the stream instead of being read.
  void recover() { recovering_ = true; }

  // Returns the problem with the header, or nothing.
  std::optional<std::string> read_header();
  const FapHeader& header() const { return header_; }

  enum class Step { Frame, End, Problem };
  // Reads one frame. On Problem, `problem` holds "path:line: what" and the parser has
  // consumed the offending line, so the caller may continue with the next frame.
  Step next(FapFrame& frame, std::string& problem);

 private:
  bool next_content_line(std::string_view& line);
  std::string at(const std::string& what) const {
    return where(lines_.path(), lines_.line_number(), what);
  }
  Step parse_values(FapFrame& frame, std::string_view line, std::string& problem);

  LineReader lines_;
  FapHeader header_;
  std::vector<std::string_view> tokens_;
  std::string joined_;  // a value line wrapped over several lines, joined
  std::bitset<kFapCount> mask_;
  long frames_read_ = 0;
  long last_frame_number_ = -1;
  bool saw_extra_ = false;
  bool recovering_ = false;
};

bool FapTextParser::next_content_line(std::string_view& line) {
  while (lines_.next(line)) {
    if (recovering_ && !lines_.last_line_terminated()) return false;
    std::size_t i = 0;
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    if (i == line.size() || line[i] == '#') continue;
    return true;
  }
  return false;
}

std::optional<std::string> FapTextParser::read_header() {
  std::string_view line;
  if (!next_content_line(line))
    return where(lines_.path(), 0, "empty file: expected a header 'version name fps frame_count'");
  split_whitespace(line, tokens_);
  if (tokens_.size() < 4)
    return at("header has " + std::to_string(tokens_.size()) +
              " fields, expected 'version name fps frame_count'");
  double version = 0;
  if (!parse_double(tokens_[0], version))
    return at("header version '" + std::string(tokens_[0]) + "' is not a number");
  header_.version = std::string(tokens_[0]);
  // The name is any token; real files carry Windows paths. A name with spaces is joined.
  header_.name = std::string(tokens_[1]);
  for (std::size_t i = 2; i + 2 < tokens_.size(); ++i)
    header_.name += " " + std::string(tokens_[i]);
  const std::string_view fps = tokens_[tokens_.size() - 2];
  const std::string_view count = tokens_.back();
  if (!parse_double(fps, header_.fps) || !valid_fps(header_.fps))
    return at("header fps '" + std::string(fps) + "' is not a number in (0, 1000]");
  if (!parse_long(count, header_.frame_count) || header_.frame_count < 0)
    return at("header frame count '" + std::string(count) + "' is not a whole number >= 0");
  return std::nullopt;
}

FapTextParser::Step FapTextParser::next(FapFrame& frame, std::string& problem) {
  std::string_view line;
  if (!next_content_line(line)) {
    if (frames_read_ < header_.frame_count && !recovering_) {
      problem = where(lines_.path(), lines_.line_number(),
                      "file ends after " + std::to_string(frames_read_) + " frames, header says " +
                          std::to_string(header_.frame_count) + " (truncated?)");
      frames_read_ = header_.frame_count;  // report truncation once
      return Step::Problem;
    }
    return Step::End;
  }
  if (frames_read_ >= header_.frame_count && !saw_extra_ && !recovering_) {
    saw_extra_ = true;
    problem = at("more frames than the header's count of " + std::to_string(header_.frame_count));
    return Step::Problem;
  }
  split_whitespace(line, tokens_);
  if (tokens_.size() != kFapCount) {
    problem = at("mask line has " + std::to_string(tokens_.size()) + " values, expected 68");
    std::string_view skipped;
    next_content_line(skipped);  // its value line
    ++frames_read_;
    return Step::Problem;
  }
  mask_.reset();
  for (std::size_t i = 0; i < tokens_.size(); ++i) {
    if (tokens_[i] == "1") {
      mask_.set(i);
    } else if (tokens_[i] != "0") {
      problem = at("mask value " + std::to_string(i + 1) + " is '" + std::string(tokens_[i]) +
                   "', expected 0 or 1");
      std::string_view skipped;
      next_content_line(skipped);
      ++frames_read_;
      return Step::Problem;
    }
  }
  if (!next_content_line(line)) {
    if (recovering_) return Step::End;
    problem = at("file ends after a mask line: expected the frame's value line (truncated?)");
    frames_read_ = header_.frame_count;
    return Step::Problem;
  }
  ++frames_read_;
  return parse_values(frame, line, problem);
}

FapTextParser::Step FapTextParser::parse_values(FapFrame& frame, std::string_view line,
                                                std::string& problem) {
  // The standard writes FAP 1 as 4 fields and FAP 2 as 6; the 2004 Xface reader reads and
  // writes one number for each (taken here as the first viseme or expression, at full
  // weight). Either is accepted, told apart by the number of values.
  std::size_t full = 1;
  for (int id = 1; id <= kFapCount; ++id)
    if (mask_.test(static_cast<std::size_t>(id - 1)))
      full += static_cast<std::size_t>(fap_value_count(id));
  const bool has_viseme = mask_.test(kVisemeFap - 1);
  const bool has_expression = mask_.test(kExpressionFap - 1);
  const std::size_t shortest = full - (has_viseme ? 3 : 0) - (has_expression ? 5 : 0);
  // Xface reads values as a stream of numbers, so a value line may be wrapped over several
  // lines: the next lines are joined until there are enough.
  split_whitespace(line, tokens_);
  if (tokens_.size() < shortest) {
    joined_.assign(line);
    std::string_view more;
    while (tokens_.size() < shortest && next_content_line(more)) {
      joined_ += ' ';
      joined_ += more;
      split_whitespace(joined_, tokens_);
    }
  }
  const std::size_t count = tokens_.size();
  const bool one_number_viseme = has_viseme && (count == full - 3 || count == full - 8);
  const bool one_number_expression = has_expression && (count == full - 5 || count == full - 8);
  if (count != full && !one_number_viseme && !one_number_expression) {
    problem =
        at("value line has " + std::to_string(count) + " fields, expected " + std::to_string(full) +
           " (frame number + values of " + std::to_string(mask_.count()) + " masked FAPs" +
           (has_viseme || has_expression ? ", or " + std::to_string(shortest) +
                                               " with FAP 1 and 2 as one number each as Xface "
                                               "writes them)"
                                         : ")"));
    return Step::Problem;
  }
  long number = 0;
  if (!parse_long(tokens_[0], number) || number < 0) {
    problem = at("frame number '" + std::string(tokens_[0]) + "' is not a whole number >= 0");
    return Step::Problem;
  }
  if (number <= last_frame_number_) {
    problem = at("frame number " + std::to_string(number) + " is out of order (after " +
                 std::to_string(last_frame_number_) + ")");
    return Step::Problem;
  }
  frame = FapFrame{};
  frame.index = number;
  frame.time_s = static_cast<double>(number) / header_.fps;
  frame.mask = mask_;
  std::size_t t = 1;
  // Each value is checked against its type and meaning; a problem quotes its own token.
  const auto bad = [&](int id, const std::string& which, const std::string& wanted) {
    problem = at(which + "FAP " + std::to_string(id) + " (" + std::string(fap_info(id).name) +
                 ") is '" + std::string(tokens_[t]) + "', expected " + wanted);
    return Step::Problem;
  };
  const auto field = [&](int& out, const HighLevelField& f) {
    double v = 0;
    if (!parse_double(tokens_[t], v) || v < -0.5 || v >= f.max + 0.5) return false;
    out = static_cast<int>(std::lround(v));
    ++t;
    return true;
  };
  for (int id = 1; id <= kFapCount; ++id) {
    if (!mask_.test(static_cast<std::size_t>(id - 1))) continue;
    if ((id == kVisemeFap && one_number_viseme) ||
        (id == kExpressionFap && one_number_expression)) {
      const bool is_viseme = id == kVisemeFap;
      const HighLevelField& select = is_viseme ? kVisemeFields[0] : kExpressionFields[0];
      int chosen = 0;
      if (!field(chosen, select))
        return bad(id, "",
                   "one whole number in 0.." + std::to_string(select.max) +
                       " (Xface's form) or its " + (is_viseme ? "4" : "6") + " fields");
      if (is_viseme)
        frame.viseme = {chosen, 0, 63, 0};
      else
        frame.expression = {chosen, 63, 0, 0, 0, 0};
    } else if (id == kVisemeFap || id == kExpressionFap) {
      VisemeParams& v = frame.viseme;
      ExpressionParams& e = frame.expression;
      int* viseme[] = {&v.select1, &v.select2, &v.blend, &v.def};
      int* expression[] = {&e.select1,    &e.intensity1, &e.select2,
                           &e.intensity2, &e.init_face,  &e.def};
      const bool is_viseme = id == kVisemeFap;
      const HighLevelField* fields = is_viseme ? kVisemeFields : kExpressionFields;
      const int n = is_viseme ? 4 : 6;
      for (int k = 0; k < n; ++k)
        if (!field(*(is_viseme ? viseme[k] : expression[k]), fields[k]))
          return bad(id, std::string(fields[k].name) + " of ",
                     "a whole number in 0.." + std::to_string(fields[k].max));
    } else {
      double& value = frame.values[static_cast<std::size_t>(id - 1)];
      if (!parse_double(tokens_[t], value) || std::abs(value) > kMaxFapValue)
        return bad(id, "value of ", "a number within +-1000000");
      ++t;
    }
  }
  last_frame_number_ = number;
  return Step::Frame;
}

class FapTextSource final : public FapSource {
 public:
  explicit FapTextSource(const std::filesystem::path& path) : parser_(path) {
    if (auto problem = parser_.read_header()) throw InputError(*problem);
  }
  FapTextSource(std::string name, std::string_view text) : parser_(std::move(name), text) {
    if (auto problem = parser_.read_header()) throw InputError(*problem);
  }
  const FapHeader& header() const override { return parser_.header(); }
  bool next(FapFrame& frame) override {
    std::string problem;
    switch (parser_.next(frame, problem)) {
      case FapTextParser::Step::Frame:
        return true;
      case FapTextParser::Step::End:
        return false;
      case FapTextParser::Step::Problem:
        break;
    }
    throw InputError(problem);
  }

 private:
  FapTextParser parser_;
};

// A take on disk is readable at every moment (DESIGN.md): the frame count sits in a
// fixed-width field of the header line, and at each checkpoint (a second of the take, or
// a second of wall-clock time, whichever comes first) the frames formatted since are
// appended straight to the kernel and the field is rewritten to vouch for them; the data is
// synced to the disk at most once a wall-clock second. A process killed at any point leaves
// the temporary NAME.tmp-PID whose header vouches for every frame up to the last checkpoint,
// which `rostro fap recover` turns into a valid file. A failed write (a full disk) cuts the
// temporary back to the last checkpoint, so the frames before it stay whole.
constexpr int kCountFieldWidth = 12;

class FapTextSink final : public FapSink {
 public:
  using Clock = std::chrono::steady_clock;

  FapTextSink(const std::filesystem::path& path, const FapHeader& header) : file_(path) {
    std::string name = header.name.empty() ? std::string("rostro") : header.name;
    for (char& c : name)
      if (c == ' ' || c == '\t' || c == '\n' || c == '\r') c = '_';
    // Xface reads the name into 255 bytes.
    if (name.size() > 200) name.resize(200);
    std::string line = header.version + " " + name + " ";
    fps_ = header.fps;
    detail::append_number(line, header.fps);
    line += ' ';
    count_offset_ = static_cast<off_t>(line.size());
    line += count_field(0);
    line += '\n';
    file_.append_now(line);
    durable_offset_ = static_cast<off_t>(line.size());
    const double fps = std::isfinite(header.fps) ? std::clamp(header.fps, 1.0, 1000.0) : 25.0;
    frames_per_checkpoint_ = std::max(1L, std::lround(fps));
    next_checkpoint_ = next_sync_ = Clock::now() + std::chrono::seconds(1);
    pending_.reserve(1 << 16);
  }

  void write(const FapFrame& frame) override {
    if (!failure_.empty()) throw InputError(failure_);
    for (int i = 0; i < kFapCount; ++i) {
      pending_ += frame.mask.test(static_cast<std::size_t>(i)) ? '1' : '0';
      pending_ += i + 1 < kFapCount ? ' ' : '\n';
    }
    append_int(frame.index);
    wrote_high_level_ = wrote_high_level_ || frame.has(kVisemeFap) || frame.has(kExpressionFap);
    for (int id = 1; id <= kFapCount; ++id) {
      if (!frame.has(id)) continue;
      if (id == kVisemeFap) {
        const VisemeParams& v = frame.viseme;
        for (int x : {v.select1, v.select2, v.blend, v.def}) space_int(x);
      } else if (id == kExpressionFap) {
        const ExpressionParams& e = frame.expression;
        for (int x : {e.select1, e.intensity1, e.select2, e.intensity2, e.init_face, e.def})
          space_int(x);
      } else {
        // The standard quantises FAPs to integers in their unit.
        space_int(std::lround(frame.values[static_cast<std::size_t>(id - 1)]));
      }
    }
    pending_ += '\n';
    ++written_;
    if (written_ - durable_frames_ >= frames_per_checkpoint_ || pending_.size() >= (1u << 20) ||
        Clock::now() >= next_checkpoint_)
      checkpoint();
  }

  void finish() override { finish_as(file_.destination()); }

  void finish_as(const std::filesystem::path& destination) override {
    if (failure_.empty()) checkpoint();
    file_.sync();
    file_.commit_as(destination);
  }

  long frames_written() const override { return written_; }

  std::string xface_warning() const override {
    std::string why;
    if (fps_ != std::floor(fps_)) {
      why = "its frame rate ";
      detail::append_number(why, fps_);
      why += " is not a whole number";
    }
    if (wrote_high_level_)
      why += std::string(why.empty() ? "" : " and ") +
             "it holds the high-level FAP 1/2 with all their fields";
    return why.empty() ? why : "Xface (2004) cannot read it: " + why;
  }

 private:
  static std::string count_field(long count) {
    char field[kCountFieldWidth + 1];
    std::snprintf(field, sizeof field, "%-*ld", kCountFieldWidth, count);
    return std::string(field, kCountFieldWidth);
  }

  void checkpoint() {
    const auto now = Clock::now();
    next_checkpoint_ = now + std::chrono::seconds(1);
    if (pending_.empty()) return;
    try {
      file_.append_now(pending_);
    } catch (const InputError& e) {
      // Keep what reached the disk whole: cut back to the last checkpoint, which the
      // header's count already vouches for.
      pending_.clear();
      written_ = durable_frames_;
      failure_ = e.what();
      file_.truncate(durable_offset_);
      throw;
    }
    durable_offset_ += static_cast<off_t>(pending_.size());
    durable_frames_ = written_;
    pending_.clear();
    file_.write_at(count_offset_, count_field(durable_frames_));
    if (now >= next_sync_) {
      file_.sync();
      next_sync_ = now + std::chrono::seconds(1);
    }
  }

  void append_int(long value) {
    char digits[24];
    auto [end, ec] = std::to_chars(digits, digits + sizeof digits, value);
    pending_.append(digits, end);
  }
  void space_int(long value) {
    pending_ += ' ';
    append_int(value);
  }

  AtomicFile file_;
  std::string pending_;  // frames formatted since the last checkpoint
  off_t count_offset_ = 0;
  off_t durable_offset_ = 0;  // the file's size at the last checkpoint
  long durable_frames_ = 0;   // the frames the header vouches for
  long written_ = 0;
  long frames_per_checkpoint_ = 25;
  double fps_ = 25;
  bool wrote_high_level_ = false;
  Clock::time_point next_checkpoint_, next_sync_;
  std::string failure_;  // after a failed write: its message
};

}  // namespace

namespace detail {

std::unique_ptr<FapSource> open_fap_text_source(const std::filesystem::path& path) {
  return std::make_unique<FapTextSource>(path);
}

std::unique_ptr<FapSink> open_fap_text_sink(const std::filesystem::path& path,
                                            const FapHeader& header) {
  return std::make_unique<FapTextSink>(path, header);
}

std::unique_ptr<FapSource> open_fap_text_source(std::string name, std::string_view text) {
  return std::make_unique<FapTextSource>(std::move(name), text);
}

void append_number(std::string& out, double value) {
  char digits[32];
  auto [end, ec] = std::to_chars(digits, digits + sizeof digits, value);
  out.append(digits, end);
}

}  // namespace detail

namespace {

// Reads every frame to the end of the file, handing each to `on_frame` and each problem to
// `on_problem`, which returns false to stop there.
template <typename OnFrame, typename OnProblem>
void read_frames(FapTextParser& parser, OnFrame on_frame, OnProblem on_problem) {
  FapFrame frame;
  std::string problem;
  for (;;) {
    const auto step = parser.next(frame, problem);
    if (step == FapTextParser::Step::End) return;
    if (step == FapTextParser::Step::Frame)
      on_frame(frame);
    else if (!on_problem(problem))
      return;
  }
}

}  // namespace

std::vector<std::string> validate_fap_file(const std::filesystem::path& path,
                                           std::size_t max_problems) {
  std::vector<std::string> problems;
  FapTextParser parser(path);
  if (auto problem = parser.read_header()) return {*problem};
  read_frames(
      parser, [](const FapFrame&) {},
      [&](const std::string& problem) {
        problems.push_back(problem);
        if (problems.size() < max_problems) return true;
        problems.push_back(path.string() + ": stopped after " + std::to_string(max_problems) +
                           " problems");
        return false;
      });
  return problems;
}

RecoveredTake recover_fap_file(const std::filesystem::path& input,
                               const std::filesystem::path& output) {
  FapTextParser parser(input);
  parser.recover();
  if (auto problem = parser.read_header()) throw InputError(*problem);
  RecoveredTake take;
  take.vouched = parser.header().frame_count;
  FapHeader header = parser.header();
  header.frame_count = 0;
  auto sink = open_fap_sink(output, header);
  read_frames(
      parser, [&](const FapFrame& frame) { sink->write(frame); },
      [&](const std::string& problem) {
        take.stopped = problem;  // the writer's last, unsynced bytes: keep what came before
        return false;
      });
  take.frames = sink->frames_written();
  sink->finish();
  return take;
}

}  // namespace rostro

// FAP streams as CSV: one row per frame, one column per FAP named as in the FAP table, an
// empty cell where a FAP is not set. A leading comment line keeps what the .fap header
// holds, so a .fap -> .csv -> .fap round trip loses nothing:
//   # rostro-fap version=2.1 name=joy fps=25
//   frame,time_s,viseme_select1,...,expression_def,open_jaw,...,pull_r_ear

#include <chrono>
#include <cmath>
#include <string>
#include <vector>

#include "facecore/atomic_file.hpp"
#include "facecore/error.hpp"
#include "facecore/fap_formats.hpp"
#include "facecore/line_reader.hpp"

namespace rostro {
namespace {

constexpr const char* kViseme[] = {"viseme_select1", "viseme_select2", "viseme_blend",
                                   "viseme_def"};
constexpr const char* kExpression[] = {"expression_select1",   "expression_intensity1",
                                       "expression_select2",   "expression_intensity2",
                                       "expression_init_face", "expression_def"};
constexpr std::size_t kColumns = 2 + 4 + 6 + (kFapCount - 2);

std::vector<std::string> column_names() {
  std::vector<std::string> names = {"frame", "time_s"};
  for (const char* n : kViseme) names.emplace_back(n);
  for (const char* n : kExpression) names.emplace_back(n);
  for (int id = 3; id <= kFapCount; ++id) names.emplace_back(fap_info(id).name);
  return names;
}

void split_commas(std::string_view line, std::vector<std::string_view>& cells) {
  cells.clear();
  std::size_t start = 0;
  for (;;) {
    const std::size_t comma = line.find(',', start);
    std::string_view cell =
        line.substr(start, comma == std::string_view::npos ? line.npos : comma - start);
    while (!cell.empty() && cell.front() == ' ') cell.remove_prefix(1);
    while (!cell.empty() && cell.back() == ' ') cell.remove_suffix(1);
    cells.push_back(cell);
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
}

class CsvSource final : public FapSource {
 public:
  explicit CsvSource(const std::filesystem::path& path) : lines_(path) { read_header(); }
  CsvSource(std::string name, std::string_view text) : lines_(std::move(name), text) {
    read_header();
  }

  const FapHeader& header() const override { return header_; }

  bool next(FapFrame& frame) override {
    std::string_view line;
    do {
      if (!lines_.next(line)) return false;
    } while (line.empty() || line.front() == '#');
    split_commas(line, cells_);
    if (cells_.size() != kColumns)
      throw InputError(at("row has " + std::to_string(cells_.size()) + " cells, expected " +
                          std::to_string(kColumns)));
    frame = FapFrame{};
    long index = 0;
    if (!parse_long(cells_[0], index) || index <= last_index_)
      throw InputError(at("frame '" + std::string(cells_[0]) +
                          "' is not a whole number after the previous frame"));
    last_index_ = index;
    frame.index = index;
    if (!parse_double(cells_[1], frame.time_s))
      throw InputError(at("time_s '" + std::string(cells_[1]) + "' is not a number"));
    std::size_t c = 2;
    int high[10];
    for (int k = 0; k < 10; ++k, ++c) {
      const HighLevelField& f = k < 4 ? kVisemeFields[k] : kExpressionFields[k - 4];
      double v = 0;
      if (cells_[c].empty()) {
        high[k] = 0;
        continue;
      }
      if (!parse_double(cells_[c], v) || v < -0.5 || v >= f.max + 0.5)
        throw bad_cell(c, "a whole number in 0.." + std::to_string(f.max) + " or nothing");
      high[k] = static_cast<int>(std::lround(v));
      if (k < 4)
        frame.mask.set(kVisemeFap - 1);
      else
        frame.mask.set(kExpressionFap - 1);
    }
    frame.viseme = {high[0], high[1], high[2], high[3]};
    frame.expression = {high[4], high[5], high[6], high[7], high[8], high[9]};
    for (int id = 3; id <= kFapCount; ++id, ++c) {
      if (cells_[c].empty()) continue;
      double v = 0;
      if (!parse_double(cells_[c], v) || std::abs(v) > kMaxFapValue)
        throw bad_cell(c, "a number within +-1000000 or nothing");
      frame.set(id, v);
    }
    return true;
  }

 private:
  void read_header() {
    std::string_view line;
    bool have_fps = false;
    while (lines_.next(line)) {
      if (line.empty()) continue;
      if (line.front() == '#') {
        have_fps |= parse_metadata(line);
        continue;
      }
      break;
    }
    split_commas(line, cells_);
    const auto names = column_names();
    if (cells_.size() != kColumns)
      throw InputError(at("CSV header has " + std::to_string(cells_.size()) +
                          " columns, expected " + std::to_string(kColumns) +
                          " (frame, time_s, then one per FAP)"));
    for (std::size_t i = 0; i < kColumns; ++i)
      if (cells_[i] != names[i])
        throw InputError(at("CSV column " + std::to_string(i + 1) + " is '" +
                            std::string(cells_[i]) + "', expected '" + names[i] + "'"));
    if (!have_fps)
      throw InputError(
          at("no '# rostro-fap ... fps=N' line before the header: the frame rate is unknown"));
  }

  bool parse_metadata(std::string_view line) {
    std::vector<std::string_view> tokens;
    split_whitespace(line.substr(1), tokens);
    if (tokens.empty() || tokens[0] != "rostro-fap") return false;
    bool fps = false;
    for (std::string_view t : tokens) {
      const auto eq = t.find('=');
      if (eq == std::string_view::npos) continue;
      const std::string_view key = t.substr(0, eq), value = t.substr(eq + 1);
      if (key == "version")
        header_.version = std::string(value);
      else if (key == "name")
        header_.name = std::string(value);
      else if (key == "fps" && !(parse_double(value, header_.fps) && valid_fps(header_.fps)))
        throw InputError(at("fps '" + std::string(value) + "' is not a frame rate in (0, 1000]"));
      else if (key == "fps")
        fps = true;
      else if (key == "frames")
        parse_long(value, header_.frame_count);
    }
    return fps;
  }
  InputError bad_cell(std::size_t c, const std::string& expected) const {
    return InputError(at("column " + column_names()[c] + " holds '" + std::string(cells_[c]) +
                         "', expected " + expected));
  }
  std::string at(const std::string& what) const {
    return where(lines_.path(), lines_.line_number(), what);
  }

  LineReader lines_;
  FapHeader header_;
  std::vector<std::string_view> cells_;
  long last_index_ = -1;
};

class CsvSink final : public FapSink {
 public:
  CsvSink(const std::filesystem::path& path, const FapHeader& header) : file_(path) {
    std::string line = "# rostro-fap version=" + header.version + " name=" + header.name + " fps=";
    detail::append_number(line, header.fps);
    line += '\n';
    const auto names = column_names();
    for (std::size_t i = 0; i < names.size(); ++i) line += (i ? "," : "") + names[i];
    line += '\n';
    file_.write(line);
  }

  void write(const FapFrame& frame) override {
    row_.clear();
    detail::append_number(row_, static_cast<double>(frame.index));
    row_ += ',';
    detail::append_number(row_, frame.time_s);
    const bool viseme = frame.has(kVisemeFap), expression = frame.has(kExpressionFap);
    const VisemeParams& v = frame.viseme;
    const ExpressionParams& e = frame.expression;
    for (int x : {v.select1, v.select2, v.blend, v.def}) cell(viseme, x);
    for (int x : {e.select1, e.intensity1, e.select2, e.intensity2, e.init_face, e.def})
      cell(expression, x);
    // FAPs are integers in the standard; every writer quantises alike.
    for (int id = 3; id <= kFapCount; ++id) cell(frame.has(id), std::round(frame.get(id)));
    row_ += '\n';
    file_.write(row_);
    ++written_;
    // Handed to the kernel once a second: a killed writer leaves every whole row up to its
    // last second in NAME.csv.tmp-PID.
    if (const auto now = std::chrono::steady_clock::now(); now >= next_flush_) {
      file_.flush();
      next_flush_ = now + std::chrono::seconds(1);
    }
  }

  void finish() override { file_.commit(); }
  void finish_as(const std::filesystem::path& destination) override {
    file_.commit_as(destination);
  }
  long frames_written() const override { return written_; }

 private:
  void cell(bool present, double value) {
    row_ += ',';
    if (present) detail::append_number(row_, value);
  }
  AtomicFile file_;
  std::string row_;
  long written_ = 0;
  std::chrono::steady_clock::time_point next_flush_;
};

}  // namespace

namespace detail {
std::unique_ptr<FapSource> open_fap_csv_source(const std::filesystem::path& path) {
  return std::make_unique<CsvSource>(path);
}
std::unique_ptr<FapSource> open_fap_csv_source(std::string name, std::string_view text) {
  return std::make_unique<CsvSource>(std::move(name), text);
}
std::unique_ptr<FapSink> open_fap_csv_sink(const std::filesystem::path& path, const FapHeader& h) {
  return std::make_unique<CsvSink>(path, h);
}
}  // namespace detail

}  // namespace rostro

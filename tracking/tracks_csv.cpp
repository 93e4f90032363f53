#include "tracking/tracks_csv.hpp"

#include <charconv>
#include <cmath>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <string_view>

#include "facecore/error.hpp"

namespace rostro::tracking {
namespace {

constexpr std::string_view kHeader = "frame,time_s,marker,fp,x,y,valid,quality";
constexpr int kColumns = 8;
// A frame's TrackedFrame::identification, on a comment line before its rows.
constexpr std::string_view kIdentification = "# identification: ";

// Shortest text that reads back to the same double: ground truth survives a round trip.
void append_number(std::string& out, double value) {
  char buffer[64];
  auto [end, ec] = std::to_chars(buffer, buffer + sizeof buffer, value);
  out.append(buffer, end);
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r'))
    s.remove_suffix(1);
  return s;
}

}  // namespace

std::string feature_point_text(FeaturePointId id) {
  return id == FeaturePointId{} ? std::string() : id.str();
}

// ---------------------------------------------------------------------------------------
// Writing

TracksWriter::TracksWriter(const std::filesystem::path& path) : file_(path) {
  file_.write(kHeader);
  file_.write("\n");
}

void TracksWriter::write(const TrackedFrame& frame) {
  std::string rows;
  if (!frame.identification.empty()) {
    rows += kIdentification;
    for (char c : frame.identification) rows += c == '\n' || c == '\r' ? ' ' : c;
    rows += '\n';
  }
  for (const MarkerObservation& m : frame.markers) {
    if (m.marker.empty() || m.marker.find_first_of(",\n\r\"") != std::string::npos)
      throw InputError(file_.destination().string() + ": frame " + std::to_string(frame.frame) +
                       ": marker id '" + m.marker +
                       "' cannot be written to CSV (empty, or holds a comma, quote or newline)");
    rows += std::to_string(frame.frame);
    rows += ',';
    append_number(rows, frame.time_s);
    rows += ',';
    rows += m.marker;
    rows += ',';
    rows += feature_point_text(m.feature_point);
    rows += ',';
    // An invalid marker's position means nothing; a non-finite one is left empty.
    if (std::isfinite(m.position.x) && std::isfinite(m.position.y)) {
      append_number(rows, m.position.x);
      rows += ',';
      append_number(rows, m.position.y);
    } else {
      rows += ',';
    }
    rows += m.valid ? ",1," : ",0,";
    append_number(rows, m.quality);
    rows += '\n';
  }
  file_.write(rows);
  if (const auto now = std::chrono::steady_clock::now(); now >= next_flush_) {
    file_.flush();
    next_flush_ = now + std::chrono::seconds(1);
  }
}

void TracksWriter::finish() {
  file_.commit();
}

void TracksWriter::finish_as(const std::filesystem::path& destination) {
  file_.commit_as(destination);
}

void write_tracks(const std::filesystem::path& path, const std::vector<TrackedFrame>& frames) {
  TracksWriter writer(path);
  for (const TrackedFrame& f : frames) writer.write(f);
  writer.finish();
}

// ---------------------------------------------------------------------------------------
// Reading

struct TracksReader::State {
  std::string path;
  std::unique_ptr<std::istream> stream;
  std::istream& in() { return *stream; }
  long line_number = 0;
  bool have_pending = false;  // a row already read that starts the next frame
  long pending_line = 0;
  TrackedFrame pending_frame;  // frame/time (and identification) of the pending row
  MarkerObservation pending;
  std::string note;  // the last identification comment, for the next row
  long last_frame = 0;
  bool any_frame = false;
  // A problem found past the end of a whole frame: reported on the next call, so that the
  // frame before it is not lost.
  std::string deferred;

  [[noreturn]] void fail(long line, const std::string& what) const {
    throw InputError(where(path, line, what));
  }

  double number(std::string_view field, long line, const char* column) const {
    field = trim(field);
    double value = 0;
    auto [end, ec] = std::from_chars(field.data(), field.data() + field.size(), value);
    if (field.empty() || ec != std::errc() || end != field.data() + field.size() ||
        !std::isfinite(value))
      fail(line, std::string("column '") + column + "' should be a finite number, got '" +
                     std::string(field) + "'");
    return value;
  }

  long integer(std::string_view field, long line, const char* column) const {
    field = trim(field);
    long value = 0;
    auto [end, ec] = std::from_chars(field.data(), field.data() + field.size(), value);
    if (field.empty() || ec != std::errc() || end != field.data() + field.size())
      fail(line, std::string("column '") + column + "' should be an integer, got '" +
                     std::string(field) + "'");
    return value;
  }

  // Reads the next data row into pending*; false at the end of the file.
  bool read_row() {
    std::string text;
    while (std::getline(in(), text)) {
      ++line_number;
      std::string_view line = trim(text);
      if (line.empty()) continue;
      if (line.front() == '#') {  // a comment; an identification one belongs to the next row
        if (line.starts_with(kIdentification)) note = line.substr(kIdentification.size());
        continue;
      }
      std::string_view fields[kColumns];
      int count = 0;
      size_t start = 0;
      while (true) {
        size_t comma = line.find(',', start);
        std::string_view field = line.substr(
            start, comma == std::string_view::npos ? std::string_view::npos : comma - start);
        if (count < kColumns) fields[count] = field;
        ++count;
        if (comma == std::string_view::npos) break;
        start = comma + 1;
      }
      if (count != kColumns)
        fail(line_number, "expected " + std::to_string(kColumns) + " columns (" +
                              std::string(kHeader) + "), found " + std::to_string(count));

      pending_line = line_number;
      pending_frame.frame = integer(fields[0], line_number, "frame");
      if (pending_frame.frame < 0) fail(line_number, "frame numbers cannot be negative");
      pending_frame.time_s = number(fields[1], line_number, "time_s");
      pending_frame.identification = std::move(note);
      note.clear();
      pending = MarkerObservation{};
      pending.marker = std::string(trim(fields[2]));
      if (pending.marker.empty()) fail(line_number, "column 'marker' is empty");
      std::string_view fp = trim(fields[3]);
      if (!fp.empty()) {
        auto id = parse_feature_point(fp);
        if (!id)
          fail(line_number, "unknown feature point '" + std::string(fp) +
                                "' (expected an MPEG-4 point such as 3.5, or empty)");
        pending.feature_point = *id;
      }
      long valid = integer(fields[6], line_number, "valid");
      if (valid != 0 && valid != 1)
        fail(line_number, "column 'valid' should be 0 or 1, got " + std::to_string(valid));
      pending.valid = valid == 1;
      // Positions may be empty only for invalid markers (nothing is known about them).
      if (!pending.valid && trim(fields[4]).empty() && trim(fields[5]).empty()) {
        pending.position = {std::nan(""), std::nan("")};
      } else {
        pending.position.x = number(fields[4], line_number, "x");
        pending.position.y = number(fields[5], line_number, "y");
      }
      pending.quality = number(fields[7], line_number, "quality");
      have_pending = true;
      return true;
    }
    if (in().bad()) fail(line_number, "read error");
    return false;
  }
};

TracksReader::TracksReader(const std::filesystem::path& path) : state_(std::make_unique<State>()) {
  state_->path = path.string();
  auto file = std::make_unique<std::ifstream>(path);
  if (!*file) throw InputError(where(state_->path, 0, "cannot open the tracks file"));
  state_->stream = std::move(file);
  read_header();
}

TracksReader::TracksReader(std::string name, std::string_view text)
    : state_(std::make_unique<State>()) {
  state_->path = std::move(name);
  state_->stream = std::make_unique<std::istringstream>(std::string(text));
  read_header();
}

void TracksReader::read_header() {
  std::string header;
  while (std::getline(state_->in(), header)) {
    ++state_->line_number;
    if (!trim(header).empty()) break;
  }
  if (trim(header) != kHeader)
    state_->fail(state_->line_number, "expected the header '" + std::string(kHeader) +
                                          "', found '" + std::string(trim(header)) + "'");
}

TracksReader::~TracksReader() = default;

bool TracksReader::next(TrackedFrame& frame) {
  if (!state_->deferred.empty()) throw InputError(state_->deferred);
  State& s = *state_;
  if (!s.have_pending && !s.read_row()) return false;

  frame = TrackedFrame{};
  frame.frame = s.pending_frame.frame;
  frame.time_s = s.pending_frame.time_s;
  frame.identification = s.pending_frame.identification;
  if (s.any_frame && frame.frame <= s.last_frame)
    s.fail(s.pending_line, "frame " + std::to_string(frame.frame) + " comes after frame " +
                               std::to_string(s.last_frame) +
                               " (frames must increase and a frame's rows be together)");
  s.any_frame = true;
  s.last_frame = frame.frame;

  std::set<std::string> seen;
  do {
    if (s.pending_frame.frame != frame.frame) {
      if (s.pending_frame.frame < frame.frame)
        s.deferred =
            where(s.path, s.pending_line,
                  "frame " + std::to_string(s.pending_frame.frame) + " comes after frame " +
                      std::to_string(frame.frame) + " (frames must be in increasing order)");
      return true;  // the pending row starts the next frame
    }
    if (s.pending_frame.time_s != frame.time_s)
      s.fail(s.pending_line, "time_s differs between rows of frame " + std::to_string(frame.frame));
    if (!seen.insert(s.pending.marker).second)
      s.fail(s.pending_line, "marker '" + s.pending.marker + "' appears twice in frame " +
                                 std::to_string(frame.frame));
    frame.markers.push_back(std::move(s.pending));
    s.have_pending = false;
    try {
      if (!s.read_row()) break;
    } catch (const InputError& e) {
      s.deferred = e.what();
      break;
    }
  } while (true);
  return true;
}

std::vector<TrackedFrame> read_tracks(const std::filesystem::path& path) {
  TracksReader reader(path);
  std::vector<TrackedFrame> frames;
  TrackedFrame frame;
  while (reader.next(frame)) frames.push_back(std::move(frame));
  return frames;
}

}  // namespace rostro::tracking

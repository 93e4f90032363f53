#include "eval/ibug_pts.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

#include "facecore/error.hpp"

namespace rostro::eval {
namespace {

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return {};
  const auto e = s.find_last_not_of(" \t\r");
  return s.substr(b, e - b + 1);
}

bool parse_number(const std::string& token, double& out) {
  const char* end = token.data() + token.size();
  auto [ptr, ec] = std::from_chars(token.data(), end, out);
  return ec == std::errc() && ptr == end && std::isfinite(out);
}

}  // namespace

bool natural_less(const std::string& a, const std::string& b) {
  std::size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    const bool da = std::isdigit(static_cast<unsigned char>(a[i])) != 0;
    const bool db = std::isdigit(static_cast<unsigned char>(b[j])) != 0;
    if (da && db) {
      std::size_t ie = i, je = j;
      while (ie < a.size() && std::isdigit(static_cast<unsigned char>(a[ie]))) ++ie;
      while (je < b.size() && std::isdigit(static_cast<unsigned char>(b[je]))) ++je;
      // Compare digit runs as numbers: strip leading zeros, then longer is larger.
      std::string_view na(a.data() + i, ie - i), nb(b.data() + j, je - j);
      while (na.size() > 1 && na.front() == '0') na.remove_prefix(1);
      while (nb.size() > 1 && nb.front() == '0') nb.remove_prefix(1);
      if (na.size() != nb.size()) return na.size() < nb.size();
      if (na != nb) return na < nb;
      i = ie;
      j = je;
    } else {
      if (a[i] != b[j]) return a[i] < b[j];
      ++i;
      ++j;
    }
  }
  return a.size() - i < b.size() - j;
}

std::vector<cv::Point2d> read_pts(const std::filesystem::path& path) {
  const std::string name = path.string();
  std::ifstream in(path);
  if (!in) throw InputError(name + ": cannot open the .pts file");
  std::string line;
  long line_no = 0;
  long declared = -1;
  bool in_points = false, closed = false;
  std::vector<cv::Point2d> points;
  while (std::getline(in, line)) {
    ++line_no;
    const std::string t = trim(line);
    if (t.empty()) continue;
    const std::string at = name + ":" + std::to_string(line_no) + ": ";
    if (closed) throw InputError(at + "unexpected text after the closing '}'");
    if (!in_points) {
      if (t == "{") {
        if (declared < 0) throw InputError(at + "expected 'n_points: N' before '{'");
        in_points = true;
      } else if (t.rfind("version:", 0) == 0) {
        continue;
      } else if (t.rfind("n_points:", 0) == 0) {
        double n = 0;
        if (!parse_number(trim(t.substr(9)), n) || n < 1 || n != std::floor(n))
          throw InputError(at + "expected 'n_points: N' with a positive whole N");
        declared = static_cast<long>(n);
      } else {
        throw InputError(at + "expected 'version:', 'n_points:' or '{', found '" + t + "'");
      }
      continue;
    }
    if (t == "}") {
      closed = true;
      continue;
    }
    std::istringstream tokens(t);
    std::string xs, ys, extra;
    tokens >> xs >> ys;
    double x = 0, y = 0;
    if (!parse_number(xs, x) || !parse_number(ys, y) || (tokens >> extra))
      throw InputError(at + "expected a point 'x y', found '" + t + "'");
    points.push_back({x, y});
  }
  if (!in_points) throw InputError(name + ": no point block ('{' ... '}') found");
  if (!closed) throw InputError(name + ": the point block is not closed with '}'");
  if (static_cast<long>(points.size()) != declared)
    throw InputError(name + ": n_points says " + std::to_string(declared) + " but " +
                     std::to_string(points.size()) + " points follow");
  return points;
}

std::vector<std::filesystem::path> list_pts_sequence(const std::filesystem::path& path) {
  namespace fs = std::filesystem;
  std::vector<fs::path> files;
  if (fs::is_directory(path)) {
    for (const auto& entry : fs::directory_iterator(path))
      if (entry.is_regular_file() && entry.path().extension() == ".pts")
        files.push_back(entry.path());
    std::sort(files.begin(), files.end(), [](const fs::path& a, const fs::path& b) {
      return natural_less(a.filename().string(), b.filename().string());
    });
    if (files.empty()) throw InputError(path.string() + ": the folder holds no .pts files");
    return files;
  }
  std::ifstream in(path);
  if (!in)
    throw InputError(path.string() + ": cannot open (expected a folder of .pts files or a list)");
  std::string line;
  long line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    const std::string t = trim(line);
    if (t.empty() || t.front() == '#') continue;
    fs::path file = t;
    if (file.is_relative()) file = path.parent_path() / file;
    if (file.extension() != ".pts")
      throw InputError(where(path.string(), line_no, "expected a .pts path, found '" + t + "'"));
    files.push_back(file);
  }
  if (files.empty()) throw InputError(path.string() + ": the list names no .pts files");
  return files;
}

std::vector<tracking::TrackedFrame> read_pts_sequence(
    const std::vector<std::filesystem::path>& files, const IbugMapping& mapping, long first_frame,
    double fps) {
  std::vector<tracking::TrackedFrame> frames;
  frames.reserve(files.size());
  for (std::size_t k = 0; k < files.size(); ++k) {
    const auto points = read_pts(files[k]);
    if (static_cast<int>(points.size()) < mapping.point_count)
      throw InputError(files[k].string() + ": has " + std::to_string(points.size()) +
                       " points, the mapping needs " + std::to_string(mapping.point_count));
    tracking::TrackedFrame f;
    f.frame = first_frame + static_cast<long>(k);
    f.time_s = fps > 0 ? static_cast<double>(k) / fps : 0.0;
    for (const IbugMarker& m : mapping.markers) {
      cv::Point2d sum(0, 0);
      for (int i : m.points) sum += points[static_cast<std::size_t>(i)];
      tracking::MarkerObservation o;
      o.marker = m.marker;
      o.feature_point = m.feature_point;
      o.position = sum / static_cast<double>(m.points.size());
      o.valid = true;
      o.quality = 1.0;
      f.markers.push_back(std::move(o));
    }
    frames.push_back(std::move(f));
  }
  return frames;
}

}  // namespace rostro::eval

// FAP streams as JSON:
//   {"format": "rostro-fap", "version": "2.1", "name": "joy", "fps": 25, "frame_count": 2,
//    "frames": [{"frame": 0, "time_s": 0, "faps": {"open_jaw": 120, ...},
//                "viseme": {...}, "expression": {...}}, ...]}
// Written as a stream; read whole (JSON is for interchange with other tools, not for
// hour-long takes: use .fap or .csv for those).

#include <cmath>
#include <nlohmann/json.hpp>

#include "facecore/atomic_file.hpp"
#include "facecore/error.hpp"
#include "facecore/fap_formats.hpp"
#include "facecore/json_file.hpp"

namespace rostro {
namespace {

using nlohmann::json;

class JsonSource final : public FapSource {
 public:
  explicit JsonSource(const std::filesystem::path& path) : path_(path.string()) {
    init(read_json_file(path, "the FAP stream"));
  }
  JsonSource(std::string name, std::string_view text) : path_(std::move(name)) {
    init(parse_json_text(text, path_, "the FAP stream"));
  }

  const FapHeader& header() const override { return header_; }

  bool next(FapFrame& frame) override {
    if (next_ >= frames_.size()) return false;
    const json& f = frames_[next_];
    const std::string here = path_ + ": frames[" + std::to_string(next_) + "]";
    ++next_;
    if (!f.is_object()) throw InputError(here + " should be an object");
    frame = FapFrame{};
    frame.index = json_integer(f, "frame", 0, kMaxFrameIndex, here);
    frame.time_s =
        json_number_or(f, "time_s", static_cast<double>(frame.index) / header_.fps, here);
    if (f.contains("faps")) {
      const json& faps = f.at("faps");
      if (!faps.is_object()) throw InputError(here + ": 'faps' should be an object");
      for (const auto& [name, value] : faps.items()) {
        const auto id = find_fap(name);
        if (!id || *id <= kExpressionFap) throw InputError(here + ": unknown FAP '" + name + "'");
        const double v = json_number(faps, name.c_str(), here + ": faps");
        if (std::abs(v) > kMaxFapValue)
          throw InputError(here + ": faps: '" + name + "' should be within +-1000000, not " +
                           value.dump());
        frame.set(*id, v);
      }
    }
    const auto high = [&](const char* key, const HighLevelField* fields, int n, int* out[]) {
      const json& o = f.at(key);
      const std::string context = here + ": " + key;
      if (!o.is_object()) throw InputError(context + " should be an object");
      for (int k = 0; k < n; ++k) {
        // select1, select2, blend and intensities are required; def and init_face default 0.
        const std::string name = fields[k].name;
        const bool optional = name == "def" || name == "init_face";
        *out[k] = static_cast<int>(
            optional ? json_integer_or(o, fields[k].name, 0, 0, fields[k].max, context)
                     : json_integer(o, fields[k].name, 0, fields[k].max, context));
      }
    };
    if (f.contains("viseme")) {
      VisemeParams v;
      int* out[] = {&v.select1, &v.select2, &v.blend, &v.def};
      high("viseme", kVisemeFields, 4, out);
      frame.set_viseme(v);
    }
    if (f.contains("expression")) {
      ExpressionParams e;
      int* out[] = {&e.select1, &e.intensity1, &e.select2, &e.intensity2, &e.init_face, &e.def};
      high("expression", kExpressionFields, 6, out);
      frame.set_expression(e);
    }
    return true;
  }

 private:
  // Frame numbers stay well inside a long, so that index / fps and index + 1 never wrap.
  static constexpr long kMaxFrameIndex = 1L << 53;

  void init(const json& doc) {
    if (!doc.is_object()) throw InputError(path_ + ": a FAP stream should be a JSON object");
    if (json_string_or(doc, "format", "", path_) != "rostro-fap")
      throw InputError(path_ + ": expected \"format\": \"rostro-fap\"");
    header_.version = json_string_or(doc, "version", "2.1", path_);
    header_.name = json_string_or(doc, "name", "rostro", path_);
    header_.fps = json_number(doc, "fps", path_);
    if (!valid_fps(header_.fps))
      throw InputError(path_ + ": 'fps' should be in (0, 1000], not " + doc.at("fps").dump());
    if (!doc.contains("frames") || !doc.at("frames").is_array())
      throw InputError(path_ + ": 'frames' should be an array");
    frames_ = doc.at("frames");
    header_.frame_count = static_cast<long>(frames_.size());
  }

  std::string path_;
  FapHeader header_;
  json frames_;
  std::size_t next_ = 0;
};

class JsonSink final : public FapSink {
 public:
  JsonSink(const std::filesystem::path& path, const FapHeader& header) : file_(path) {
    json head = {{"format", "rostro-fap"},
                 {"version", header.version},
                 {"name", header.name},
                 {"fps", header.fps}};
    std::string text = head.dump();
    text.pop_back();  // reopen the object to stream the frames in
    text += ",\"frames\":[\n";
    file_.write(text);
  }

  void write(const FapFrame& frame) override {
    json f = {{"frame", frame.index}, {"time_s", frame.time_s}};
    json faps = json::object();
    for (int id = 3; id <= kFapCount; ++id)
      if (frame.has(id))  // integers, as every writer quantises
        faps[std::string(fap_info(id).name)] = std::llround(frame.get(id));
    f["faps"] = std::move(faps);
    if (frame.has(kVisemeFap)) {
      const VisemeParams& v = frame.viseme;
      f["viseme"] = {
          {"select1", v.select1}, {"select2", v.select2}, {"blend", v.blend}, {"def", v.def}};
    }
    if (frame.has(kExpressionFap)) {
      const ExpressionParams& e = frame.expression;
      f["expression"] = {{"select1", e.select1},     {"intensity1", e.intensity1},
                         {"select2", e.select2},     {"intensity2", e.intensity2},
                         {"init_face", e.init_face}, {"def", e.def}};
    }
    file_.write(written_ == 0 ? "" : ",\n");
    file_.write(f.dump());
    ++written_;
  }

  void finish() override { finish_as(file_.destination()); }
  void finish_as(const std::filesystem::path& destination) override {
    file_.write("\n],\"frame_count\":" + std::to_string(written_) + "}\n");
    file_.commit_as(destination);
  }
  long frames_written() const override { return written_; }

 private:
  AtomicFile file_;
  long written_ = 0;
};

}  // namespace

namespace detail {
std::unique_ptr<FapSource> open_fap_json_source(const std::filesystem::path& path) {
  return std::make_unique<JsonSource>(path);
}
std::unique_ptr<FapSource> open_fap_json_source(std::string name, std::string_view text) {
  return std::make_unique<JsonSource>(std::move(name), text);
}
std::unique_ptr<FapSink> open_fap_json_sink(const std::filesystem::path& path, const FapHeader& h) {
  return std::make_unique<JsonSink>(path, h);
}
}  // namespace detail

}  // namespace rostro

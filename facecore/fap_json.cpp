// FAP streams as JSON:
//   {"format": "rostro-fap", "version": "2.1", "name": "joy", "fps": 25, "frame_count": 2,
//    "frames": [{"frame": 0, "time_s": 0, "faps": {"open_jaw": 120, ...},
//                "viseme": {...}, "expression": {...}}, ...]}
// Written as a stream; read whole (JSON is for interchange with other tools, not for
// hour-long takes: use .fap or .csv for those).

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
    const json doc = read_json_file(path, "the FAP stream");
    try {
      if (doc.value("format", "") != "rostro-fap")
        throw InputError(path_ + ": expected \"format\": \"rostro-fap\"");
      header_.version = doc.value("version", "2.1");
      header_.name = doc.value("name", "rostro");
      header_.fps = doc.at("fps").get<double>();
      if (header_.fps <= 0) throw InputError(path_ + ": fps must be positive");
      frames_ = doc.at("frames");
      if (!frames_.is_array()) throw InputError(path_ + ": \"frames\" must be an array");
      header_.frame_count = static_cast<long>(frames_.size());
    } catch (const json::exception& e) {
      throw InputError(path_ + ": " + e.what());
    }
  }

  const FapHeader& header() const override { return header_; }

  bool next(FapFrame& frame) override {
    if (next_ >= frames_.size()) return false;
    const json& f = frames_[next_];
    const std::string here = path_ + ": frames[" + std::to_string(next_) + "]";
    ++next_;
    try {
      frame = FapFrame{};
      frame.index = f.at("frame").get<long>();
      frame.time_s = f.value("time_s", static_cast<double>(frame.index) / header_.fps);
      if (f.contains("faps")) {
        for (const auto& [name, value] : f.at("faps").items()) {
          const auto id = find_fap(name);
          if (!id || *id <= kExpressionFap) throw InputError(here + ": unknown FAP '" + name + "'");
          frame.set(*id, value.get<double>());
        }
      }
      if (f.contains("viseme")) {
        const json& v = f.at("viseme");
        frame.set_viseme({v.at("select1").get<int>(), v.at("select2").get<int>(),
                          v.at("blend").get<int>(), v.value("def", 0)});
      }
      if (f.contains("expression")) {
        const json& e = f.at("expression");
        frame.set_expression({e.at("select1").get<int>(), e.at("intensity1").get<int>(),
                              e.at("select2").get<int>(), e.at("intensity2").get<int>(),
                              e.value("init_face", 0), e.value("def", 0)});
      }
    } catch (const json::exception& e) {
      throw InputError(here + ": " + e.what());
    }
    return true;
  }

 private:
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
      if (frame.has(id)) faps[std::string(fap_info(id).name)] = frame.get(id);
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

  void finish() override {
    file_.write("\n],\"frame_count\":" + std::to_string(written_) + "}\n");
    file_.commit();
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
std::unique_ptr<FapSink> open_fap_json_sink(const std::filesystem::path& path, const FapHeader& h) {
  return std::make_unique<JsonSink>(path, h);
}
}  // namespace detail

}  // namespace rostro

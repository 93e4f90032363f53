#include "facecore/expression_library.hpp"

#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "facecore/atomic_file.hpp"
#include "facecore/data_path.hpp"
#include "facecore/error.hpp"
#include "facecore/fap_table.hpp"
#include "facecore/json_file.hpp"

namespace rostro {
namespace {

using nlohmann::json;

constexpr std::array<std::string_view, kExpressionCount> kExpressionNames = {
    "neutral", "joy", "sadness", "anger", "fear", "disgust", "surprise"};

constexpr std::array<std::string_view, kVisemeCount> kVisemeNames = {
    "sil", "p_b_m", "f_v", "th_dh", "t_d", "k_g", "ch_jh_sh", "s_z",
    "n_l", "r",     "aa",  "eh",    "ih",  "oh",  "uh"};

// {"open_jaw": 300, "raise_l_cornerlip_o": 150, ...} -> a frame with those FAPs set.
FapFrame fap_vector(const json& j, const std::string& context) {
  if (!j.is_object()) throw InputError(context + ": expected an object of FAP name -> value");
  FapFrame frame;
  for (const auto& [name, value] : j.items()) {
    const auto id = find_fap(name);
    if (!id || *id <= kExpressionFap)
      throw InputError(context + ": '" + name + "' is not a low-level FAP name (3..68)");
    if (!value.is_number())
      throw InputError(context + ": the value of " + name + " is not a number");
    frame.set(*id, value.get<double>());
  }
  return frame;
}

// The low-level FAPs a frame sets, by name: integers stay integers in the file.
json fap_object(const FapFrame& frame) {
  json j = json::object();
  for (int id = kExpressionFap + 1; id <= kFapCount; ++id) {
    if (!frame.has(id)) continue;
    const double v = frame.get(id);
    const std::string name(fap_info(id).name);
    if (v == std::round(v) && std::abs(v) < 1e9)
      j[name] = static_cast<long long>(v);
    else
      j[name] = v;
  }
  return j;
}

// Only the low-level FAPs of `faps`.
FapFrame low_level(const FapFrame& faps) {
  FapFrame out;
  for (int id = kExpressionFap + 1; id <= kFapCount; ++id)
    if (faps.has(id)) out.set(id, faps.get(id));
  return out;
}

// Adds `scale` x `source` to the FAPs of `target` that `locked` does not set.
void accumulate(FapFrame& target, const FapFrame& source, double scale, const FapFrame& locked) {
  if (scale == 0.0) return;
  for (int id = kExpressionFap + 1; id <= kFapCount; ++id) {
    if (!source.has(id) || locked.has(id)) continue;
    target.set(id, target.get(id) + scale * source.get(id));
  }
}

}  // namespace

ExpressionLibrary ExpressionLibrary::load(const std::filesystem::path& expressions_json,
                                          const std::filesystem::path& visemes_json) {
  ExpressionLibrary lib;
  const json e = read_json_file(expressions_json, "the expression library");
  const std::string e_src = expressions_json.string();
  if (!e.contains("expressions") || !e["expressions"].is_object())
    throw InputError(e_src + ": expected an object 'expressions'");
  for (int i = 0; i < kExpressionCount; ++i) {
    const std::string name(kExpressionNames[static_cast<std::size_t>(i)]);
    if (!e["expressions"].contains(name))
      throw InputError(e_src + ": expression '" + name + "' is missing");
    lib.expressions_[static_cast<std::size_t>(i)] =
        fap_vector(e["expressions"][name], e_src + ": expression '" + name + "'");
  }
  const json v = read_json_file(visemes_json, "the viseme library");
  const std::string v_src = visemes_json.string();
  if (!v.contains("visemes") || !v["visemes"].is_array())
    throw InputError(v_src + ": expected an array 'visemes'");
  std::array<bool, kVisemeCount> seen{};
  for (const json& entry : v["visemes"]) {
    if (!entry.is_object() || !entry.contains("index") || !entry["index"].is_number_integer())
      throw InputError(v_src + ": every viseme needs an integer 'index'");
    const int index = entry["index"].get<int>();
    if (index < 0 || index >= kVisemeCount)
      throw InputError(fmt::format("{}: viseme index {} is outside 0..14", v_src, index));
    const std::string ctx = fmt::format("{}: viseme {}", v_src, index);
    lib.visemes_[static_cast<std::size_t>(index)] =
        fap_vector(entry.contains("faps") ? entry["faps"] : json::object(), ctx);
    if (entry.contains("phonemes") && entry["phonemes"].is_string())
      lib.viseme_phonemes_[static_cast<std::size_t>(index)] = entry["phonemes"].get<std::string>();
    seen[static_cast<std::size_t>(index)] = true;
  }
  for (int i = 0; i < kVisemeCount; ++i)
    if (!seen[static_cast<std::size_t>(i)])
      throw InputError(fmt::format("{}: viseme {} is missing", v_src, i));
  return lib;
}

ExpressionLibrary ExpressionLibrary::load_default() {
  return load(data_file("expressions.json"), data_file("visemes.json"));
}

std::string_view ExpressionLibrary::expression_name(int select) {
  if (select < 0 || select >= kExpressionCount)
    throw std::out_of_range(fmt::format("expression_select {} is outside 0..6", select));
  return kExpressionNames[static_cast<std::size_t>(select)];
}

std::optional<int> ExpressionLibrary::expression_index(std::string_view name) {
  for (int i = 0; i < kExpressionCount; ++i)
    if (kExpressionNames[static_cast<std::size_t>(i)] == name) return i;
  return std::nullopt;
}

std::string_view ExpressionLibrary::viseme_name(int index) {
  if (index < 0 || index >= kVisemeCount)
    throw std::out_of_range(fmt::format("viseme {} is outside 0..14", index));
  return kVisemeNames[static_cast<std::size_t>(index)];
}

const FapFrame& ExpressionLibrary::expression(int select) const {
  if (select < 0 || select >= kExpressionCount)
    throw std::out_of_range(fmt::format("expression_select {} is outside 0..6", select));
  return expressions_[static_cast<std::size_t>(select)];
}

const FapFrame& ExpressionLibrary::viseme(int index) const {
  if (index < 0 || index >= kVisemeCount)
    throw std::out_of_range(fmt::format("viseme {} is outside 0..14", index));
  return visemes_[static_cast<std::size_t>(index)];
}

const FapFrame* ExpressionLibrary::find_expression(std::string_view name) const {
  const auto index = expression_index(name);
  return index ? &expressions_[static_cast<std::size_t>(*index)] : nullptr;
}

void ExpressionLibrary::set_expression(int select, const FapFrame& faps) {
  expression(select);  // checks the range
  expressions_[static_cast<std::size_t>(select)] = low_level(faps);
}

void ExpressionLibrary::set_viseme(int index, const FapFrame& faps) {
  viseme(index);  // checks the range
  visemes_[static_cast<std::size_t>(index)] = low_level(faps);
}

void ExpressionLibrary::save(const std::filesystem::path& expressions_json,
                             const std::filesystem::path& visemes_json) const {
  json e = {{"format", "rostro-expressions/1"},
            {"comment",
             "The neutral face and the six MPEG-4 expressions (expression_select 1..6) as "
             "low-level FAP vectors at full intensity (63), by FAP name, in each FAP's own unit "
             "(FAPU)."},
            {"expressions", json::object()}};
  for (int i = 0; i < kExpressionCount; ++i)
    e["expressions"][std::string(expression_name(i))] =
        fap_object(expressions_[static_cast<std::size_t>(i)]);
  json v = {{"format", "rostro-visemes/1"},
            {"comment",
             "The 15 MPEG-4 visemes (FAP 1 viseme_select 0..14) as low-level FAP vectors, by "
             "FAP name, in each FAP's own unit (FAPU)."},
            {"visemes", json::array()}};
  for (int i = 0; i < kVisemeCount; ++i) {
    const auto k = static_cast<std::size_t>(i);
    v["visemes"].push_back({{"index", i},
                            {"name", std::string(viseme_name(i))},
                            {"phonemes", viseme_phonemes_[k]},
                            {"faps", fap_object(visemes_[k])}});
  }
  AtomicFile e_file(expressions_json);
  AtomicFile v_file(visemes_json);
  e_file.write(e.dump(2) + "\n");
  v_file.write(v.dump(2) + "\n");
  e_file.commit();
  v_file.commit();
}

FapFrame ExpressionLibrary::expression_frame(int select, double intensity) const {
  FapFrame out;
  accumulate(out, expression(select), intensity, FapFrame{});
  return out;
}

FapFrame ExpressionLibrary::expand(const FapFrame& frame) const {
  FapFrame out = frame;
  FapFrame added;  // the high-level contributions, summed before merging
  if (frame.has(kExpressionFap)) {
    const ExpressionParams& e = frame.expression;
    // Out-of-range selects (a damaged file) contribute nothing rather than failing a stream.
    if (e.select1 >= 0 && e.select1 < kExpressionCount)
      accumulate(added, expression(e.select1), e.intensity1 / 63.0, frame);
    if (e.select2 >= 0 && e.select2 < kExpressionCount)
      accumulate(added, expression(e.select2), e.intensity2 / 63.0, frame);
  }
  if (frame.has(kVisemeFap)) {
    const VisemeParams& v = frame.viseme;
    const double blend = std::clamp(v.blend / 63.0, 0.0, 1.0);
    if (v.select1 >= 0 && v.select1 < kVisemeCount)
      accumulate(added, viseme(v.select1), blend, frame);
    if (v.select2 >= 0 && v.select2 < kVisemeCount)
      accumulate(added, viseme(v.select2), 1.0 - blend, frame);
  }
  for (int id = kExpressionFap + 1; id <= kFapCount; ++id)
    if (added.has(id)) out.set(id, added.get(id));
  return out;
}

}  // namespace rostro

#include "facecore/json_file.hpp"

#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <string>

#include "facecore/error.hpp"

namespace rostro {
namespace {

using nlohmann::json;

[[noreturn]] void wrong(const json& value, const char* key, const char* expected,
                        const std::string& context) {
  std::string shown = value.dump();
  if (shown.size() > 40) shown = shown.substr(0, 37) + "...";
  throw InputError(context + ": '" + key + "' should be " + expected + ", not " + shown);
}

}  // namespace

nlohmann::json read_json_file(const std::filesystem::path& path, std::string_view what) {
  if (std::filesystem::is_directory(path))
    throw InputError(path.string() + ": is a folder, expected " + std::string(what));
  std::ifstream in(path);
  if (!in)
    throw InputError(path.string() + ": cannot open " + std::string(what) + ": " +
                     std::strerror(errno));
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {  // parse_error, or out_of_range for a number
    throw InputError(path.string() + ": " + std::string(what) +
                     " is not valid JSON: " + json_error_text(e));
  }
}

nlohmann::json parse_json_text(std::string_view text, const std::string& name,
                               std::string_view what) {
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {  // parse_error, or out_of_range for a number
    throw InputError(name + ": " + std::string(what) + " is not valid JSON: " + json_error_text(e));
  }
}

double json_number(const json& object, const char* key, const std::string& context) {
  if (!object.is_object() || !object.contains(key))
    throw InputError(context + ": '" + key + "' is missing");
  const json& value = object.at(key);
  if (!value.is_number()) wrong(value, key, "a number", context);
  const double v = value.get<double>();
  if (!std::isfinite(v)) wrong(value, key, "a finite number", context);
  return v;
}

double json_number_or(const json& object, const char* key, double fallback,
                      const std::string& context) {
  if (!object.is_object() || !object.contains(key)) return fallback;
  return json_number(object, key, context);
}

long json_integer(const json& object, const char* key, long lo, long hi,
                  const std::string& context) {
  if (!object.is_object() || !object.contains(key))
    throw InputError(context + ": '" + key + "' is missing");
  const json& value = object.at(key);
  const std::string expected =
      "a whole number in " + std::to_string(lo) + ".." + std::to_string(hi);
  if (value.is_number_unsigned()) {
    const auto v = value.get<unsigned long long>();
    if (v > static_cast<unsigned long long>(hi) || (lo > 0 && v < static_cast<unsigned long>(lo)))
      wrong(value, key, expected.c_str(), context);
    return static_cast<long>(v);
  }
  if (value.is_number_integer()) {
    const auto v = value.get<long long>();
    if (v < lo || v > hi) wrong(value, key, expected.c_str(), context);
    return static_cast<long>(v);
  }
  if (value.is_number_float()) {
    const double v = value.get<double>();
    if (!(v >= static_cast<double>(lo) && v <= static_cast<double>(hi)) || v != std::floor(v))
      wrong(value, key, expected.c_str(), context);
    return static_cast<long>(v);
  }
  wrong(value, key, expected.c_str(), context);
}

long json_integer_or(const json& object, const char* key, long fallback, long lo, long hi,
                     const std::string& context) {
  if (!object.is_object() || !object.contains(key)) return fallback;
  return json_integer(object, key, lo, hi, context);
}

std::string json_string_or(const json& object, const char* key, const std::string& fallback,
                           const std::string& context) {
  if (!object.is_object() || !object.contains(key)) return fallback;
  const json& value = object.at(key);
  if (!value.is_string()) wrong(value, key, "a string", context);
  return value.get<std::string>();
}

bool json_bool_or(const json& object, const char* key, bool fallback, const std::string& context) {
  if (!object.is_object() || !object.contains(key)) return fallback;
  const json& value = object.at(key);
  if (!value.is_boolean()) wrong(value, key, "true or false", context);
  return value.get<bool>();
}

std::string json_error_text(const nlohmann::json::exception& e) {
  std::string text = e.what();
  if (text.rfind("[json.exception.", 0) == 0) {
    const auto close = text.find("] ");
    if (close != std::string::npos) text.erase(0, close + 2);
  }
  return text;
}

}  // namespace rostro

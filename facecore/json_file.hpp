#pragma once
// Reading the JSON files rostro describes things in (face models, layouts, language tables,
// profiles, rules), with the one error every stage reports for a file that is missing or
// not JSON, and typed reads whose errors name the file and the key. What the document must
// hold is each reader's own business.

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

namespace rostro {

// Throws InputError "<path>: cannot open <what>" or "<path>: <what> is not valid JSON: ...".
nlohmann::json read_json_file(const std::filesystem::path& path, std::string_view what);
// The same for text in memory; `name` stands for the path in messages.
nlohmann::json parse_json_text(std::string_view text, const std::string& name,
                               std::string_view what);

// Typed reads from an object. `context` names the file and the place ("a.json: frames[3]");
// errors read "CONTEXT: 'KEY' should be WHAT, not VALUE" and are InputError.
double json_number(const nlohmann::json& object, const char* key, const std::string& context);
double json_number_or(const nlohmann::json& object, const char* key, double fallback,
                      const std::string& context);
// A whole number in lo..hi (a JSON integer, or a number with no fraction).
long json_integer(const nlohmann::json& object, const char* key, long lo, long hi,
                  const std::string& context);
long json_integer_or(const nlohmann::json& object, const char* key, long fallback, long lo, long hi,
                     const std::string& context);
std::string json_string_or(const nlohmann::json& object, const char* key,
                           const std::string& fallback, const std::string& context);
bool json_bool_or(const nlohmann::json& object, const char* key, bool fallback,
                  const std::string& context);

// nlohmann's own message without its "[json.exception.type_error.302] " prefix.
std::string json_error_text(const nlohmann::json::exception& e);

}  // namespace rostro

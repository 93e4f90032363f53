#pragma once
// Reading the JSON files rostro describes things in (face models, layouts, language tables,
// profiles, rules), with the one error every stage reports for a file that is missing or
// not JSON. What the document must hold is each reader's own business.

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string_view>

namespace rostro {

// Throws InputError "<path>: cannot open <what>" or "<path>: <what> is not valid JSON: ...".
nlohmann::json read_json_file(const std::filesystem::path& path, std::string_view what);

}  // namespace rostro

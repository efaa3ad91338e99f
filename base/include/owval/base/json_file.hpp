#pragma once
// The one way owval reads a JSON input (predictions, manifests, frames.json, histories, backend
// files): a parse error becomes one InputError line naming the file, line and column.
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

namespace owval {

// Parses `path`; InputError("FILE:LINE: not valid JSON: ...") when it does not parse or cannot
// be read.
nlohmann::json ReadJsonFile(const std::filesystem::path& path);

// Parses `text` read from `name` (for messages), as ReadJsonFile.
nlohmann::json ParseJsonText(const std::string& text, const std::string& name);

// object[key] as a finite number: InputError naming the file and the field (`field`, the key's
// path in the document such as "sibernetic.time_s"; the key when empty) when it is missing, not
// a number or not finite.
double NumberField(const nlohmann::json& object, const std::string& key,
                   const std::filesystem::path& file, const std::string& field = "");

}  // namespace owval

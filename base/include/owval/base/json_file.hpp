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

}  // namespace owval

#include "owval/base/json_file.hpp"

#include <cmath>
#include <set>
#include <vector>

#include "owval/base/atomic_output.hpp"
#include "owval/base/errors.hpp"
#include "owval/base/one_line.hpp"

namespace owval {
namespace {

// nlohmann's messages start with "[json.exception.parse_error.101] parse error at line L,
// column C: "; owval's say the file and line themselves.
std::string WithoutExceptionTag(const std::string& what) {
  const auto close = what.find("] ");
  return what.rfind("[json.exception.", 0) == 0 && close != std::string::npos
             ? what.substr(close + 2)
             : what;
}

// A key given twice in one object: nlohmann keeps the last, so a backends file's second "mine"
// replaced the first without a word. Thrown from the parser's callback.
struct DuplicateKey {
  std::string key;
};

// nlohmann::json::parse, refusing a key given twice in one object.
nlohmann::json ParseRefusingDuplicateKeys(const std::string& text) {
  std::vector<std::set<std::string>> keys;  // of each object open around the parser
  return nlohmann::json::parse(
      text, [&keys](int, nlohmann::json::parse_event_t event, nlohmann::json& parsed) {
        using Event = nlohmann::json::parse_event_t;
        if (event == Event::object_start) keys.emplace_back();
        if (event == Event::object_end) keys.pop_back();
        if (event == Event::key && !keys.back().insert(parsed.get<std::string>()).second)
          throw DuplicateKey{parsed.get<std::string>()};
        return true;
      });
}

}  // namespace

nlohmann::json ParseJsonText(const std::string& text, const std::string& name) {
  // nlohmann's "unexpected end of input; expected '[', '{', or a literal" for an empty file
  if (text.find_first_not_of(" \t\r\n") == std::string::npos)
    throw InputError(name, 0, "is empty; expected a JSON document");
  try {
    return ParseRefusingDuplicateKeys(text);
  } catch (const DuplicateKey& d) {
    throw InputError(name, 0, "\"" + OneLine(d.key, 40) + "\" is given twice in one object");
  } catch (const nlohmann::json::parse_error& e) {
    // Line of the error: count newlines up to the byte the parser stopped at.
    std::size_t line = 1;
    for (std::size_t i = 0; i < e.byte && i < text.size(); ++i) line += text[i] == '\n';
    throw InputError(name, line, "not valid JSON: " + WithoutExceptionTag(e.what()));
  } catch (const nlohmann::json::exception& e) {  // 1e400: out_of_range, "number overflow"
    throw InputError(name, 0, "not valid JSON: " + WithoutExceptionTag(e.what()));
  }
}

nlohmann::json ReadJsonFile(const std::filesystem::path& path) {
  return ParseJsonText(ReadWholeFile(path), path.string());
}

double NumberField(const nlohmann::json& object, const std::string& key,
                   const std::filesystem::path& file, const std::string& field) {
  if (!object.is_object() || !object.contains(key) || !object[key].is_number() ||
      !std::isfinite(object[key].get<double>()))
    throw InputError(file.string(), 0,
                     "\"" + (field.empty() ? key : field) + "\": expected a finite number");
  return object[key].get<double>();
}

}  // namespace owval

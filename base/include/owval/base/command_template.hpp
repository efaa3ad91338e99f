#pragma once
// Command templates: "{NAME}" and "{set:NAME}" replaced by values in one pass (a value that
// itself contains "{out}" is never expanded again). Used by user-defined backends ("{config}",
// "{time}", "{out}", ...) and by fits driving an external command ("{out}", "{PARAM}"). In a
// command run by the shell every substituted value is single-quoted first, so paths with spaces
// or quotes stay one argument.
#include <map>
#include <string>

namespace owval {

// The names a template may use, e.g. {"config", "/a b/c"} and, for {set:NAME}, sets["NAME"].
struct TemplateValues {
  std::map<std::string, std::string> values;
  std::map<std::string, std::string> sets;
};

// POSIX single-quoting: 'it'\''s' for it's. Always quotes (also the empty string: '').
std::string ShellQuote(const std::string& text);

// Replaces every {NAME} and {set:NAME}; `quote` shell-quotes each substituted value. InputError
// naming `where` for an unknown placeholder, a {set:NAME} without a value, or an unclosed '{'.
std::string ExpandTemplate(const std::string& text, const TemplateValues& values, bool quote,
                           const std::string& where);

}  // namespace owval

#pragma once
// Command templates of user-defined backends: "{config}", "{time}", "{time_step}", "{log_step}",
// "{out}" and "{set:NAME}" replaced by the run's values. In a command run by the shell every
// substituted value is single-quoted first, so paths with spaces or quotes stay one argument.
#include <map>
#include <string>

namespace owval::backends {

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

}  // namespace owval::backends

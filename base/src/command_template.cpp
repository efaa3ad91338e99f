#include "owval/base/command_template.hpp"

#include "owval/base/errors.hpp"

namespace owval {

std::string ShellQuote(const std::string& text) {
  std::string quoted = "'";
  for (char c : text) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

namespace {

std::string Lookup(const std::string& name, const TemplateValues& v, const std::string& where) {
  if (name.rfind("set:", 0) == 0) {
    const auto it = v.sets.find(name.substr(4));
    if (it == v.sets.end())
      throw InputError(where, 0,
                       "{" + name + "} has no value (give --set " + name.substr(4) +
                           "=VALUE or a \"set\" default)");
    return it->second;
  }
  const auto it = v.values.find(name);
  if (it == v.values.end()) {
    std::string known;
    for (const auto& [key, value] : v.values) known += " {" + key + "}";
    throw InputError(where, 0,
                     "unknown placeholder {" + name + "}; known:" + known + " {set:NAME}");
  }
  return it->second;
}

}  // namespace

std::string ExpandTemplate(const std::string& text, const TemplateValues& values, bool quote,
                           const std::string& where) {
  std::string out;
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] != '{') {
      out += text[i];
      continue;
    }
    const std::size_t close = text.find('}', i);
    if (close == std::string::npos)
      throw InputError(where, 0, "unclosed '{' at character " + std::to_string(i + 1));
    const std::string value = Lookup(text.substr(i + 1, close - i - 1), values, where);
    out += quote ? ShellQuote(value) : value;
    i = close;
  }
  return out;
}

}  // namespace owval

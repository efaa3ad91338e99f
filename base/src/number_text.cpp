#include "owval/base/number_text.hpp"

#include <cmath>
#include <cstdlib>
#include <set>

#include "owval/base/errors.hpp"

namespace owval {
namespace {

// Digits from `i` on; returns how many.
std::size_t SkipDigits(std::string_view s, std::size_t& i) {
  const std::size_t start = i;
  while (i < s.size() && s[i] >= '0' && s[i] <= '9') ++i;
  return i - start;
}

// [+-] digits [. digits] | [+-] . digits, then [eE [+-] digits], and nothing else.
bool IsDecimal(std::string_view s) {
  std::size_t i = 0;
  if (i < s.size() && (s[i] == '+' || s[i] == '-')) ++i;
  std::size_t mantissa = SkipDigits(s, i);
  if (i < s.size() && s[i] == '.') mantissa += SkipDigits(s, ++i);
  if (mantissa == 0) return false;
  if (i < s.size() && (s[i] == 'e' || s[i] == 'E')) {
    ++i;
    if (i < s.size() && (s[i] == '+' || s[i] == '-')) ++i;
    if (SkipDigits(s, i) == 0) return false;
  }
  return i == s.size();
}

}  // namespace

std::optional<double> ParseDecimal(std::string_view text) {
  if (!IsDecimal(text)) return std::nullopt;
  const std::string copy(text);  // strtod needs a terminated string
  const double value = std::strtod(copy.c_str(), nullptr);
  // Past double's range strtod gives infinity (refused); below it, 0 or a subnormal (a number).
  if (!std::isfinite(value)) return std::nullopt;
  return value;
}

std::vector<std::pair<std::string, double>> ParseAssignments(
    const std::vector<std::string>& assignments, const std::string& flag) {
  std::vector<std::pair<std::string, double>> out;
  std::set<std::string> given;
  for (const std::string& a : assignments) {
    const auto eq = a.find('=');
    const std::optional<double> value =
        eq == std::string::npos ? std::nullopt : ParseDecimal(std::string_view(a).substr(eq + 1));
    if (eq == 0 || !value)
      throw InputError(flag + " " + a + ": expected NAME=NUMBER (a decimal number such as 2.5e8)");
    const std::string name = a.substr(0, eq);
    if (!given.insert(name).second)
      throw InputError(flag + " " + a + ": " + name + " is given twice");
    out.emplace_back(name, *value);
  }
  return out;
}

}  // namespace owval

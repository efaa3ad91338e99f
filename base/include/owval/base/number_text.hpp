#pragma once
// Numbers and NAME=NUMBER assignments as users type them on the command line (--set, --param,
// --target, --tolerance, thresholds). One parser for all of them: std::stod and strtod also take
// hexadecimal ("0x10" read as 16), "inf", "nan", leading white space and stop early on "1e" or
// "5cu" (caught only by each caller's own trailing-text check), so every flag refused a different
// set of typos.
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace owval {

// A finite decimal number, the whole of `text`: an optional sign, digits with an optional
// decimal point (".5" and "5." too), an optional exponent (e or E, optional sign, digits).
// Empty for anything else: hexadecimal, inf, nan, white space, "1e", a value past double's range.
std::optional<double> ParseDecimal(std::string_view text);

// "NAME=NUMBER" arguments of one flag (`flag`, e.g. "--set"), in the order given. InputError
// quoting the argument when it is not NAME=NUMBER (no '=', an empty name, a number ParseDecimal
// refuses), and naming NAME when it is given twice (the last one won silently).
std::vector<std::pair<std::string, double>> ParseAssignments(
    const std::vector<std::string>& assignments, const std::string& flag);

}  // namespace owval

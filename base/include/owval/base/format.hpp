#pragma once
// Numbers as reports print them: one formatter for every table, Markdown page and message, so
// the same value reads the same everywhere.
#include <string>

namespace owval {

// `value` with `significant_digits` significant digits ("%.Ng"): 0.000724637 -> "0.0007246" (4).
std::string FormatNumber(double value, int significant_digits = 4);

// A fraction as a percentage with `significant_digits` digits: 0.0213 -> "2.13%" (3).
std::string FormatPercent(double fraction, int significant_digits = 3);

}  // namespace owval

#include "owval/base/format.hpp"

#include <cstdio>

namespace owval {

std::string FormatNumber(double value, int significant_digits) {
  char text[64];
  std::snprintf(text, sizeof text, "%.*g", significant_digits, value);
  return text;
}

std::string FormatPercent(double fraction, int significant_digits) {
  return FormatNumber(fraction * 100, significant_digits) + "%";
}

}  // namespace owval

#pragma once
// The units a WCON reader accepts (tracker-commons WCON_format.md), shared by WconReader and the
// OME-Zarr reader (a store's positions unit).
#include <cmath>
#include <limits>
#include <string>

#include "owval/base/errors.hpp"
#include "owval/base/format.hpp"

namespace owval {

// Factor from the unit to s, or 0 when the unit is not one a WCON reader accepts.
double WconTimeFactor(const std::string& unit);
// Factor from the unit to mm, or 0 when unknown.
double WconLengthFactor(const std::string& unit);

// A coordinate in mm as a track stores it (x, y as floats, cx, cy as doubles), or InputError
// naming `file` and `field`: 1e308 mm, or 1e38 m, became infinite and the kinematics printed an
// infinite body length and NaN speeds.
template <typename Stored>
Stored WconMillimetres(double value_mm, const std::string& file, const std::string& field) {
  // Compared before the cast: a double beyond a float's range does not convert (undefined).
  if (!(std::fabs(value_mm) <= double(std::numeric_limits<Stored>::max())))
    throw InputError(file, 0,
                     field + ": " + FormatNumber(value_mm) +
                         " mm is out of range: expected a coordinate below " +
                         FormatNumber(std::numeric_limits<Stored>::max(), 2) + " mm");
  return static_cast<Stored>(value_mm);
}

}  // namespace owval

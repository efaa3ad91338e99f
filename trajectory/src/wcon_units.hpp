#pragma once
// The units a WCON reader accepts (tracker-commons WCON_format.md), shared by ReadWcon and
// WconTimePoints.
#include <string>

namespace owval {

// Factor from the unit to s, or 0 when the unit is not one a WCON reader accepts.
double WconTimeFactor(const std::string& unit);
// Factor from the unit to mm, or 0 when unknown.
double WconLengthFactor(const std::string& unit);

}  // namespace owval

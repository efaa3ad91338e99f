#pragma once
// SHA-256 (FIPS 180-4) as lower-case hex, by libavutil (FFmpeg, already linked for video):
// run-cache keys.
#include <string>
#include <string_view>

namespace owval::backends {

std::string Sha256Hex(std::string_view bytes);

}  // namespace owval::backends

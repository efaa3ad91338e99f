#include "owval/backends/sha256.hpp"

extern "C" {
#include <libavutil/mem.h>
#include <libavutil/sha.h>
}

#include <memory>
#include <stdexcept>

namespace owval::backends {

std::string Sha256Hex(std::string_view bytes) {
  // libavutil (an agreed dependency: FFmpeg) carries a FIPS 180-4 SHA-256.
  std::unique_ptr<AVSHA, decltype(&av_free)> sha(av_sha_alloc(), &av_free);
  if (!sha || av_sha_init(sha.get(), 256) != 0)
    throw std::runtime_error("SHA-256: libavutil failed");
  av_sha_update(sha.get(), reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size());
  uint8_t digest[32];
  av_sha_final(sha.get(), digest);
  static const char* hex = "0123456789abcdef";
  std::string out;
  for (uint8_t b : digest) {
    out += hex[b >> 4];
    out += hex[b & 15];
  }
  return out;
}

}  // namespace owval::backends

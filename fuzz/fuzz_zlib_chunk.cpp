// Fuzz target: the HDF5 chunk decoder (libdeflate's zlib decompression) on arbitrary streams.
// The first two bytes choose the declared chunk size; the decoder must never write past it, and
// whatever it accepts must be exactly what zlib decodes.
#include <zlib.h>

#include <cstring>
#include <vector>

#include "fuzz_common.hpp"
#include "zlib_chunk.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 2) return 0;
  const std::size_t declared = (std::size_t(data[0]) << 8 | data[1]) * 4;  // up to 256 KiB
  const std::uint8_t* stream = data + 2;
  const std::size_t stream_bytes = size - 2;
  static owval::internal::ZlibChunkDecoder decoder;
  std::vector<unsigned char> out(declared);
  if (!decoder.Decode(stream, stream_bytes, out.data(), declared)) return 0;
  std::vector<unsigned char> reference(declared + 1);
  uLongf length = uLongf(reference.size());
  if (uncompress(reference.data(), &length, stream, uLong(stream_bytes)) != Z_OK ||
      length != declared || std::memcmp(reference.data(), out.data(), declared) != 0)
    __builtin_trap();  // accepted something zlib decodes otherwise
  return 0;
}

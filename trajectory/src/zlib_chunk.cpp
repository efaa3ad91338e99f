#include "zlib_chunk.hpp"

#include <libdeflate.h>

#include <new>

namespace owval::internal {

ZlibChunkDecoder::ZlibChunkDecoder() : decompressor_(libdeflate_alloc_decompressor()) {
  if (!decompressor_) throw std::bad_alloc();
}

ZlibChunkDecoder::~ZlibChunkDecoder() { libdeflate_free_decompressor(decompressor_); }

bool ZlibChunkDecoder::Decode(const unsigned char* in, std::size_t in_bytes, unsigned char* out,
                              std::size_t size) {
  // A null actual-size pointer makes libdeflate require exactly `size` bytes of output.
  return libdeflate_zlib_decompress(decompressor_, in, in_bytes, out, size, nullptr) ==
         LIBDEFLATE_SUCCESS;
}

}  // namespace owval::internal

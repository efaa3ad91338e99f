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

ZlibChunkEncoder::ZlibChunkEncoder(int level) : compressor_(libdeflate_alloc_compressor(level)) {
  if (!compressor_) throw std::bad_alloc();  // also a level outside 0..12
}

ZlibChunkEncoder::~ZlibChunkEncoder() { libdeflate_free_compressor(compressor_); }

void ZlibChunkEncoder::Encode(const unsigned char* in, std::size_t size,
                              std::vector<unsigned char>* out) {
  out->resize(libdeflate_zlib_compress_bound(compressor_, size));
  // Within the bound the compressor cannot run out of room.
  out->resize(libdeflate_zlib_compress(compressor_, in, size, out->data(), out->size()));
}

}  // namespace owval::internal

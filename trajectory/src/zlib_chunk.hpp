#pragma once
// The zlib streams (RFC 1950: header, RFC 1951 deflate data, Adler-32) inside owval's HDF5 chunks,
// encoded and decoded with libdeflate: a whole-buffer decoder that verifies the Adler-32 itself
// and, on the bench file's chunks, runs faster than zlib's streaming inflate (docs/benchmarks.md).
// One decompressor per thread: libdeflate's decompressors are not shared.
#include <cstddef>
#include <memory>
#include <vector>

struct libdeflate_decompressor;
struct libdeflate_compressor;

namespace owval::internal {

class ZlibChunkDecoder {
 public:
  ZlibChunkDecoder();
  ~ZlibChunkDecoder();
  ZlibChunkDecoder(const ZlibChunkDecoder&) = delete;
  ZlibChunkDecoder& operator=(const ZlibChunkDecoder&) = delete;

  // Decodes `in[0, in_bytes)` into `out[0, size)`. True only when the stream is valid, produces
  // exactly `size` bytes and its Adler-32 matches them; bytes after the checksum are ignored, as
  // zlib does. Never writes past out + size, whatever the input.
  bool Decode(const unsigned char* in, std::size_t in_bytes, unsigned char* out, std::size_t size);

 private:
  libdeflate_decompressor* decompressor_;
};

// The writing side: a zlib stream of the same kind, from libdeflate's whole-buffer compressor
// (HDF5's deflate filter calls zlib's streaming deflate; at level 4, on the chunks of a demo1
// run, libdeflate took 2.1 s where zlib took 4.1 s, and wrote 5% fewer bytes). One encoder per
// thread, as for the decoder.
class ZlibChunkEncoder {
 public:
  explicit ZlibChunkEncoder(int level);  // 0 (stored) .. 9, as zlib's levels
  ~ZlibChunkEncoder();
  ZlibChunkEncoder(const ZlibChunkEncoder&) = delete;
  ZlibChunkEncoder& operator=(const ZlibChunkEncoder&) = delete;

  // Replaces `out` with the zlib stream of in[0, size).
  void Encode(const unsigned char* in, std::size_t size, std::vector<unsigned char>* out);

 private:
  libdeflate_compressor* compressor_;
};

// Deflate cannot expand data more than 1032:1 (a 258-byte match per 2 bits at best); a chunk
// whose declared size exceeds this many times its stored bytes is corrupt, and refused before
// any buffer is sized from it.
inline constexpr std::size_t kMaxDeflateRatio = 1032;

}  // namespace owval::internal

#pragma once
// A table-driven inflater for the zlib streams in owval's HDF5 chunks: 11-bit first-level tables,
// a 64-bit bit buffer refilled a word at a time, up to three literals per refill, matches copied
// 8 bytes at a time. On the bench file's chunks it runs 1.5x zlib's raw inflate (both with the
// same vectorised Adler-32), twice zlib's uncompress(). It is strict: any stream it does not decode
// to exactly `size` bytes with a matching Adler-32 is refused, including rare valid ones (an
// incomplete Huffman code, which zlib's deflate never writes), so callers hand refused streams
// to zlib for the final word.
#include <cstddef>

namespace owval::internal {

// Decodes the zlib stream (RFC 1950 header, RFC 1951 deflate data, Adler-32) `in[0, in_bytes)`
// into `out[0, size)`. True only when the stream ends having produced exactly `size` bytes and
// its checksum matches them; bytes after the checksum are ignored, as zlib does.
bool InflateZlib(const unsigned char* in, std::size_t in_bytes, unsigned char* out,
                 std::size_t size);

}  // namespace owval::internal

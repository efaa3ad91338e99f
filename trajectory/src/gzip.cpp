#include "gzip.hpp"

#include <zlib.h>

#include <algorithm>

#include "owval/base/errors.hpp"
#include "owval/base/memory_budget.hpp"

namespace owval::internal {

namespace {
// zlib's stream state, released on every exit path (a refusal below throws).
struct Inflater {
  z_stream z{};
  bool ready = false;
  Inflater() { ready = inflateInit2(&z, 16 + MAX_WBITS) == Z_OK; }
  ~Inflater() {
    if (ready) inflateEnd(&z);
  }
};
}  // namespace

std::string Gunzip(std::string_view data, const std::string& name) {
  Inflater inflater;
  if (!inflater.ready) throw InputError(name, 0, "gzip: out of memory");
  z_stream& z = inflater.z;
  std::string out;
  out.resize(std::max<std::size_t>(data.size() * 4, 1 << 16));
  std::size_t consumed = 0, produced = 0;
  int status = Z_OK;
  while (true) {
    const std::size_t in_chunk = std::min<std::size_t>(data.size() - consumed, 1u << 30);
    if (produced == out.size()) {
      // Deflate expands up to 1032:1: the output, not the file, is what must fit in memory.
      CheckAllocation(SaturatingProduct(out.size(), 2), name, "the decompressed text");
      out.resize(out.size() * 2);
    }
    const std::size_t out_chunk = std::min<std::size_t>(out.size() - produced, 1u << 30);
    z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(data.data() + consumed));
    z.avail_in = uInt(in_chunk);
    z.next_out = reinterpret_cast<Bytef*>(out.data() + produced);
    z.avail_out = uInt(out_chunk);
    status = inflate(&z, Z_NO_FLUSH);
    consumed += in_chunk - z.avail_in;
    produced += out_chunk - z.avail_out;
    if (status == Z_STREAM_END) {
      if (consumed == data.size()) break;
      inflateReset(&z);  // a further gzip member follows
      continue;
    }
    if (status == Z_BUF_ERROR && consumed == data.size()) break;  // input ended mid-stream
    if (status != Z_OK && status != Z_BUF_ERROR) break;
  }
  if (status != Z_STREAM_END)
    throw InputError(name, 0,
                     status == Z_DATA_ERROR
                         ? "gzip: corrupt compressed data"
                         : "gzip: truncated file (the compressed stream ends early)");
  out.resize(produced);
  return out;
}

}  // namespace owval::internal

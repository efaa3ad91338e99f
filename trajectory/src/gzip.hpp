#pragma once
// Sibernetic reference runs are often kept gzip-compressed (position_buffer.txt.gz); the text
// reader takes them as they are.
#include <string>
#include <string_view>

namespace owval::internal {

inline bool IsGzip(std::string_view data) {
  return data.size() >= 2 && static_cast<unsigned char>(data[0]) == 0x1f &&
         static_cast<unsigned char>(data[1]) == 0x8b;
}

// The decompressed content of a gzip file (all members). Throws InputError naming `name` when
// the data is truncated or corrupt.
std::string Gunzip(std::string_view data, const std::string& name);

}  // namespace owval::internal

#pragma once
// Lists of frame indices as users write them ("0,15,100,200": compare --frames, frames --at).
#include <cstddef>
#include <string>
#include <vector>

namespace owval {

// "0,15,100,200" → {0, 15, 100, 200}. InputError naming `flag` on anything else: an empty list
// or item, a sign or a non-digit ("-1" is not wrapped to 2^64 - 1), an index past 2^64, a frame
// listed twice.
std::vector<std::size_t> ParseIndexList(const std::string& text, const std::string& flag);

}  // namespace owval

#pragma once
// Messages that reach a terminal or a CI log come from hostile files as often as from owval: a
// token may be 5 MB long, hold a newline or raw control bytes. OneLine() makes any text safe to
// print as one line of a log (design notes §5; issue 18 item 12).
#include <cstddef>
#include <string>
#include <string_view>

namespace owval {

inline constexpr std::size_t kMaxMessageChars = 300;
inline constexpr std::size_t kMaxTokenChars = 80;

// One line of printable ASCII, at most `max_chars` characters: control and non-ASCII bytes are
// escaped (\n, \r, \t, \xHH), a run of more than kMaxTokenChars non-blank characters is cut to
// its head and tail around "...", and a text still too long is cut at the end with "...".
std::string OneLine(std::string_view text, std::size_t max_chars = kMaxMessageChars);

}  // namespace owval

#include "owval/base/one_line.hpp"

#include <algorithm>

namespace owval {
namespace {

// The escaped form of one byte.
void AppendEscaped(std::string& out, unsigned char c) {
  static const char kHex[] = "0123456789abcdef";
  if (c >= 0x20 && c < 0x7f) {
    out.push_back(static_cast<char>(c));
  } else if (c == '\n') {
    out += "\\n";
  } else if (c == '\r') {
    out += "\\r";
  } else if (c == '\t') {
    out += "\\t";
  } else {
    out += "\\x";
    out.push_back(kHex[c >> 4]);
    out.push_back(kHex[c & 15]);
  }
}

// Escapes `token` (a run without blanks); a long one keeps its head and tail around "...".
void AppendToken(std::string& out, std::string_view token) {
  if (token.size() > kMaxTokenChars) {
    const std::size_t keep = (kMaxTokenChars - 3) / 2;
    for (std::size_t i = 0; i < keep; ++i) AppendEscaped(out, token[i]);
    out += "...";
    for (std::size_t i = token.size() - keep; i < token.size(); ++i) AppendEscaped(out, token[i]);
    return;
  }
  for (char c : token) AppendEscaped(out, static_cast<unsigned char>(c));
}

}  // namespace

std::string OneLine(std::string_view text, std::size_t max_chars) {
  std::string out;
  out.reserve(std::min(text.size(), max_chars) + 8);
  std::size_t i = 0;
  // Past this much escaped output the rest is cut anyway: stop scanning a 5 MB input early.
  while (i < text.size() && out.size() <= max_chars) {
    if (text[i] == ' ') {
      out.push_back(' ');
      ++i;
      continue;
    }
    std::size_t end = i;
    while (end < text.size() && text[end] != ' ') ++end;
    AppendToken(out, text.substr(i, end - i));
    i = end;
  }
  if (out.size() > max_chars) {
    out.resize(max_chars >= 3 ? max_chars - 3 : 0);
    // Never end inside an escape sequence such as "\x1".
    const std::size_t slash = out.rfind('\\');
    if (slash != std::string::npos && out.size() - slash < 4) out.resize(slash);
    out += "...";
  }
  return out;
}

}  // namespace owval

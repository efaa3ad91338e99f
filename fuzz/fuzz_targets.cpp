// Fuzz target: `owval fit`'s --param and --target specifications (sgd/src/targets.cpp:
// ParseParameter, ParseTarget). A command-line argument holds no NUL or newline, so the input is
// split at both and every piece is parsed both ways.
#include <string>
#include <string_view>

#include "fuzz_common.hpp"
#include "owval/sgd/targets.hpp"

namespace {

template <typename Parse>
void Refused(Parse parse, const std::string& text) {
  try {
    parse(text);
  } catch (const owval::InputError& e) {
    owval::fuzz::CheckMessage(e);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  owval::fuzz::SetUpOnce();
  const std::string_view input(reinterpret_cast<const char*>(data), size);
  std::size_t begin = 0;
  while (begin <= input.size()) {
    std::size_t end = input.find_first_of(std::string_view("\n\0", 2), begin);
    if (end == std::string_view::npos) end = input.size();
    const std::string piece(input.substr(begin, end - begin));
    Refused([](const std::string& t) { owval::sgd::ParseParameter(t); }, piece);
    Refused([](const std::string& t) { owval::sgd::ParseTarget(t); }, piece);
    begin = end + 1;
  }
  return 0;
}

// Fuzz target: the Sibernetic text trajectory reader, plain or gzip-compressed (as
// ReadSiberneticText sees a file's bytes).
#include <string_view>

#include "fuzz_common.hpp"
#include "gzip.hpp"
#include "owval/trajectory/formats.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  owval::fuzz::SetUpOnce();
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  owval::TextReadOptions options;
  options.quiet = true;
  try {
    if (owval::internal::IsGzip(bytes)) {
      owval::ParseSiberneticText(owval::internal::Gunzip(bytes, "fuzz.txt.gz"), "fuzz.txt.gz",
                                 options);
    } else {
      owval::ParseSiberneticText(bytes, "fuzz.txt", options);
    }
  } catch (const owval::InputError& e) {
    owval::fuzz::CheckMessage(e);
  }
  return 0;
}

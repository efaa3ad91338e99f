// Fuzz target: Sibernetic's configuration reader (engine/src/config.cpp).
#include "fuzz_common.hpp"
#include "owval/engine/config.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  owval::fuzz::SetUpOnce();
  try {
    owval::engine::ParseSiberneticConfig(std::string(reinterpret_cast<const char*>(data), size),
                                         "fuzz.cfg");
  } catch (const owval::InputError& e) {
    owval::fuzz::CheckMessage(e);
  }
  return 0;
}

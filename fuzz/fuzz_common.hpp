#pragma once
// Shared by owval's fuzz targets. Each target defines LLVMFuzzerTestOneInput: linked with
// libFuzzer in the `fuzz` preset (clang), and with replay_main.cpp in every other build, where
// ctest replays the seed corpus and every regression input under fuzz/regressions/.
//
// A target passes an input when the reader returns or throws owval::InputError (a refusal with a
// message); any other exception, a crash, a sanitizer report, a leak, a timeout or an allocation
// over libFuzzer's limit is a finding.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

#include "owval/base/errors.hpp"
#include "owval/base/memory_budget.hpp"
#include "owval/base/one_line.hpp"

namespace owval::fuzz {

// A budget well under libFuzzer's default -rss_limit_mb=2048: readers must refuse larger inputs.
inline constexpr std::size_t kFuzzMemoryBudgetBytes = std::size_t{64} << 20;

inline void SetUpOnce() {
  static const bool done = [] {
    SetMemoryBudgetBytes(kFuzzMemoryBudgetBytes);
    return true;
  }();
  (void)done;
}

// The readers read files: each input (or a part of one) is written to `file` first, replacing it.
inline void WriteInput(const std::filesystem::path& file, std::string_view bytes) {
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}
inline void WriteInput(const std::filesystem::path& file, const std::uint8_t* data,
                       std::size_t size) {
  WriteInput(file, std::string_view(reinterpret_cast<const char*>(data), size));
}

// Every refusal's message must be what the CLI prints: one line, printable, <= 300 characters.
inline void CheckMessage(const InputError& e) {
  const std::string what = e.what();
  if (what.size() > kMaxMessageChars) __builtin_trap();
  for (char c : what)
    if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) >= 0x7f)
      __builtin_trap();
}

}  // namespace owval::fuzz

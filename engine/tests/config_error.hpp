#pragma once
// The one-line message ParseSiberneticConfig refuses TEXT with ("no error" when it accepts it),
// for the configuration reader's tests (config_test.cpp, config_hostile_test.cpp).
#include <string>

#include "owval/engine/config.hpp"
#include "owval/testing/test_files.hpp"

namespace owval::engine {

inline std::string ConfigErrorOf(const std::string& text) {
  return testing::InputErrorOf([&] { ParseSiberneticConfig(text, "cfg"); });
}

}  // namespace owval::engine

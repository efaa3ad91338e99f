#include "owval/base/index_list.hpp"

#include <algorithm>
#include <sstream>
#include <stdexcept>

#include "owval/base/errors.hpp"

namespace owval {

std::vector<std::size_t> ParseIndexList(const std::string& text, const std::string& flag) {
  // An empty list ("" or a trailing comma) named nothing to render or gate: refused, as ",".
  if (text.empty() || text.back() == ',')
    throw InputError(flag + ": expected comma-separated frame indices, found '" + text + "'");
  std::vector<std::size_t> indices;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');) {
    try {  // digits only: stoul would take "-1" as 2^64 - 1 (and throws past 2^64)
      if (item.empty() || item.find_first_not_of("0123456789") != std::string::npos)
        throw std::invalid_argument(item);
      indices.push_back(std::stoul(item));
    } catch (const std::exception&) {
      throw InputError(flag + ": expected comma-separated frame indices, found '" + item + "'");
    }
    if (std::count(indices.begin(), indices.end(), indices.back()) > 1)
      throw InputError(flag + ": frame " + item + " is listed twice");
  }
  return indices;
}

}  // namespace owval

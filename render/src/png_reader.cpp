// A PNG read back through libpng: the checklist trusts nothing it has not decoded.
#include <png.h>

#include <vector>

#include "owval/base/errors.hpp"
#include "owval/render/read_back.hpp"

namespace owval::render {

std::pair<int, int> ProbePng(const std::filesystem::path& path) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&image, path.c_str()))
    throw InputError(path.string(), 0, std::string("not a readable PNG: ") + image.message);
  image.format = PNG_FORMAT_RGBA;
  std::vector<png_byte> pixels(PNG_IMAGE_SIZE(image));
  if (!png_image_finish_read(&image, nullptr, pixels.data(), 0, nullptr))
    throw InputError(path.string(), 0, std::string("PNG does not decode: ") + image.message);
  return {int(image.width), int(image.height)};
}

}  // namespace owval::render

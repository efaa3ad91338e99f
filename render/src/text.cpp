#include "text.hpp"

#include <ft2build.h>
#include FT_FREETYPE_H

#include <filesystem>

#include "owval/base/errors.hpp"

namespace owval::render::internal {
namespace {
const char* kFonts[] = {"/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
                        "/usr/share/fonts/truetype/dejavu/DejaVuSansMono.ttf",
                        "/usr/share/fonts/truetype/liberation/LiberationSans-Regular.ttf"};
}

TextPainter::TextPainter() {
  if (FT_Init_FreeType(&library_)) throw InputError("FreeType failed to initialise");
  for (const char* font : kFonts)
    if (std::filesystem::exists(font) && FT_New_Face(library_, font, 0, &face_) == 0) return;
  throw InputError("no TrueType font found (install fonts-dejavu-core)");
}

TextPainter::~TextPainter() {
  if (face_) FT_Done_Face(face_);
  if (library_) FT_Done_FreeType(library_);
}

void TextPainter::Draw(std::vector<unsigned char>& rgba, int width, int height, int x, int y,
                       const std::string& text, int size_px, const unsigned char colour[3]) {
  FT_Set_Pixel_Sizes(face_, 0, static_cast<FT_UInt>(size_px));
  int pen = x;
  for (unsigned char c : text) {
    if (FT_Load_Char(face_, c, FT_LOAD_RENDER)) continue;
    const FT_GlyphSlot g = face_->glyph;
    for (unsigned row = 0; row < g->bitmap.rows; ++row) {
      for (unsigned col = 0; col < g->bitmap.width; ++col) {
        const int px = pen + g->bitmap_left + int(col), py = y - g->bitmap_top + int(row);
        if (px < 0 || py < 0 || px >= width || py >= height) continue;
        const float alpha = g->bitmap.buffer[row * unsigned(g->bitmap.pitch) + col] / 255.0f;
        unsigned char* p = &rgba[(std::size_t(py) * std::size_t(width) + std::size_t(px)) * 4];
        for (int k = 0; k < 3; ++k)
          p[k] = static_cast<unsigned char>(p[k] * (1 - alpha) + colour[k] * alpha);
      }
    }
    pen += int(g->advance.x >> 6);
  }
}

}  // namespace owval::render::internal

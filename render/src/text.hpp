#pragma once
// Labels drawn with FreeType into an RGBA image (a Debian DejaVu font, not a hand-made one).
#include <string>
#include <vector>

typedef struct FT_LibraryRec_* FT_Library;
typedef struct FT_FaceRec_* FT_Face;

namespace owval::render::internal {

class TextPainter {
 public:
  TextPainter();
  ~TextPainter();
  TextPainter(const TextPainter&) = delete;
  TextPainter& operator=(const TextPainter&) = delete;
  // Draws text with its baseline at (x, y) (pixels from the top left).
  void Draw(std::vector<unsigned char>& rgba, int width, int height, int x, int y,
            const std::string& text, int size_px, const unsigned char colour[3]);

 private:
  FT_Library library_ = nullptr;
  FT_Face face_ = nullptr;
};

}  // namespace owval::render::internal

#pragma once
// A small software rasteriser for the policy pictures: an RGB image, filled
// rectangles, rectangle outlines, triangles, thick lines and text in a
// built-in 5x7 bitmap font. No anti-aliasing: every pixel gets one of the
// colours it is drawn with, so a picture uses a handful of colours (which a
// GIF's fixed palette then holds exactly).
//
// Coordinates are pixels; pixel (x, y) covers [x, x+1) x [y, y+1) and is
// covered by a shape when its centre (x + 0.5, y + 0.5) is inside it.
// Everything is clipped to the image.

#include <cstdint>
#include <string_view>
#include <vector>

namespace dynapath::view {

struct Rgb {
  uint8_t r = 0, g = 0, b = 0;
  friend bool operator==(const Rgb&, const Rgb&) = default;
};

class RgbImage {
 public:
  RgbImage() = default;
  RgbImage(int width, int height, Rgb fill = {});

  int width() const { return width_; }
  int height() const { return height_; }
  // Row-major, three bytes (r, g, b) per pixel.
  const std::vector<uint8_t>& bytes() const { return bytes_; }

  Rgb At(int x, int y) const;          // {0, 0, 0} outside the image
  void Set(int x, int y, Rgb colour);  // ignored outside the image

 private:
  int width_ = 0, height_ = 0;
  std::vector<uint8_t> bytes_;
};

// Pixels [x, x+w) x [y, y+h).
void FillRect(RgbImage& image, int x, int y, int w, int h, Rgb colour);
// The `thickness` innermost pixel rings of the rectangle [x, x+w) x [y, y+h).
void OutlineRect(RgbImage& image, int x, int y, int w, int h, int thickness, Rgb colour);
void FillTriangle(RgbImage& image, double x0, double y0, double x1, double y1, double x2, double y2,
                  Rgb colour);
// A segment of the given width (a filled rectangle along it).
void ThickLine(RgbImage& image, double x0, double y0, double x1, double y1, double width,
               Rgb colour);

// The built-in font: 5x7 glyphs (descenders two rows below) on a 6x11 grid,
// scaled by `scale` (>= 1). Printable ASCII; anything else is drawn as '?'.
inline constexpr int kGlyphWidth = 5;
inline constexpr int kGlyphHeight = 7;  // capitals and digits
inline constexpr int kDescender = 2;    // g, j, p, q, y
inline constexpr int kGlyphAdvance = 6;
inline constexpr int kLineHeight = 11;
int TextWidth(std::string_view text, int scale);
// Draws `text` with its top-left corner at (x, y); returns the x after it.
int DrawText(RgbImage& image, int x, int y, std::string_view text, int scale, Rgb colour);

}  // namespace dynapath::view

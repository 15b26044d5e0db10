#include "tools/view/raster.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <string>

namespace dynapath::view {

RgbImage::RgbImage(int width, int height, Rgb fill)
    : width_(std::max(0, width)), height_(std::max(0, height)) {
  bytes_.resize(static_cast<size_t>(width_) * static_cast<size_t>(height_) * 3);
  for (size_t i = 0; i < bytes_.size(); i += 3) {
    bytes_[i] = fill.r;
    bytes_[i + 1] = fill.g;
    bytes_[i + 2] = fill.b;
  }
}

Rgb RgbImage::At(int x, int y) const {
  if (x < 0 || y < 0 || x >= width_ || y >= height_) return {};
  const size_t i = (static_cast<size_t>(y) * static_cast<size_t>(width_) + x) * 3;
  return {bytes_[i], bytes_[i + 1], bytes_[i + 2]};
}

void RgbImage::Set(int x, int y, Rgb colour) {
  if (x < 0 || y < 0 || x >= width_ || y >= height_) return;
  const size_t i = (static_cast<size_t>(y) * static_cast<size_t>(width_) + x) * 3;
  bytes_[i] = colour.r;
  bytes_[i + 1] = colour.g;
  bytes_[i + 2] = colour.b;
}

void FillRect(RgbImage& image, int x, int y, int w, int h, Rgb colour) {
  const int x0 = std::max(0, x), y0 = std::max(0, y);
  const int x1 = std::min(image.width(), x + w), y1 = std::min(image.height(), y + h);
  for (int py = y0; py < y1; ++py) {
    for (int px = x0; px < x1; ++px) image.Set(px, py, colour);
  }
}

void OutlineRect(RgbImage& image, int x, int y, int w, int h, int thickness, Rgb colour) {
  const int t = std::min({thickness, (w + 1) / 2, (h + 1) / 2});
  if (t <= 0) return;
  FillRect(image, x, y, w, t, colour);
  FillRect(image, x, y + h - t, w, t, colour);
  FillRect(image, x, y, t, h, colour);
  FillRect(image, x + w - t, y, t, h, colour);
}

void FillTriangle(RgbImage& image, double x0, double y0, double x1, double y1, double x2, double y2,
                  Rgb colour) {
  const double area = (x1 - x0) * (y2 - y0) - (y1 - y0) * (x2 - x0);
  if (area == 0.0) return;
  const double sign = area > 0 ? 1.0 : -1.0;
  const int min_x = std::max(0, static_cast<int>(std::floor(std::min({x0, x1, x2}))));
  const int max_x =
      std::min(image.width() - 1, static_cast<int>(std::ceil(std::max({x0, x1, x2}))));
  const int min_y = std::max(0, static_cast<int>(std::floor(std::min({y0, y1, y2}))));
  const int max_y =
      std::min(image.height() - 1, static_cast<int>(std::ceil(std::max({y0, y1, y2}))));
  // Edge functions, oriented so that inside is >= 0 (a small tolerance keeps
  // the shared edge of two triangles of a quad free of gaps).
  auto edge = [sign](double ax, double ay, double bx, double by, double px, double py) {
    return sign * ((bx - ax) * (py - ay) - (by - ay) * (px - ax));
  };
  constexpr double kTolerance = -1e-9;
  for (int py = min_y; py <= max_y; ++py) {
    for (int px = min_x; px <= max_x; ++px) {
      const double cx = px + 0.5, cy = py + 0.5;
      if (edge(x0, y0, x1, y1, cx, cy) >= kTolerance &&
          edge(x1, y1, x2, y2, cx, cy) >= kTolerance &&
          edge(x2, y2, x0, y0, cx, cy) >= kTolerance) {
        image.Set(px, py, colour);
      }
    }
  }
}

void ThickLine(RgbImage& image, double x0, double y0, double x1, double y1, double width,
               Rgb colour) {
  const double dx = x1 - x0, dy = y1 - y0;
  const double length = std::hypot(dx, dy);
  if (length == 0.0) return;
  const double nx = -dy / length * width / 2, ny = dx / length * width / 2;
  FillTriangle(image, x0 + nx, y0 + ny, x1 + nx, y1 + ny, x1 - nx, y1 - ny, colour);
  FillTriangle(image, x0 + nx, y0 + ny, x1 - nx, y1 - ny, x0 - nx, y0 - ny, colour);
}

namespace {

// The glyphs of printable ASCII, 7 rows of 5 pixels each ('#' set), rows
// separated by '|'; letters with a descender have two more rows. Drawn for
// this project.
constexpr std::array<const char*, 95> kGlyphs = {
    ".....|.....|.....|.....|.....|.....|.....",              // ' '
    "..#..|..#..|..#..|..#..|..#..|.....|..#..",              // !
    ".#.#.|.#.#.|.....|.....|.....|.....|.....",              // "
    ".#.#.|.#.#.|#####|.#.#.|#####|.#.#.|.#.#.",              // #
    "..#..|.####|#.#..|.###.|..#.#|####.|..#..",              // $
    "##...|##..#|...#.|..#..|.#...|#..##|...##",              // %
    ".##..|#..#.|#.#..|.#...|#.#.#|#..#.|.##.#",              // &
    "..#..|..#..|.#...|.....|.....|.....|.....",              // '
    "...#.|..#..|.#...|.#...|.#...|..#..|...#.",              // (
    ".#...|..#..|...#.|...#.|...#.|..#..|.#...",              // )
    ".....|..#..|#.#.#|.###.|#.#.#|..#..|.....",              // *
    ".....|..#..|..#..|#####|..#..|..#..|.....",              // +
    ".....|.....|.....|.....|.##..|..#..|.#...",              // ,
    ".....|.....|.....|#####|.....|.....|.....",              // -
    ".....|.....|.....|.....|.....|.##..|.##..",              // .
    ".....|....#|...#.|..#..|.#...|#....|.....",              // /
    ".###.|#...#|#..##|#.#.#|##..#|#...#|.###.",              // 0
    "..#..|.##..|..#..|..#..|..#..|..#..|.###.",              // 1
    ".###.|#...#|....#|...#.|..#..|.#...|#####",              // 2
    "#####|...#.|..#..|...#.|....#|#...#|.###.",              // 3
    "...#.|..##.|.#.#.|#..#.|#####|...#.|...#.",              // 4
    "#####|#....|####.|....#|....#|#...#|.###.",              // 5
    "..##.|.#...|#....|####.|#...#|#...#|.###.",              // 6
    "#####|....#|...#.|..#..|.#...|.#...|.#...",              // 7
    ".###.|#...#|#...#|.###.|#...#|#...#|.###.",              // 8
    ".###.|#...#|#...#|.####|....#|...#.|.##..",              // 9
    ".....|.##..|.##..|.....|.##..|.##..|.....",              // :
    ".....|.##..|.##..|.....|.##..|..#..|.#...",              // ;
    "...#.|..#..|.#...|#....|.#...|..#..|...#.",              // <
    ".....|.....|#####|.....|#####|.....|.....",              // =
    ".#...|..#..|...#.|....#|...#.|..#..|.#...",              // >
    ".###.|#...#|....#|...#.|..#..|.....|..#..",              // ?
    ".###.|#...#|#.###|#.#.#|#.###|#....|.###.",              // @
    ".###.|#...#|#...#|#####|#...#|#...#|#...#",              // A
    "####.|#...#|#...#|####.|#...#|#...#|####.",              // B
    ".###.|#...#|#....|#....|#....|#...#|.###.",              // C
    "###..|#..#.|#...#|#...#|#...#|#..#.|###..",              // D
    "#####|#....|#....|####.|#....|#....|#####",              // E
    "#####|#....|#....|####.|#....|#....|#....",              // F
    ".###.|#...#|#....|#.###|#...#|#...#|.####",              // G
    "#...#|#...#|#...#|#####|#...#|#...#|#...#",              // H
    ".###.|..#..|..#..|..#..|..#..|..#..|.###.",              // I
    "..###|...#.|...#.|...#.|...#.|#..#.|.##..",              // J
    "#...#|#..#.|#.#..|##...|#.#..|#..#.|#...#",              // K
    "#....|#....|#....|#....|#....|#....|#####",              // L
    "#...#|##.##|#.#.#|#.#.#|#...#|#...#|#...#",              // M
    "#...#|#...#|##..#|#.#.#|#..##|#...#|#...#",              // N
    ".###.|#...#|#...#|#...#|#...#|#...#|.###.",              // O
    "####.|#...#|#...#|####.|#....|#....|#....",              // P
    ".###.|#...#|#...#|#...#|#.#.#|#..#.|.##.#",              // Q
    "####.|#...#|#...#|####.|#.#..|#..#.|#...#",              // R
    ".####|#....|#....|.###.|....#|....#|####.",              // S
    "#####|..#..|..#..|..#..|..#..|..#..|..#..",              // T
    "#...#|#...#|#...#|#...#|#...#|#...#|.###.",              // U
    "#...#|#...#|#...#|#...#|#...#|.#.#.|..#..",              // V
    "#...#|#...#|#...#|#.#.#|#.#.#|#.#.#|.#.#.",              // W
    "#...#|#...#|.#.#.|..#..|.#.#.|#...#|#...#",              // X
    "#...#|#...#|.#.#.|..#..|..#..|..#..|..#..",              // Y
    "#####|....#|...#.|..#..|.#...|#....|#####",              // Z
    ".###.|.#...|.#...|.#...|.#...|.#...|.###.",              // [
    ".....|#....|.#...|..#..|...#.|....#|.....",              // backslash
    ".###.|...#.|...#.|...#.|...#.|...#.|.###.",              // ]
    "..#..|.#.#.|#...#|.....|.....|.....|.....",              // ^
    ".....|.....|.....|.....|.....|.....|#####",              // _
    ".#...|..#..|.....|.....|.....|.....|.....",              // `
    ".....|.....|.###.|....#|.####|#...#|.####",              // a
    "#....|#....|#.##.|##..#|#...#|#...#|####.",              // b
    ".....|.....|.###.|#....|#....|#...#|.###.",              // c
    "....#|....#|.##.#|#..##|#...#|#...#|.####",              // d
    ".....|.....|.###.|#...#|#####|#....|.###.",              // e
    "..##.|.#..#|.#...|###..|.#...|.#...|.#...",              // f
    ".....|.....|.####|#...#|#...#|#...#|.####|....#|.###.",  // g
    "#....|#....|#.##.|##..#|#...#|#...#|#...#",              // h
    "..#..|.....|.##..|..#..|..#..|..#..|.###.",              // i
    "...#.|.....|..##.|...#.|...#.|...#.|...#.|#..#.|.##..",  // j
    "#....|#....|#..#.|#.#..|##...|#.#..|#..#.",              // k
    ".##..|..#..|..#..|..#..|..#..|..#..|.###.",              // l
    ".....|.....|##.#.|#.#.#|#.#.#|#...#|#...#",              // m
    ".....|.....|#.##.|##..#|#...#|#...#|#...#",              // n
    ".....|.....|.###.|#...#|#...#|#...#|.###.",              // o
    ".....|.....|####.|#...#|#...#|#...#|####.|#....|#....",  // p
    ".....|.....|.####|#...#|#...#|#...#|.####|....#|....#",  // q
    ".....|.....|#.##.|##..#|#....|#....|#....",              // r
    ".....|.....|.###.|#....|.###.|....#|####.",              // s
    ".#...|.#...|###..|.#...|.#...|.#..#|..##.",              // t
    ".....|.....|#...#|#...#|#...#|#..##|.##.#",              // u
    ".....|.....|#...#|#...#|#...#|.#.#.|..#..",              // v
    ".....|.....|#...#|#...#|#.#.#|#.#.#|.#.#.",              // w
    ".....|.....|#...#|.#.#.|..#..|.#.#.|#...#",              // x
    ".....|.....|#...#|#...#|#...#|#...#|.####|....#|.###.",  // y
    ".....|.....|#####|...#.|..#..|.#...|#####",              // z
    "...##|..#..|..#..|##...|..#..|..#..|...##",              // {
    "..#..|..#..|..#..|..#..|..#..|..#..|..#..",              // |
    "##...|..#..|..#..|...##|..#..|..#..|##...",              // }
    ".....|.....|.#...|#.#.#|...#.|.....|.....",              // ~
};

const char* Glyph(char c) {
  const int index = static_cast<unsigned char>(c) - 32;
  return index >= 0 && index < static_cast<int>(kGlyphs.size()) ? kGlyphs[index]
                                                                : kGlyphs['?' - 32];
}

}  // namespace

int TextWidth(std::string_view text, int scale) {
  if (text.empty()) return 0;
  return (static_cast<int>(text.size()) * kGlyphAdvance - 1) * std::max(1, scale);
}

int DrawText(RgbImage& image, int x, int y, std::string_view text, int scale, Rgb colour) {
  scale = std::max(1, scale);
  for (char c : text) {
    const char* glyph = Glyph(c);
    const int rows = (static_cast<int>(std::strlen(glyph)) + 1) / (kGlyphWidth + 1);
    for (int row = 0; row < rows; ++row) {
      for (int col = 0; col < kGlyphWidth; ++col) {
        if (glyph[row * (kGlyphWidth + 1) + col] == '#') {
          FillRect(image, x + col * scale, y + row * scale, scale, scale, colour);
        }
      }
    }
    x += kGlyphAdvance * scale;
  }
  return x;
}

}  // namespace dynapath::view

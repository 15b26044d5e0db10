// image_info FILE: prints "png WIDTH HEIGHT" or "gif WIDTH HEIGHT FRAMES"
// after decoding the whole file with libpng or giflib; exit 1 when it is not
// a valid PNG or GIF. For the view end-to-end tests.

#include <cstdio>
#include <fstream>
#include <iterator>

#include "tests/view/image_decoders.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: image_info FILE\n");
    return 2;
  }
  std::ifstream in(argv[1], std::ios::binary);
  if (!in) {
    std::fprintf(stderr, "image_info: cannot open %s\n", argv[1]);
    return 1;
  }
  const std::vector<uint8_t> bytes{std::istreambuf_iterator<char>(in), {}};
  using namespace dynapath::view::testing;
  if (bytes.size() >= 6 && std::string(bytes.begin(), bytes.begin() + 3) == "GIF") {
    const DecodedGif gif = DecodeGif(bytes);
    if (!gif.error.empty()) {
      std::fprintf(stderr, "image_info: %s: %s\n", argv[1], gif.error.c_str());
      return 1;
    }
    std::printf("gif %d %d %zu\n", gif.width, gif.height, gif.frames.size());
    return 0;
  }
  const DecodedPng png = DecodePng(bytes);
  if (!png.error.empty()) {
    std::fprintf(stderr, "image_info: %s: %s\n", argv[1], png.error.c_str());
    return 1;
  }
  std::printf("png %d %d\n", png.width, png.height);
  return 0;
}

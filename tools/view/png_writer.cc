#include "tools/view/png_writer.h"

#include <png.h>

#include "dynapath/text_file.h"

namespace dynapath::view {

std::vector<uint8_t> EncodePng(const RgbImage& image) {
  if (image.width() <= 0 || image.height() <= 0) return {};
  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  png.width = static_cast<png_uint_32>(image.width());
  png.height = static_cast<png_uint_32>(image.height());
  png.format = PNG_FORMAT_RGB;
  const png_int_32 stride = 3 * image.width();
  // First call: the size; second: the bytes (libpng's simplified API).
  png_alloc_size_t size = 0;
  if (!png_image_write_to_memory(&png, nullptr, &size, 0, image.bytes().data(), stride, nullptr)) {
    png_image_free(&png);
    return {};
  }
  std::vector<uint8_t> bytes(size);
  if (!png_image_write_to_memory(&png, bytes.data(), &size, 0, image.bytes().data(), stride,
                                 nullptr)) {
    png_image_free(&png);
    return {};
  }
  bytes.resize(size);
  return bytes;
}

Status WritePng(const std::string& path, const RgbImage& image) {
  if (image.width() <= 0 || image.height() <= 0) return Error{"cannot write an empty image"};
  const std::vector<uint8_t> bytes = EncodePng(image);
  if (bytes.empty()) return Error::Internal("cannot encode " + path + " as PNG");
  return WriteFileAtomically(path, bytes);
}

}  // namespace dynapath::view

#pragma once
// PNG output through libpng (8-bit RGB, no interlace): the image library the
// whole ecosystem trusts for chunk layout, CRCs and filtering, instead of a
// writer of our own.

#include <cstdint>
#include <string>
#include <vector>

#include "dynapath/result.h"
#include "tools/view/raster.h"

namespace dynapath::view {

// The PNG file of `image`; empty on failure (an empty image, or libpng out
// of memory).
std::vector<uint8_t> EncodePng(const RgbImage& image);
// Writes the PNG atomically (a temporary file renamed over `path`).
Status WritePng(const std::string& path, const RgbImage& image);

}  // namespace dynapath::view

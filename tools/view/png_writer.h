#pragma once
// PNG output: 8-bit RGB, no interlace, every row with filter type 0 (the
// pictures are flat colours, which deflate packs well as they are). The
// chunks and their CRCs are written here; zlib does the deflate.

#include <cstdint>
#include <string>
#include <vector>

#include "core/result.h"
#include "tools/view/raster.h"

namespace dynapath::view {

// CRC-32 (ISO 3309, as PNG and zlib use) of `size` bytes, continuing `crc`
// (0 to start).
uint32_t Crc32(const uint8_t* data, size_t size, uint32_t crc = 0);

std::vector<uint8_t> EncodePng(const RgbImage& image);
// Writes the PNG atomically (a temporary file renamed over `path`).
Status WritePng(const std::string& path, const RgbImage& image);

// Writes `bytes` to `path` through a temporary file in the same directory.
Status WriteFileAtomically(const std::string& path, const std::vector<uint8_t>& bytes);

}  // namespace dynapath::view

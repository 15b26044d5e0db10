#pragma once
// Independent decoders for the tests of the PNG and GIF writers (and the
// image_info helper of the end-to-end tests): libpng and giflib, the
// libraries every image viewer uses, so a mistake in our encoders cannot be
// mirrored by a decoder written alongside them. GIF frames are composited
// as a viewer shows them (transparent pixels keep the previous frame).

#include <gif_lib.h>
#include <png.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace dynapath::view::testing {

struct DecodedPng {
  std::string error;  // "" when the file is a valid PNG (decoded to 8-bit RGB)
  int width = 0, height = 0;
  bool rgb8 = false;         // the file itself is 8-bit RGB, no interlace
  std::vector<uint8_t> rgb;  // row-major, 3 bytes per pixel
};

inline DecodedPng DecodePng(const std::vector<uint8_t>& file) {
  DecodedPng png;
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_memory(&image, file.data(), file.size())) {
    png.error = std::string("libpng: ") + image.message;
    png_image_free(&image);
    return png;
  }
  // The header's own fields (IHDR): colour type RGB, 8 bits, no interlace.
  png.rgb8 = file.size() > 28 && file[24] == 8 && file[25] == 2 && file[28] == 0;
  image.format = PNG_FORMAT_RGB;
  png.width = static_cast<int>(image.width);
  png.height = static_cast<int>(image.height);
  png.rgb.resize(PNG_IMAGE_SIZE(image));
  if (!png_image_finish_read(&image, nullptr, png.rgb.data(), 0, nullptr)) {
    png.error = std::string("libpng: ") + image.message;
    png.rgb.clear();
  }
  png_image_free(&image);
  return png;
}

struct DecodedGif {
  std::string error;
  int width = 0, height = 0;
  int loop_count = -1;           // -1: no NETSCAPE2.0 extension
  std::vector<uint8_t> palette;  // global colour table, 3 bytes per entry
  std::vector<int> delays_cs;
  std::vector<std::vector<uint8_t>> frames;  // composited RGB canvases
};

namespace gif_internal {
struct Source {
  const std::vector<uint8_t>* file;
  size_t at = 0;
};
inline int Read(GifFileType* gif, GifByteType* into, int wanted) {
  Source& source = *static_cast<Source*>(gif->UserData);
  const size_t n = std::min(static_cast<size_t>(wanted), source.file->size() - source.at);
  std::memcpy(into, source.file->data() + source.at, n);
  source.at += n;
  return static_cast<int>(n);
}
}  // namespace gif_internal

inline DecodedGif DecodeGif(const std::vector<uint8_t>& file) {
  DecodedGif result;
  gif_internal::Source source{&file};
  int error = 0;
  GifFileType* gif = DGifOpen(&source, gif_internal::Read, &error);
  if (gif == nullptr) {
    result.error = std::string("giflib: ") + GifErrorString(error);
    return result;
  }
  if (DGifSlurp(gif) != GIF_OK) {
    result.error = std::string("giflib: ") + GifErrorString(gif->Error);
    DGifCloseFile(gif, &error);
    return result;
  }
  result.width = gif->SWidth;
  result.height = gif->SHeight;
  if (gif->SColorMap != nullptr) {
    for (int i = 0; i < gif->SColorMap->ColorCount; ++i) {
      const GifColorType c = gif->SColorMap->Colors[i];
      result.palette.insert(result.palette.end(), {c.Red, c.Green, c.Blue});
    }
  }
  std::vector<uint8_t> canvas(static_cast<size_t>(result.width) * result.height * 3, 0);
  for (int f = 0; f < gif->ImageCount && result.error.empty(); ++f) {
    const SavedImage& frame = gif->SavedImages[f];
    // The application extension NETSCAPE2.0 and its sub-block {1, lo, hi}.
    for (int e = 0; e + 1 < frame.ExtensionBlockCount; ++e) {
      const ExtensionBlock& block = frame.ExtensionBlocks[e];
      const ExtensionBlock& next = frame.ExtensionBlocks[e + 1];
      if (block.Function == APPLICATION_EXT_FUNC_CODE && block.ByteCount == 11 &&
          std::memcmp(block.Bytes, "NETSCAPE2.0", 11) == 0 &&
          next.Function == CONTINUE_EXT_FUNC_CODE && next.ByteCount == 3 && next.Bytes[0] == 1) {
        result.loop_count = next.Bytes[1] | (next.Bytes[2] << 8);
      }
    }
    GraphicsControlBlock control{};
    control.TransparentColor = NO_TRANSPARENT_COLOR;
    DGifSavedExtensionToGCB(gif, f, &control);
    const ColorMapObject* colours =
        frame.ImageDesc.ColorMap != nullptr ? frame.ImageDesc.ColorMap : gif->SColorMap;
    const GifImageDesc& at = frame.ImageDesc;
    if (colours == nullptr || at.Left + at.Width > result.width ||
        at.Top + at.Height > result.height) {
      result.error = "frame " + std::to_string(f) + " has no colours or lies outside the screen";
      break;
    }
    for (int y = 0; y < at.Height && result.error.empty(); ++y) {
      for (int x = 0; x < at.Width; ++x) {
        const int index = frame.RasterBits[static_cast<size_t>(y) * at.Width + x];
        if (index == control.TransparentColor) continue;
        if (index >= colours->ColorCount) {
          result.error = "colour index outside the table";
          break;
        }
        const GifColorType c = colours->Colors[index];
        const size_t pixel = (static_cast<size_t>(at.Top + y) * result.width + at.Left + x) * 3;
        canvas[pixel] = c.Red;
        canvas[pixel + 1] = c.Green;
        canvas[pixel + 2] = c.Blue;
      }
    }
    result.frames.push_back(canvas);
    result.delays_cs.push_back(control.DelayTime);
  }
  DGifCloseFile(gif, &error);
  return result;
}

}  // namespace dynapath::view::testing

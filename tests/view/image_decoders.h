#pragma once
// Small independent decoders for the tests of the PNG and GIF writers (and
// the image_info helper of the end-to-end tests): PNG chunks with their CRCs
// checked by zlib, inflate, the five scanline filters; GIF blocks, the LZW
// decoder, frames composited as a viewer shows them.

#include <zlib.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace dynapath::view::testing {

struct DecodedPng {
  std::string error;  // "" when the file is a valid 8-bit RGB PNG
  int width = 0, height = 0;
  int chunks = 0;
  std::vector<uint8_t> rgb;  // row-major, 3 bytes per pixel
};

inline uint32_t ReadU32(const uint8_t* p) {
  return (uint32_t{p[0]} << 24) | (uint32_t{p[1]} << 16) | (uint32_t{p[2]} << 8) | p[3];
}

inline DecodedPng DecodePng(const std::vector<uint8_t>& file) {
  DecodedPng png;
  static const uint8_t kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (file.size() < 8 || std::memcmp(file.data(), kSignature, 8) != 0) {
    png.error = "bad signature";
    return png;
  }
  std::vector<uint8_t> idat;
  bool ended = false;
  size_t at = 8;
  while (at + 12 <= file.size() && !ended) {
    const uint32_t length = ReadU32(&file[at]);
    if (at + 12 + length > file.size()) {
      png.error = "chunk beyond the end";
      return png;
    }
    const std::string type(reinterpret_cast<const char*>(&file[at + 4]), 4);
    const uint8_t* data = &file[at + 8];
    const uint32_t crc = ReadU32(&file[at + 8 + length]);
    if (crc != static_cast<uint32_t>(crc32(0, &file[at + 4], length + 4))) {
      png.error = "bad CRC in chunk " + type;
      return png;
    }
    ++png.chunks;
    if (type == "IHDR") {
      if (length != 13) {
        png.error = "bad IHDR";
        return png;
      }
      png.width = static_cast<int>(ReadU32(data));
      png.height = static_cast<int>(ReadU32(data + 4));
      if (data[8] != 8 || data[9] != 2 || data[10] != 0 || data[11] != 0 || data[12] != 0) {
        png.error = "not 8-bit RGB, deflate, no interlace";
        return png;
      }
    } else if (type == "IDAT") {
      idat.insert(idat.end(), data, data + length);
    } else if (type == "IEND") {
      ended = true;
    }
    at += 12 + length;
  }
  if (!ended) {
    png.error = "no IEND";
    return png;
  }
  const size_t stride = static_cast<size_t>(png.width) * 3;
  std::vector<uint8_t> raw((stride + 1) * png.height);
  uLongf raw_size = static_cast<uLongf>(raw.size());
  if (uncompress(raw.data(), &raw_size, idat.data(), static_cast<uLong>(idat.size())) != Z_OK ||
      raw_size != raw.size()) {
    png.error = "bad image data";
    return png;
  }
  png.rgb.assign(stride * png.height, 0);
  for (int y = 0; y < png.height; ++y) {
    const uint8_t filter = raw[y * (stride + 1)];
    const uint8_t* in = &raw[y * (stride + 1) + 1];
    uint8_t* out = &png.rgb[y * stride];
    const uint8_t* up = y > 0 ? &png.rgb[(y - 1) * stride] : nullptr;
    for (size_t i = 0; i < stride; ++i) {
      const int a = i >= 3 ? out[i - 3] : 0, b = up ? up[i] : 0, c = up && i >= 3 ? up[i - 3] : 0;
      int predictor = 0;
      switch (filter) {
        case 0:
          predictor = 0;
          break;
        case 1:
          predictor = a;
          break;
        case 2:
          predictor = b;
          break;
        case 3:
          predictor = (a + b) / 2;
          break;
        case 4: {
          const int p = a + b - c, pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
          predictor = pa <= pb && pa <= pc ? a : (pb <= pc ? b : c);
          break;
        }
        default:
          png.error = "bad filter type";
          return png;
      }
      out[i] = static_cast<uint8_t>(in[i] + predictor);
    }
  }
  return png;
}

struct DecodedGif {
  std::string error;
  int width = 0, height = 0;
  int loop_count = -1;           // -1: no NETSCAPE2.0 extension
  std::vector<uint8_t> palette;  // 3 bytes per entry
  std::vector<int> delays_cs;
  std::vector<std::vector<uint8_t>> frames;  // composited RGB canvases
};

// GIF's LZW: returns the indices, or false on a malformed stream.
inline bool LzwDecode(const std::vector<uint8_t>& data, int min_code_size,
                      std::vector<uint8_t>& out) {
  const int clear = 1 << min_code_size, end = clear + 1;
  std::vector<std::vector<uint8_t>> table;
  auto reset = [&] {
    table.assign(static_cast<size_t>(clear) + 2, {});
    for (int i = 0; i < clear; ++i) table[i] = {static_cast<uint8_t>(i)};
  };
  reset();
  int code_size = min_code_size + 1;
  size_t bit = 0;
  int previous = -1;
  while (true) {
    if (bit + code_size > data.size() * 8) return false;  // no end code
    int code = 0;
    for (int i = 0; i < code_size; ++i, ++bit) {
      code |= ((data[bit / 8] >> (bit % 8)) & 1) << i;
    }
    if (code == clear) {
      reset();
      code_size = min_code_size + 1;
      previous = -1;
      continue;
    }
    if (code == end) return true;
    std::vector<uint8_t> entry;
    if (previous < 0) {
      if (code >= clear) return false;
      entry = table[code];
    } else {
      if (code < static_cast<int>(table.size()) && code != clear && code != end) {
        entry = table[code];
      } else if (code == static_cast<int>(table.size())) {
        entry = table[previous];
        entry.push_back(table[previous][0]);
      } else {
        return false;
      }
      if (table.size() < 4096) {
        std::vector<uint8_t> added = table[previous];
        added.push_back(entry[0]);
        table.push_back(std::move(added));
        if (static_cast<int>(table.size()) == (1 << code_size) && code_size < 12) ++code_size;
      }
    }
    out.insert(out.end(), entry.begin(), entry.end());
    previous = code;
  }
}

inline DecodedGif DecodeGif(const std::vector<uint8_t>& file) {
  DecodedGif gif;
  auto fail = [&gif](const std::string& why) {
    gif.error = why;
    return gif;
  };
  if (file.size() < 13 || std::memcmp(file.data(), "GIF89a", 6) != 0) return fail("bad header");
  auto u16 = [&file](size_t at) { return file[at] | (file[at + 1] << 8); };
  gif.width = u16(6);
  gif.height = u16(8);
  const uint8_t flags = file[10];
  size_t at = 13;
  if (flags & 0x80) {
    const size_t entries = size_t{1} << ((flags & 7) + 1);
    if (at + 3 * entries > file.size()) return fail("short colour table");
    gif.palette.assign(file.begin() + at, file.begin() + at + 3 * entries);
    at += 3 * entries;
  }
  std::vector<uint8_t> canvas(static_cast<size_t>(gif.width) * gif.height * 3, 0);
  int delay = 0, transparent = -1;
  auto sub_blocks = [&](std::vector<uint8_t>* into) {
    while (at < file.size()) {
      const size_t size = file[at++];
      if (size == 0) return true;
      if (at + size > file.size()) return false;
      if (into) into->insert(into->end(), file.begin() + at, file.begin() + at + size);
      at += size;
    }
    return false;
  };
  while (at < file.size()) {
    const uint8_t block = file[at++];
    if (block == 0x3b) return gif;  // trailer
    if (block == 0x21) {
      if (at >= file.size()) return fail("short extension");
      const uint8_t label = file[at++];
      std::vector<uint8_t> body;
      if (!sub_blocks(&body)) return fail("bad extension");
      if (label == 0xf9 && body.size() == 4) {
        delay = body[1] | (body[2] << 8);
        transparent = (body[0] & 1) ? body[3] : -1;
      } else if (label == 0xff && body.size() == 14 &&
                 std::memcmp(body.data(), "NETSCAPE2.0", 11) == 0 && body[11] == 1) {
        gif.loop_count = body[12] | (body[13] << 8);
      }
      continue;
    }
    if (block != 0x2c) return fail("unknown block");
    if (at + 10 > file.size()) return fail("short image descriptor");
    const int left = u16(at), top = u16(at + 2), w = u16(at + 4), h = u16(at + 6);
    const uint8_t image_flags = file[at + 8];
    at += 9;
    if (image_flags & 0x80) return fail("unexpected local colour table");
    if (left + w > gif.width || top + h > gif.height) return fail("frame outside the screen");
    const int min_code_size = file[at++];
    std::vector<uint8_t> data;
    if (!sub_blocks(&data)) return fail("bad image data blocks");
    std::vector<uint8_t> indices;
    if (!LzwDecode(data, min_code_size, indices)) return fail("bad LZW data");
    if (indices.size() != static_cast<size_t>(w) * h) return fail("wrong pixel count");
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        const int index = indices[static_cast<size_t>(y) * w + x];
        if (index == transparent) continue;
        if (3 * static_cast<size_t>(index) + 2 >= gif.palette.size()) return fail("bad index");
        const size_t pixel = (static_cast<size_t>(top + y) * gif.width + left + x) * 3;
        for (int k = 0; k < 3; ++k) canvas[pixel + k] = gif.palette[3 * index + k];
      }
    }
    gif.frames.push_back(canvas);
    gif.delays_cs.push_back(delay);
    transparent = -1;
  }
  return fail("no trailer");
}

}  // namespace dynapath::view::testing

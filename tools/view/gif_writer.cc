#include "tools/view/gif_writer.h"

#include <algorithm>
#include <cstddef>
#include <limits>

namespace dynapath::view {
namespace {

constexpr int kMaxCodes = 4096;  // 12-bit codes

void PutU16(std::vector<uint8_t>& out, int value) {
  out.push_back(static_cast<uint8_t>(value & 0xff));
  out.push_back(static_cast<uint8_t>((value >> 8) & 0xff));
}

// Packs codes least significant bit first.
class BitWriter {
 public:
  explicit BitWriter(std::vector<uint8_t>& out) : out_(out) {}
  void Put(int code, int bits) {
    buffer_ |= static_cast<uint32_t>(code) << count_;
    count_ += bits;
    while (count_ >= 8) {
      out_.push_back(static_cast<uint8_t>(buffer_ & 0xff));
      buffer_ >>= 8;
      count_ -= 8;
    }
  }
  void Flush() {
    if (count_ > 0) out_.push_back(static_cast<uint8_t>(buffer_ & 0xff));
    buffer_ = 0;
    count_ = 0;
  }

 private:
  std::vector<uint8_t>& out_;
  uint32_t buffer_ = 0;
  int count_ = 0;
};

}  // namespace

std::vector<uint8_t> LzwEncode(const std::vector<uint8_t>& indices, int min_code_size) {
  std::vector<uint8_t> out;
  BitWriter bits(out);
  const int alphabet = 1 << min_code_size;
  const int clear = alphabet, end = alphabet + 1;
  // next_code[prefix * alphabet + symbol]: the code of prefix+symbol, or -1.
  std::vector<int16_t> table(static_cast<size_t>(kMaxCodes) * alphabet, -1);
  int code_size = min_code_size + 1;
  int next = end + 1;
  bits.Put(clear, code_size);
  if (indices.empty()) {
    bits.Put(end, code_size);
    bits.Flush();
    return out;
  }
  int prefix = indices[0] & (alphabet - 1);
  for (size_t i = 1; i < indices.size(); ++i) {
    const int symbol = indices[i] & (alphabet - 1);
    int16_t& entry = table[static_cast<size_t>(prefix) * alphabet + symbol];
    if (entry >= 0) {
      prefix = entry;
      continue;
    }
    bits.Put(prefix, code_size);
    entry = static_cast<int16_t>(next++);
    // The decoder widens its codes one code later than the encoder adds
    // them: widen once the code just added no longer fits.
    if (next - 1 >= (1 << code_size) && code_size < 12) ++code_size;
    if (next >= kMaxCodes) {
      bits.Put(clear, code_size);
      std::fill(table.begin(), table.end(), int16_t{-1});
      code_size = min_code_size + 1;
      next = end + 1;
    }
    prefix = symbol;
  }
  bits.Put(prefix, code_size);
  bits.Put(end, code_size);
  bits.Flush();
  return out;
}

GifEncoder::GifEncoder(int width, int height, std::vector<Rgb> palette, int loop_count)
    : width_(std::clamp(width, 1, 65535)),
      height_(std::clamp(height, 1, 65535)),
      palette_(std::move(palette)) {
  if (palette_.empty()) palette_.push_back(Rgb{});
  if (palette_.size() > 256) palette_.resize(256);
  // One more entry, when there is room, for "unchanged" (transparent).
  if (palette_.size() < 256) transparent_ = static_cast<int>(palette_.size());
  const size_t entries = palette_.size() + (transparent_ >= 0 ? 1 : 0);
  table_bits_ = 1;
  while ((1u << table_bits_) < entries) ++table_bits_;

  const char* signature = "GIF89a";
  out_.insert(out_.end(), signature, signature + 6);
  PutU16(out_, width_);
  PutU16(out_, height_);
  // Global colour table present, 8 bits of colour resolution, its size.
  out_.push_back(static_cast<uint8_t>(0x80 | (7 << 4) | (table_bits_ - 1)));
  out_.push_back(0);  // background colour index
  out_.push_back(0);  // pixel aspect ratio: unspecified
  for (int i = 0; i < (1 << table_bits_); ++i) {
    const Rgb c = i < static_cast<int>(palette_.size()) ? palette_[i] : Rgb{};
    out_.insert(out_.end(), {c.r, c.g, c.b});
  }
  // NETSCAPE2.0 application extension: loop count.
  out_.insert(out_.end(), {0x21, 0xff, 0x0b});
  const char* application = "NETSCAPE2.0";
  out_.insert(out_.end(), application, application + 11);
  out_.insert(out_.end(), {0x03, 0x01});
  PutU16(out_, std::clamp(loop_count, 0, 65535));
  out_.push_back(0);
}

uint8_t GifEncoder::IndexOf(Rgb colour) {
  const uint32_t key = (uint32_t{colour.r} << 16) | (uint32_t{colour.g} << 8) | colour.b;
  if (auto it = nearest_.find(key); it != nearest_.end()) return it->second;
  int best = 0;
  int best_distance = std::numeric_limits<int>::max();
  for (size_t i = 0; i < palette_.size(); ++i) {
    const int dr = colour.r - palette_[i].r, dg = colour.g - palette_[i].g,
              db = colour.b - palette_[i].b;
    const int distance = dr * dr + dg * dg + db * db;
    if (distance < best_distance) best = static_cast<int>(i), best_distance = distance;
  }
  nearest_.emplace(key, static_cast<uint8_t>(best));
  return static_cast<uint8_t>(best);
}

Status GifEncoder::AddFrame(const RgbImage& frame, int delay_ms) {
  if (frame.width() != width_ || frame.height() != height_) {
    return Error{"frame of " + std::to_string(frame.width()) + "x" +
                 std::to_string(frame.height()) + " in an animation of " + std::to_string(width_) +
                 "x" + std::to_string(height_)};
  }
  std::vector<uint8_t> indices(static_cast<size_t>(width_) * height_);
  const std::vector<uint8_t>& rgb = frame.bytes();
  for (size_t i = 0; i < indices.size(); ++i) {
    indices[i] = IndexOf(Rgb{rgb[3 * i], rgb[3 * i + 1], rgb[3 * i + 2]});
  }
  // The rectangle that differs from the previous frame (all of the first).
  int x0 = 0, y0 = 0, x1 = width_, y1 = height_;
  if (!previous_.empty()) {
    x0 = width_, y0 = height_, x1 = 0, y1 = 0;
    for (int y = 0; y < height_; ++y) {
      for (int x = 0; x < width_; ++x) {
        const size_t i = static_cast<size_t>(y) * width_ + x;
        if (indices[i] == previous_[i]) continue;
        x0 = std::min(x0, x), y0 = std::min(y0, y);
        x1 = std::max(x1, x + 1), y1 = std::max(y1, y + 1);
      }
    }
    if (x1 <= x0) x0 = 0, y0 = 0, x1 = 1, y1 = 1;  // unchanged: one pixel
  }
  // Within it, pixels that did not change are transparent (the previous
  // frame shows through): long runs of one index, which LZW packs well.
  const bool see_through = !previous_.empty() && transparent_ >= 0;
  std::vector<uint8_t> part;
  part.reserve(static_cast<size_t>(x1 - x0) * (y1 - y0));
  for (int y = y0; y < y1; ++y) {
    for (int x = x0; x < x1; ++x) {
      const size_t i = static_cast<size_t>(y) * width_ + x;
      part.push_back(see_through && indices[i] == previous_[i] ? static_cast<uint8_t>(transparent_)
                                                               : indices[i]);
    }
  }

  // Graphic control extension: disposal 1 (leave in place), the delay, the
  // transparent index.
  out_.insert(out_.end(), {0x21, 0xf9, 0x04, static_cast<uint8_t>(see_through ? 0x05 : 0x04)});
  PutU16(out_, std::clamp((delay_ms + 5) / 10, 2, 65535));
  out_.push_back(static_cast<uint8_t>(see_through ? transparent_ : 0));
  out_.push_back(0);
  // Image descriptor, no local colour table.
  out_.push_back(0x2c);
  PutU16(out_, x0);
  PutU16(out_, y0);
  PutU16(out_, x1 - x0);
  PutU16(out_, y1 - y0);
  out_.push_back(0);
  const int min_code_size = std::max(2, table_bits_);
  out_.push_back(static_cast<uint8_t>(min_code_size));
  const std::vector<uint8_t> data = LzwEncode(part, min_code_size);
  for (size_t at = 0; at < data.size(); at += 255) {
    const size_t size = std::min<size_t>(255, data.size() - at);
    out_.push_back(static_cast<uint8_t>(size));
    out_.insert(out_.end(), data.begin() + static_cast<std::ptrdiff_t>(at),
                data.begin() + static_cast<std::ptrdiff_t>(at + size));
  }
  out_.push_back(0);
  previous_ = std::move(indices);
  ++frames_;
  return Ok{};
}

std::vector<uint8_t> GifEncoder::Finish() {
  out_.push_back(0x3b);
  return std::move(out_);
}

}  // namespace dynapath::view

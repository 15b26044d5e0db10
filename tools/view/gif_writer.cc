#include "tools/view/gif_writer.h"

#include <gif_lib.h>

#include <algorithm>
#include <limits>

namespace dynapath::view {

GifEncoder::GifEncoder(int width, int height, std::vector<Rgb> palette, int loop_count)
    : width_(std::clamp(width, 1, 65535)),
      height_(std::clamp(height, 1, 65535)),
      palette_(std::move(palette)) {
  if (palette_.empty()) palette_.push_back(Rgb{});
  if (palette_.size() > 256) palette_.resize(256);
  // One more entry, when there is room, for "unchanged" (transparent).
  if (palette_.size() < 256) transparent_ = static_cast<int>(palette_.size());
  const size_t entries = palette_.size() + (transparent_ >= 0 ? 1 : 0);
  int table_bits = 1;
  while ((1u << table_bits) < entries) ++table_bits;

  int error = 0;
  gif_ = EGifOpen(this, &GifEncoder::Write, &error);
  if (gif_ == nullptr) {
    status_ = Error::Internal(std::string("giflib: EGifOpen: ") + GifErrorString(error));
    return;
  }
  EGifSetGifVersion(gif_, true);  // GIF89a: the extensions below need it
  ColorMapObject* colours = GifMakeMapObject(1 << table_bits, nullptr);
  if (colours == nullptr) {
    status_ = Error::Internal("giflib: GifMakeMapObject failed");
    return;
  }
  for (int i = 0; i < (1 << table_bits); ++i) {
    const Rgb c = i < static_cast<int>(palette_.size()) ? palette_[i] : Rgb{};
    colours->Colors[i] = GifColorType{c.r, c.g, c.b};
  }
  // 8 bits of colour resolution, background index 0 (giflib copies the map).
  const int put = EGifPutScreenDesc(gif_, width_, height_, 8, 0, colours);
  GifFreeMapObject(colours);
  if (!Check(put, "EGifPutScreenDesc")) return;
  // NETSCAPE2.0 application extension: sub-block 1, the loop count.
  const int loops = std::clamp(loop_count, 0, 65535);
  const uint8_t loop_block[3] = {1, static_cast<uint8_t>(loops & 0xff),
                                 static_cast<uint8_t>(loops >> 8)};
  if (!Check(EGifPutExtensionLeader(gif_, APPLICATION_EXT_FUNC_CODE), "EGifPutExtensionLeader") ||
      !Check(EGifPutExtensionBlock(gif_, 11, "NETSCAPE2.0"), "EGifPutExtensionBlock") ||
      !Check(EGifPutExtensionBlock(gif_, 3, loop_block), "EGifPutExtensionBlock") ||
      !Check(EGifPutExtensionTrailer(gif_), "EGifPutExtensionTrailer")) {
    return;
  }
}

GifEncoder::~GifEncoder() {
  if (gif_ != nullptr) EGifCloseFile(gif_, nullptr);
}

int GifEncoder::Write(GifFileType* gif, const uint8_t* bytes, int size) {
  auto* self = static_cast<GifEncoder*>(gif->UserData);
  // No exception may cross giflib's C frames: keep it for Check.
  try {
    self->out_.insert(self->out_.end(), bytes, bytes + size);
  } catch (...) {
    if (!self->write_failure_) self->write_failure_ = std::current_exception();
    return 0;
  }
  return size;
}

Status GifEncoder::Check(int code, const char* call) {
  if (write_failure_) std::rethrow_exception(write_failure_);
  if (code != GIF_OK && status_) {
    const char* reason = gif_ != nullptr ? GifErrorString(gif_->Error) : nullptr;
    status_ = Error::Internal(std::string("giflib: ") + call + ": " + (reason ? reason : "failed"));
  }
  return status_;
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
  if (!status_) return status_;
  if (gif_ == nullptr) return Error{"a frame added to a finished GIF"};
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

  // Graphic control extension: disposal "leave in place", the delay, the
  // transparent index.
  GraphicsControlBlock control{};
  control.DisposalMode = DISPOSE_DO_NOT;
  control.UserInputFlag = false;
  control.DelayTime = std::clamp((delay_ms + 5) / 10, 2, 65535);
  control.TransparentColor = see_through ? transparent_ : NO_TRANSPARENT_COLOR;
  GifByteType extension[4];
  const size_t extension_size = EGifGCBToExtension(&control, extension);
  if (!Check(EGifPutExtension(gif_, GRAPHICS_EXT_FUNC_CODE, static_cast<int>(extension_size),
                              extension),
             "EGifPutExtension")) {
    return status_;
  }
  // Image descriptor of the rectangle, no local colour table.
  if (!Check(EGifPutImageDesc(gif_, x0, y0, x1 - x0, y1 - y0, false, nullptr),
             "EGifPutImageDesc")) {
    return status_;
  }
  std::vector<GifPixelType> row(static_cast<size_t>(x1 - x0));
  for (int y = y0; y < y1; ++y) {
    for (int x = x0; x < x1; ++x) {
      const size_t i = static_cast<size_t>(y) * width_ + x;
      row[static_cast<size_t>(x - x0)] = see_through && indices[i] == previous_[i]
                                             ? static_cast<GifPixelType>(transparent_)
                                             : indices[i];
    }
    if (!Check(EGifPutLine(gif_, row.data(), x1 - x0), "EGifPutLine")) return status_;
  }
  previous_ = std::move(indices);
  ++frames_;
  return Ok{};
}

std::vector<uint8_t> GifEncoder::Finish() {
  if (gif_ == nullptr) return {};
  // Writes the trailer and frees giflib's state, whatever it returns.
  int error = 0;
  const int code = EGifCloseFile(gif_, &error);
  gif_ = nullptr;
  if (write_failure_) std::rethrow_exception(write_failure_);
  if (code != GIF_OK && status_) {
    status_ = Error::Internal(std::string("giflib: EGifCloseFile: ") + GifErrorString(error));
  }
  if (!status_) return {};
  return std::move(out_);
}

}  // namespace dynapath::view

#pragma once
// Animated GIF output (GIF89a): one global palette, the NETSCAPE2.0 loop
// extension, a per-frame delay, LZW-compressed frames. After the first frame
// only the rectangle that changed is stored (disposal "leave in place"), its
// unchanged pixels transparent, so a run where a few cells change per step
// makes a small file.

#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

#include "core/result.h"
#include "tools/view/raster.h"

namespace dynapath::view {

// GIF's variable-width LZW of colour indices (each < 2^min_code_size), as
// the image data's sub-blocks hold it (without the block framing).
std::vector<uint8_t> LzwEncode(const std::vector<uint8_t>& indices, int min_code_size);

class GifEncoder {
 public:
  // `palette`: 1 to 256 colours; frame pixels are mapped to the nearest one.
  // `loop_count`: 0 loops forever.
  GifEncoder(int width, int height, std::vector<Rgb> palette, int loop_count = 0);

  // Appends a frame shown for `delay_ms` (rounded to GIF's 1/100 s, at least
  // 2/100 s, as browsers play shorter delays slowly). The frame must be
  // width x height.
  Status AddFrame(const RgbImage& frame, int delay_ms);
  int frames() const { return frames_; }
  // The whole file (header, frames, trailer). Call once.
  std::vector<uint8_t> Finish();

 private:
  uint8_t IndexOf(Rgb colour);

  int width_, height_;
  std::vector<Rgb> palette_;
  int transparent_ = -1;  // the index meaning "unchanged" (-1: 256 colours, none)
  int table_bits_;        // the global colour table holds 2^table_bits_ entries
  int frames_ = 0;
  std::vector<uint8_t> out_;
  std::vector<uint8_t> previous_;  // colour indices of the last frame
  std::unordered_map<uint32_t, uint8_t> nearest_;
};

}  // namespace dynapath::view

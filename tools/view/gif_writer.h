#pragma once
// Animated GIF output (GIF89a): one global palette, the NETSCAPE2.0 loop
// extension, a per-frame delay. giflib encodes (blocks and LZW); the frame
// logic is ours: after the first frame only the rectangle that changed is
// stored (disposal "leave in place"), its unchanged pixels transparent, so a
// run where a few cells change per step makes a small file.

#include <cstdint>
#include <exception>
#include <string>
#include <unordered_map>
#include <vector>

#include "dynapath/result.h"
#include "tools/view/raster.h"

struct GifFileType;  // giflib's encoder state (gif_lib.h)

namespace dynapath::view {

class GifEncoder {
 public:
  // `palette`: 1 to 256 colours; frame pixels are mapped to the nearest one.
  // `loop_count`: 0 loops forever.
  GifEncoder(int width, int height, std::vector<Rgb> palette, int loop_count = 0);
  ~GifEncoder();
  GifEncoder(const GifEncoder&) = delete;
  GifEncoder& operator=(const GifEncoder&) = delete;

  // Appends a frame shown for `delay_ms` (rounded to GIF's 1/100 s, at least
  // 2/100 s, as browsers play shorter delays slowly). The frame must be
  // width x height. A giflib error is returned here (and by every later
  // call: the file cannot be completed).
  Status AddFrame(const RgbImage& frame, int delay_ms);
  int frames() const { return frames_; }
  // The whole file (header, frames, trailer). Call once. Empty after a
  // giflib error (which AddFrame has returned).
  std::vector<uint8_t> Finish();

 private:
  static int Write(GifFileType* gif, const uint8_t* bytes, int size);
  // Turns a giflib return code into a Status, the first error sticking.
  Status Check(int code, const char* call);
  uint8_t IndexOf(Rgb colour);

  int width_, height_;
  std::vector<Rgb> palette_;
  int transparent_ = -1;  // the index meaning "unchanged" (-1: 256 colours, none)
  int frames_ = 0;
  GifFileType* gif_ = nullptr;        // null once finished (or when it failed to open)
  Status status_ = Ok{};              // the first giflib error
  std::vector<uint8_t> out_;          // what giflib has written
  std::exception_ptr write_failure_;  // thrown inside Write (out of memory)
  std::vector<uint8_t> previous_;     // colour indices of the last frame
  std::unordered_map<uint32_t, uint8_t> nearest_;
};

}  // namespace dynapath::view

#include "tools/view/gif_writer.h"

#include <gtest/gtest.h>

#include "core/rng.h"
#include "tests/view/image_decoders.h"
#include "tests/view/policy_test_support.h"
#include "tools/view/policy_drawing.h"

namespace dynapath::view {
namespace {

const std::vector<Rgb> kPalette = {
    {0, 0, 0}, {255, 0, 0}, {0, 255, 0}, {0, 0, 255}, {250, 250, 250}};

RgbImage Pattern(int width, int height, int seed) {
  RgbImage image(width, height);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      image.Set(x, y, kPalette[static_cast<size_t>((x / 3 + y / 2 + seed) % kPalette.size())]);
    }
  }
  return image;
}

// Wraps `indices` (w x h of them), LZW-coded by our encoder, in a one-frame
// GIF whose palette maps index i to grey level i, and decodes it with giflib.
void ExpectLzwRoundTrip(const std::vector<uint8_t>& indices, int min_code_size) {
  size_t width = 1;
  while (indices.size() / width > 65535 || indices.size() % width != 0) ++width;
  ASSERT_LE(width, 65535u) << "choose a test length with a factorisation that fits a GIF";
  const size_t height = indices.size() / width;
  std::vector<uint8_t> file = {'G', 'I', 'F', '8', '9', 'a'};
  auto put16 = [&file](size_t v) { file.insert(file.end(), {uint8_t(v & 0xff), uint8_t(v >> 8)}); };
  put16(width);
  put16(height);
  file.insert(file.end(), {static_cast<uint8_t>(0x80 | (min_code_size - 1)), 0, 0});
  for (int i = 0; i < (1 << min_code_size); ++i) file.insert(file.end(), 3, uint8_t(i));
  file.push_back(0x2c);
  put16(0);
  put16(0);
  put16(width);
  put16(height);
  file.push_back(0);
  file.push_back(static_cast<uint8_t>(min_code_size));
  const std::vector<uint8_t> coded = LzwEncode(indices, min_code_size);
  for (size_t at = 0; at < coded.size(); at += 255) {
    const size_t n = std::min<size_t>(255, coded.size() - at);
    file.push_back(static_cast<uint8_t>(n));
    file.insert(file.end(), coded.begin() + at, coded.begin() + at + n);
  }
  file.push_back(0);
  file.push_back(0x3b);
  const testing::DecodedGif gif = testing::DecodeGif(file);
  ASSERT_EQ(gif.error, "");
  ASSERT_EQ(gif.frames.size(), 1u);
  std::vector<uint8_t> decoded;
  for (size_t i = 0; i < indices.size(); ++i) decoded.push_back(gif.frames[0][3 * i]);
  EXPECT_EQ(decoded, indices);
}

TEST(Lzw, RoundTrips) {
  ExpectLzwRoundTrip({1}, 2);
  ExpectLzwRoundTrip({0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0}, 2);
  ExpectLzwRoundTrip({3, 1, 3, 1, 3, 1, 2, 2, 2, 0}, 2);
  for (int bits : {2, 4, 8}) {
    SCOPED_TRACE("min code size " + std::to_string(bits));
    Rng rng(42 + bits);
    // Random data fills the 4096-code table many times (clear codes).
    std::vector<uint8_t> random(200000);
    for (uint8_t& v : random) v = static_cast<uint8_t>(rng.Uniform() * (1 << bits));
    ExpectLzwRoundTrip(random, bits);
    // Long runs: the longest strings, and code widths that grow to 12 bits.
    std::vector<uint8_t> runs;
    for (int i = 0; i < 300000; ++i) runs.push_back(static_cast<uint8_t>((i / 1000) % (1 << bits)));
    ExpectLzwRoundTrip(runs, bits);
    // Few symbols, structured: what policy pictures look like.
    std::vector<uint8_t> stripes;
    for (int i = 0; i < 100000; ++i) stripes.push_back(static_cast<uint8_t>((i % 17 < 3) ? 1 : 0));
    ExpectLzwRoundTrip(stripes, bits);
  }
}

TEST(GifWriter, HeaderLoopAndFrames) {
  GifEncoder encoder(13, 7, kPalette);
  const std::vector<RgbImage> frames = {Pattern(13, 7, 0), Pattern(13, 7, 1), Pattern(13, 7, 1),
                                        Pattern(13, 7, 3)};
  for (const RgbImage& frame : frames) ASSERT_TRUE(encoder.AddFrame(frame, 100).ok());
  EXPECT_EQ(encoder.frames(), 4);
  const std::vector<uint8_t> file = encoder.Finish();
  ASSERT_GE(file.size(), 13u);
  EXPECT_EQ(std::string(file.begin(), file.begin() + 6), "GIF89a");
  EXPECT_EQ(file.back(), 0x3b);

  const testing::DecodedGif gif = testing::DecodeGif(file);
  ASSERT_EQ(gif.error, "");
  EXPECT_EQ(gif.width, 13);
  EXPECT_EQ(gif.height, 7);
  EXPECT_EQ(gif.loop_count, 0);  // forever
  ASSERT_EQ(gif.frames.size(), frames.size());
  for (size_t i = 0; i < frames.size(); ++i) {
    EXPECT_EQ(gif.frames[i], frames[i].bytes()) << "frame " << i;
    EXPECT_EQ(gif.delays_cs[i], 10);
  }
  // The palette comes first in the colour table.
  for (size_t i = 0; i < kPalette.size(); ++i) {
    EXPECT_EQ(gif.palette[3 * i], kPalette[i].r);
    EXPECT_EQ(gif.palette[3 * i + 1], kPalette[i].g);
    EXPECT_EQ(gif.palette[3 * i + 2], kPalette[i].b);
  }
}

TEST(GifWriter, DelaysAndNearestColours) {
  GifEncoder encoder(4, 4, kPalette, 3);
  RgbImage frame(4, 4, Rgb{240, 10, 10});  // nearest: red
  frame.Set(1, 2, Rgb{10, 10, 200});       // nearest: blue
  ASSERT_TRUE(encoder.AddFrame(frame, 1).ok());
  ASSERT_TRUE(encoder.AddFrame(frame, 333).ok());
  const testing::DecodedGif gif = testing::DecodeGif(encoder.Finish());
  ASSERT_EQ(gif.error, "");
  EXPECT_EQ(gif.loop_count, 3);
  ASSERT_EQ(gif.frames.size(), 2u);
  EXPECT_EQ(gif.delays_cs[0], 2);  // at least 2/100 s
  EXPECT_EQ(gif.delays_cs[1], 33);
  const RgbImage expected = [] {
    RgbImage image(4, 4, Rgb{255, 0, 0});
    image.Set(1, 2, Rgb{0, 0, 255});
    return image;
  }();
  EXPECT_EQ(gif.frames[0], expected.bytes());
  EXPECT_EQ(gif.frames[1], expected.bytes());
}

TEST(GifWriter, RejectsFramesOfAnotherSize) {
  GifEncoder encoder(5, 5, kPalette);
  EXPECT_FALSE(encoder.AddFrame(RgbImage(5, 6), 100).ok());
  EXPECT_EQ(encoder.frames(), 0);
}

TEST(GifWriter, PolicyPicturesAreExact) {
  // Drawn pictures use only DrawingPalette() colours: the GIF holds them
  // exactly, also when only small parts change between frames.
  policy_t policy = testing::MakePolicy(24, 24, "singleAgent", 0);
  GifEncoder encoder(DrawPolicy(policy).width(), DrawPolicy(policy).height(), DrawingPalette());
  std::vector<RgbImage> frames;
  for (int step = 0; step < 5; ++step) {
    policy.time_step = step;
    policy.actions[static_cast<size_t>(step * 30)] = static_cast<int8_t>(step);
    policy.reaches[static_cast<size_t>(step * 50)] = 0;
    if (step == 3) testing::AddRegion(policy, 12, 12, 12, 12);
    frames.push_back(DrawPolicy(policy));
    ASSERT_TRUE(encoder.AddFrame(frames.back(), 200).ok());
  }
  const std::vector<uint8_t> file = encoder.Finish();
  const testing::DecodedGif gif = testing::DecodeGif(file);
  ASSERT_EQ(gif.error, "");
  ASSERT_EQ(gif.frames.size(), frames.size());
  for (size_t i = 0; i < frames.size(); ++i) EXPECT_EQ(gif.frames[i], frames[i].bytes());
  // Later frames store only what changed: the file is far smaller than
  // five full frames.
  GifEncoder single(frames[0].width(), frames[0].height(), DrawingPalette());
  ASSERT_TRUE(single.AddFrame(frames[0], 200).ok());
  EXPECT_LT(file.size(), 2 * single.Finish().size());
}

}  // namespace
}  // namespace dynapath::view

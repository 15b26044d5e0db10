#include "tools/view/gif_writer.h"

#include <gtest/gtest.h>

#include <initializer_list>

#include "dynapath/rng.h"
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

// The file's structure as giflib reads it (DGifSlurp, no compositing): each
// frame's rectangle, graphic control block and colour indices, and the
// extension blocks before the first frame.
struct RawFrame {
  int left = 0, top = 0, width = 0, height = 0;
  bool interlaced = false, local_colours = false;
  GraphicsControlBlock control{};
  std::vector<uint8_t> indices;
};
struct RawGif {
  std::string error;
  int colour_resolution = 0, background = -1, table_size = 0;
  std::vector<RawFrame> frames;
  std::vector<std::vector<uint8_t>> first_extensions;  // function code, then the bytes
  int extensions_after_first = 0;  // application or comment blocks on later frames
};

RawGif ReadRaw(const std::vector<uint8_t>& file) {
  RawGif raw;
  testing::gif_internal::Source source{&file};
  int error = 0;
  GifFileType* gif = DGifOpen(&source, testing::gif_internal::Read, &error);
  if (gif == nullptr) {
    raw.error = GifErrorString(error);
    return raw;
  }
  if (DGifSlurp(gif) != GIF_OK) {
    raw.error = GifErrorString(gif->Error);
    DGifCloseFile(gif, &error);
    return raw;
  }
  raw.colour_resolution = gif->SColorResolution;
  raw.background = gif->SBackGroundColor;
  raw.table_size = gif->SColorMap != nullptr ? gif->SColorMap->ColorCount : 0;
  for (int f = 0; f < gif->ImageCount; ++f) {
    const SavedImage& image = gif->SavedImages[f];
    RawFrame frame;
    frame.left = image.ImageDesc.Left, frame.top = image.ImageDesc.Top;
    frame.width = image.ImageDesc.Width, frame.height = image.ImageDesc.Height;
    frame.interlaced = image.ImageDesc.Interlace;
    frame.local_colours = image.ImageDesc.ColorMap != nullptr;
    frame.control.TransparentColor = -2;  // "no graphic control extension"
    DGifSavedExtensionToGCB(gif, f, &frame.control);
    frame.indices.assign(image.RasterBits,
                         image.RasterBits + static_cast<size_t>(frame.width) * frame.height);
    for (int e = 0; e < image.ExtensionBlockCount; ++e) {
      const ExtensionBlock& block = image.ExtensionBlocks[e];
      if (block.Function == GRAPHICS_EXT_FUNC_CODE) continue;
      if (f > 0) {
        ++raw.extensions_after_first;
        continue;
      }
      std::vector<uint8_t> bytes = {static_cast<uint8_t>(block.Function)};
      bytes.insert(bytes.end(), block.Bytes, block.Bytes + block.ByteCount);
      raw.first_extensions.push_back(bytes);
    }
    raw.frames.push_back(frame);
  }
  DGifCloseFile(gif, &error);
  return raw;
}

std::vector<uint8_t> Bytes(std::initializer_list<int> values) {
  std::vector<uint8_t> bytes;
  for (int v : values) bytes.push_back(static_cast<uint8_t>(v));
  return bytes;
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

  // The file's structure: a table of 8 (5 colours and "unchanged"), the
  // loop extension once before the first frame, then the frames. Frames 1
  // and 3 change every pixel (whole rectangle, nothing transparent); frame
  // 2 repeats frame 1 (one transparent pixel).
  const RawGif raw = ReadRaw(file);
  ASSERT_EQ(raw.error, "");
  EXPECT_EQ(raw.table_size, 8);
  EXPECT_EQ(raw.colour_resolution, 8);
  EXPECT_EQ(raw.background, 0);
  const std::vector<std::vector<uint8_t>> loop = {
      Bytes({APPLICATION_EXT_FUNC_CODE, 'N', 'E', 'T', 'S', 'C', 'A', 'P', 'E', '2', '.', '0'}),
      Bytes({CONTINUE_EXT_FUNC_CODE, 1, 0, 0})};
  EXPECT_EQ(raw.first_extensions, loop);
  EXPECT_EQ(raw.extensions_after_first, 0);
  ASSERT_EQ(raw.frames.size(), 4u);
  auto pattern_indices = [](int seed) {
    std::vector<uint8_t> indices;
    for (int y = 0; y < 7; ++y) {
      for (int x = 0; x < 13; ++x)
        indices.push_back(static_cast<uint8_t>((x / 3 + y / 2 + seed) % 5));
    }
    return indices;
  };
  const int left[] = {0, 0, 0, 0}, width[] = {13, 13, 1, 13}, height[] = {7, 7, 1, 7};
  const int transparent[] = {NO_TRANSPARENT_COLOR, 5, 5, 5};
  const std::vector<uint8_t> indices[] = {
      pattern_indices(0), pattern_indices(1), {5}, pattern_indices(3)};
  for (size_t i = 0; i < raw.frames.size(); ++i) {
    SCOPED_TRACE("frame " + std::to_string(i));
    const RawFrame& frame = raw.frames[i];
    EXPECT_EQ(frame.left, left[i]);
    EXPECT_EQ(frame.top, 0);
    EXPECT_EQ(frame.width, width[i]);
    EXPECT_EQ(frame.height, height[i]);
    EXPECT_FALSE(frame.interlaced);
    EXPECT_FALSE(frame.local_colours);
    EXPECT_EQ(frame.control.DisposalMode, DISPOSE_DO_NOT);
    EXPECT_FALSE(frame.control.UserInputFlag);
    EXPECT_EQ(frame.control.DelayTime, 10);
    EXPECT_EQ(frame.control.TransparentColor, transparent[i]);
    EXPECT_EQ(frame.indices, indices[i]);
  }
}

TEST(GifWriter, StoresTheChangedRectangleWithUnchangedPixelsTransparent) {
  // 10x8 black; then (3,2) red and (6,4) green; then (3,2) black again.
  std::vector<RgbImage> frames(3, RgbImage(10, 8, kPalette[0]));
  frames[1].Set(3, 2, kPalette[1]);
  frames[1].Set(6, 4, kPalette[2]);
  frames[2].Set(6, 4, kPalette[2]);
  GifEncoder encoder(10, 8, kPalette, 0);
  const int delays_ms[] = {250, 1000, 54};
  for (size_t i = 0; i < frames.size(); ++i) {
    ASSERT_TRUE(encoder.AddFrame(frames[i], delays_ms[i]).ok());
  }
  const std::vector<uint8_t> file = encoder.Finish();

  const testing::DecodedGif gif = testing::DecodeGif(file);
  ASSERT_EQ(gif.error, "");
  ASSERT_EQ(gif.frames.size(), 3u);
  for (size_t i = 0; i < frames.size(); ++i) EXPECT_EQ(gif.frames[i], frames[i].bytes());
  EXPECT_EQ(gif.delays_cs, (std::vector<int>{25, 100, 5}));

  const RawGif raw = ReadRaw(file);
  ASSERT_EQ(raw.error, "");
  ASSERT_EQ(raw.frames.size(), 3u);
  const RawFrame& first = raw.frames[0];
  EXPECT_EQ(std::vector<int>({first.left, first.top, first.width, first.height}),
            std::vector<int>({0, 0, 10, 8}));
  EXPECT_EQ(first.control.TransparentColor, NO_TRANSPARENT_COLOR);
  EXPECT_EQ(first.indices, std::vector<uint8_t>(80, 0));
  // Columns 3..6, rows 2..4: red at the top left, green at the bottom right.
  const RawFrame& second = raw.frames[1];
  EXPECT_EQ(std::vector<int>({second.left, second.top, second.width, second.height}),
            std::vector<int>({3, 2, 4, 3}));
  EXPECT_EQ(second.control.TransparentColor, 5);
  EXPECT_EQ(second.indices, Bytes({1, 5, 5, 5,  //
                                   5, 5, 5, 5,  //
                                   5, 5, 5, 2}));
  const RawFrame& third = raw.frames[2];
  EXPECT_EQ(std::vector<int>({third.left, third.top, third.width, third.height}),
            std::vector<int>({3, 2, 1, 1}));
  EXPECT_EQ(third.control.TransparentColor, 5);
  EXPECT_EQ(third.indices, Bytes({0}));
  for (const RawFrame& frame : raw.frames) EXPECT_EQ(frame.control.DisposalMode, DISPOSE_DO_NOT);
}

TEST(GifWriter, FullPaletteHasNoTransparentIndex) {
  // 256 colours leave no index for "unchanged": later frames store their
  // changed rectangle with every pixel's own index. Random pixels fill
  // giflib's 4096-code LZW table many times.
  std::vector<Rgb> palette;
  for (int i = 0; i < 256; ++i) {
    palette.push_back(
        Rgb{static_cast<uint8_t>(i), static_cast<uint8_t>(255 - i), static_cast<uint8_t>(i * 7)});
  }
  Rng rng(7);
  const int width = 300, height = 200;
  std::vector<uint8_t> indices(static_cast<size_t>(width) * height);
  for (uint8_t& v : indices) v = static_cast<uint8_t>(rng.Uniform() * 256);
  RgbImage first(width, height);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) first.Set(x, y, palette[indices[y * width + x]]);
  }
  RgbImage second = first;
  second.Set(40, 30, palette[(indices[30 * width + 40] + 1) % 256]);
  second.Set(299, 31, palette[(indices[31 * width + 299] + 1) % 256]);
  GifEncoder encoder(width, height, palette);
  ASSERT_TRUE(encoder.AddFrame(first, 100).ok());
  ASSERT_TRUE(encoder.AddFrame(second, 100).ok());
  const std::vector<uint8_t> file = encoder.Finish();

  const testing::DecodedGif gif = testing::DecodeGif(file);
  ASSERT_EQ(gif.error, "");
  ASSERT_EQ(gif.frames.size(), 2u);
  EXPECT_EQ(gif.frames[0], first.bytes());
  EXPECT_EQ(gif.frames[1], second.bytes());
  const RawGif raw = ReadRaw(file);
  ASSERT_EQ(raw.error, "");
  EXPECT_EQ(raw.table_size, 256);
  ASSERT_EQ(raw.frames.size(), 2u);
  EXPECT_EQ(raw.frames[0].indices, indices);
  const RawFrame& changed = raw.frames[1];
  EXPECT_EQ(std::vector<int>({changed.left, changed.top, changed.width, changed.height}),
            std::vector<int>({40, 30, 260, 2}));
  EXPECT_EQ(changed.control.TransparentColor, NO_TRANSPARENT_COLOR);
  std::vector<uint8_t> expected;
  for (int y = 30; y < 32; ++y) {
    for (int x = 40; x < 300; ++x) expected.push_back(indices[y * width + x]);
  }
  expected[0] = static_cast<uint8_t>(expected[0] + 1);
  expected.back() = static_cast<uint8_t>(expected.back() + 1);
  EXPECT_EQ(changed.indices, expected);
}

TEST(GifWriter, LoopCountIsLittleEndian) {
  GifEncoder encoder(2, 2, kPalette, 1000);
  ASSERT_TRUE(encoder.AddFrame(RgbImage(2, 2), 100).ok());
  const RawGif raw = ReadRaw(encoder.Finish());
  ASSERT_EQ(raw.error, "");
  ASSERT_EQ(raw.first_extensions.size(), 2u);
  EXPECT_EQ(raw.first_extensions[1], Bytes({CONTINUE_EXT_FUNC_CODE, 1, 0xe8, 0x03}));
}

TEST(GifWriter, NoFramesAfterFinish) {
  GifEncoder encoder(3, 3, kPalette);
  ASSERT_TRUE(encoder.AddFrame(RgbImage(3, 3), 100).ok());
  const std::vector<uint8_t> file = encoder.Finish();
  EXPECT_EQ(testing::DecodeGif(file).frames.size(), 1u);
  EXPECT_FALSE(encoder.AddFrame(RgbImage(3, 3), 100).ok());
  EXPECT_EQ(encoder.frames(), 1);
  EXPECT_TRUE(encoder.Finish().empty());
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
  // The encoder goes on with frames of the right size.
  ASSERT_TRUE(encoder.AddFrame(RgbImage(5, 5, kPalette[3]), 100).ok());
  const testing::DecodedGif gif = testing::DecodeGif(encoder.Finish());
  ASSERT_EQ(gif.error, "");
  ASSERT_EQ(gif.frames.size(), 1u);
  EXPECT_EQ(gif.frames[0], RgbImage(5, 5, kPalette[3]).bytes());
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

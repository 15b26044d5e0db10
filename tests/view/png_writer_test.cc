#include "tools/view/png_writer.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "tests/view/image_decoders.h"
#include "tests/view/policy_test_support.h"
#include "tools/view/policy_drawing.h"

namespace dynapath::view {
namespace {

RgbImage Gradient(int width, int height) {
  RgbImage image(width, height);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      image.Set(x, y,
                Rgb{static_cast<uint8_t>(x * 37 + y), static_cast<uint8_t>(y * 53 + 7 * x),
                    static_cast<uint8_t>((x * y) ^ 0x5a)});
    }
  }
  return image;
}

TEST(PngWriter, DecodesBackToTheSamePixels) {
  for (auto [w, h] : {std::pair{1, 1}, std::pair{7, 5}, std::pair{64, 3}, std::pair{300, 211}}) {
    const RgbImage image = Gradient(w, h);
    const testing::DecodedPng png = testing::DecodePng(EncodePng(image));
    ASSERT_EQ(png.error, "") << w << "x" << h;
    EXPECT_EQ(png.width, w);
    EXPECT_EQ(png.height, h);
    EXPECT_TRUE(png.rgb8);
    EXPECT_EQ(png.rgb, image.bytes());
  }
}

TEST(PngWriter, HeaderAndCorruption) {
  const std::vector<uint8_t> file = EncodePng(Gradient(3, 2));
  ASSERT_GT(file.size(), 8u + 25 + 12 + 12);
  // The signature, then IHDR: length 13, type, width 3, height 2, 8-bit RGB.
  EXPECT_EQ(std::vector<uint8_t>(file.begin(), file.begin() + 8),
            (std::vector<uint8_t>{0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'}));
  EXPECT_EQ(std::string(file.begin() + 12, file.begin() + 16), "IHDR");
  EXPECT_EQ(file[19], 3);
  EXPECT_EQ(file[23], 2);
  EXPECT_EQ(file[24], 8);
  EXPECT_EQ(file[25], 2);
  // The file ends with IEND and its well-known CRC.
  const std::vector<uint8_t> end(file.end() - 12, file.end());
  EXPECT_EQ(end, (std::vector<uint8_t>{0, 0, 0, 0, 'I', 'E', 'N', 'D', 0xae, 0x42, 0x60, 0x82}));
  // A flipped bit in the header is caught by libpng's CRC check, and a
  // truncated file is refused.
  std::vector<uint8_t> broken = file;
  broken[18] ^= 1;
  EXPECT_NE(testing::DecodePng(broken).error, "");
  const std::vector<uint8_t> truncated(file.begin(), file.begin() + 40);
  EXPECT_NE(testing::DecodePng(truncated).error, "");
}

TEST(PngWriter, EmptyImageIsNotEncoded) { EXPECT_TRUE(EncodePng(RgbImage()).empty()); }

TEST(PngWriter, WritesFiles) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("png_writer_test_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const RgbImage picture = DrawPolicy(testing::MakePolicy(10, 12));
  const std::string path = (dir / "policy.png").string();
  ASSERT_TRUE(WritePng(path, picture).ok());
  std::ifstream in(path, std::ios::binary);
  const std::vector<uint8_t> bytes{std::istreambuf_iterator<char>(in), {}};
  EXPECT_EQ(bytes, EncodePng(picture));
  const testing::DecodedPng png = testing::DecodePng(bytes);
  EXPECT_EQ(png.width, picture.width());
  EXPECT_EQ(png.height, picture.height());
  EXPECT_EQ(png.rgb, picture.bytes());
  // No temporary files left behind.
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir),
                          std::filesystem::directory_iterator()),
            1);
  // A directory that does not exist: an error, no crash.
  const Status failed = WritePng((dir / "missing" / "x.png").string(), picture);
  EXPECT_FALSE(failed.ok());
  EXPECT_NE(failed.error().message.find("x.png: cannot write: No such file or directory"),
            std::string::npos);
  EXPECT_FALSE(WritePng((dir / "empty.png").string(), RgbImage()).ok());
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace dynapath::view

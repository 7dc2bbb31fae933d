// MjpegDecoder against images encoded in the test by libturbojpeg (an independent encoder run),
// compared to the source pixels by PSNR, and with its Huffman tables stripped as UVC cameras do.
#include "drivers/convert/mjpeg_decoder.h"

#include <gtest/gtest.h>
#include <turbojpeg.h>

#include <cmath>
#include <map>
#include <vector>

#include "drivers/convert/mjpeg_huffman_tables.h"

namespace hd::drivers {
namespace {

// A smooth scene with edges: gradients plus a bright disc, as RGBA.
std::vector<uint8_t> test_image(int w, int h) {
  std::vector<uint8_t> img(static_cast<std::size_t>(w) * h * 4);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      uint8_t* p = &img[static_cast<std::size_t>((y * w + x) * 4)];
      const double dx = x - w * 0.6;
      const double dy = y - h * 0.4;
      const bool disc = dx * dx + dy * dy < (h * 0.2) * (h * 0.2);
      p[0] = static_cast<uint8_t>(disc ? 240 : 255 * x / w);
      p[1] = static_cast<uint8_t>(disc ? 220 : 255 * y / h);
      p[2] = static_cast<uint8_t>(disc ? 40 : 128 + 100 * std::sin(x * 0.05));
      p[3] = 255;
    }
  }
  return img;
}

std::vector<uint8_t> encode(const std::vector<uint8_t>& rgba, int w, int h, int quality) {
  tjhandle tj = tjInitCompress();
  unsigned char* out = nullptr;
  unsigned long out_len = 0;
  const int rc =
      tjCompress2(tj, rgba.data(), w, w * 4, h, TJPF_RGBA, &out, &out_len, TJSAMP_422, quality, 0);
  std::vector<uint8_t> jpeg;
  if (rc == 0) jpeg.assign(out, out + out_len);
  tjFree(out);
  tjDestroy(tj);
  return jpeg;
}

double psnr_rgb(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
  double sse = 0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (i % 4 == 3) continue;
    const double d = double(a[i]) - double(b[i]);
    sse += d * d;
    ++n;
  }
  return 10.0 * std::log10(255.0 * 255.0 / (sse / double(n)));
}

// The test's own marker walk: every DHT segment cut out, the rest kept.
std::vector<uint8_t> strip_dht(const std::vector<uint8_t>& jpeg,
                               std::vector<std::vector<uint8_t>>* removed = nullptr) {
  std::vector<uint8_t> out(jpeg.begin(), jpeg.begin() + 2);
  std::size_t pos = 2;
  while (pos + 4 <= jpeg.size()) {
    const uint8_t marker = jpeg[pos + 1];
    if (marker == 0xDA) break;
    const std::size_t seg = 2 + ((jpeg[pos + 2] << 8) | jpeg[pos + 3]);
    if (marker == 0xC4) {
      if (removed) removed->emplace_back(jpeg.begin() + pos, jpeg.begin() + pos + seg);
    } else {
      out.insert(out.end(), jpeg.begin() + pos, jpeg.begin() + pos + seg);
    }
    pos += seg;
  }
  out.insert(out.end(), jpeg.begin() + pos, jpeg.end());
  return out;
}

// DHT segments -> {class/id: counts+symbols}, however the encoder grouped them into segments.
std::map<int, std::vector<uint8_t>> parse_tables(const std::vector<std::vector<uint8_t>>& segs) {
  std::map<int, std::vector<uint8_t>> tables;
  for (const auto& s : segs) {
    std::size_t p = 4;
    while (p < s.size()) {
      const int id = s[p];
      int count = 0;
      for (int i = 0; i < 16; ++i) count += s[p + 1 + i];
      tables[id].assign(s.begin() + p + 1, s.begin() + p + 17 + count);
      p += 17 + count;
    }
  }
  return tables;
}

TEST(MjpegDecoder, DecodesToRgbaWithHighPsnr) {
  const int w = 160;
  const int h = 120;
  const auto src = test_image(w, h);
  const auto jpeg = encode(src, w, h, 90);
  ASSERT_FALSE(jpeg.empty());
  MjpegDecoder dec(jpeg.size());
  int rw = 0;
  int rh = 0;
  ASSERT_TRUE(dec.read_size(jpeg.data(), jpeg.size(), rw, rh)) << dec.error();
  EXPECT_EQ(rw, w);
  EXPECT_EQ(rh, h);
  std::vector<uint8_t> out(src.size(), 0);
  ASSERT_TRUE(dec.decode_rgba(jpeg.data(), jpeg.size(), w, h, out.data(), out.size(), w * 4))
      << dec.error();
  EXPECT_GT(psnr_rgb(src, out), 30.0);
  for (std::size_t i = 3; i < out.size(); i += 4) ASSERT_EQ(out[i], 255);
  EXPECT_EQ(dec.tables_inserted(), 0u);
}

TEST(MjpegDecoder, DecodesIntoAPaddedStride) {
  const int w = 64;
  const int h = 32;
  const auto src = test_image(w, h);
  const auto jpeg = encode(src, w, h, 95);
  const int stride = w * 4 + 16;
  std::vector<uint8_t> out(static_cast<std::size_t>(stride) * h, 0x5A);
  MjpegDecoder dec;
  ASSERT_TRUE(dec.decode_rgba(jpeg.data(), jpeg.size(), w, h, out.data(), out.size(), stride));
  std::vector<uint8_t> packed;
  for (int y = 0; y < h; ++y) {
    packed.insert(packed.end(), out.begin() + y * stride, out.begin() + y * stride + w * 4);
    for (int b = w * 4; b < stride; ++b) ASSERT_EQ(out[y * stride + b], 0x5A);
  }
  // Same pixels as a decode into a packed buffer; the padding is never touched.
  std::vector<uint8_t> direct(src.size());
  ASSERT_TRUE(dec.decode_rgba(jpeg.data(), jpeg.size(), w, h, direct.data(), direct.size(), w * 4));
  EXPECT_EQ(packed, direct);
  EXPECT_GT(psnr_rgb(src, packed), 25.0);  // small image, sharp disc edge, 4:2:2 chroma
}

TEST(MjpegDecoder, OurStandardTablesEqualTheEncodersDefaults) {
  const auto jpeg = encode(test_image(32, 32), 32, 32, 80);
  std::vector<std::vector<uint8_t>> removed;
  strip_dht(jpeg, &removed);
  ASSERT_FALSE(removed.empty());
  const auto theirs = parse_tables(removed);
  const auto seg = standard_dht_segment();
  const auto ours = parse_tables({std::vector<uint8_t>(seg.begin(), seg.end())});
  EXPECT_EQ(ours.size(), 4u);
  EXPECT_EQ(ours, theirs);
  EXPECT_EQ((seg[2] << 8) | seg[3], static_cast<int>(seg.size()) - 2);
}

TEST(MjpegDecoder, InsertsHuffmanTablesWhenAFrameHasNone) {
  const int w = 96;
  const int h = 64;
  const auto src = test_image(w, h);
  const auto jpeg = encode(src, w, h, 85);
  const auto stripped = strip_dht(jpeg);
  ASSERT_LT(stripped.size(), jpeg.size());
  ASSERT_FALSE(scan_jpeg_layout(stripped.data(), stripped.size()).has_huffman);
  ASSERT_TRUE(scan_jpeg_layout(jpeg.data(), jpeg.size()).has_huffman);

  MjpegDecoder dec(jpeg.size());
  std::vector<uint8_t> a(src.size());
  std::vector<uint8_t> b(src.size());
  ASSERT_TRUE(dec.decode_rgba(jpeg.data(), jpeg.size(), w, h, a.data(), a.size(), w * 4));
  ASSERT_TRUE(dec.decode_rgba(stripped.data(), stripped.size(), w, h, b.data(), b.size(), w * 4))
      << dec.error();
  EXPECT_EQ(a, b);  // same entropy-coded data, same tables: bit-identical pixels
  EXPECT_EQ(dec.tables_inserted(), 1u);

  std::vector<uint8_t> fixed(stripped.size() + standard_dht_segment().size());
  ASSERT_EQ(
      insert_standard_huffman_tables(stripped.data(), stripped.size(), fixed.data(), fixed.size()),
      fixed.size());
  EXPECT_TRUE(scan_jpeg_layout(fixed.data(), fixed.size()).has_huffman);
  EXPECT_EQ(insert_standard_huffman_tables(stripped.data(), stripped.size(), fixed.data(),
                                           fixed.size() - 1),
            0u);
}

TEST(MjpegDecoder, RejectsTruncatedCorruptAndMismatchedFrames) {
  const int w = 64;
  const int h = 48;
  const auto jpeg = encode(test_image(w, h), w, h, 90);
  MjpegDecoder dec(jpeg.size());
  std::vector<uint8_t> out(static_cast<std::size_t>(w) * h * 4);

  const std::size_t cut = jpeg.size() * 6 / 10;
  EXPECT_FALSE(dec.decode_rgba(jpeg.data(), cut, w, h, out.data(), out.size(), w * 4));
  EXPECT_STRNE(dec.error(), "");

  std::vector<uint8_t> garbage(500, 0x42);
  EXPECT_FALSE(
      dec.decode_rgba(garbage.data(), garbage.size(), w, h, out.data(), out.size(), w * 4));
  EXPECT_NE(std::string(dec.error()).find("SOI"), std::string::npos) << dec.error();

  // Header cut inside a marker segment.
  EXPECT_FALSE(dec.decode_rgba(jpeg.data(), 30, w, h, out.data(), out.size(), w * 4));
  EXPECT_NE(std::string(dec.error()).find("corrupt"), std::string::npos) << dec.error();

  EXPECT_FALSE(
      dec.decode_rgba(jpeg.data(), jpeg.size(), w + 16, h, out.data(), out.size(), (w + 16) * 4));
  EXPECT_FALSE(dec.decode_rgba(jpeg.data(), jpeg.size(), w, h, out.data(), out.size() - 1, w * 4));
  EXPECT_NE(std::string(dec.error()).find("too small"), std::string::npos) << dec.error();

  // The decoder still works after errors.
  EXPECT_TRUE(dec.decode_rgba(jpeg.data(), jpeg.size(), w, h, out.data(), out.size(), w * 4))
      << dec.error();
  EXPECT_STREQ(dec.error(), "");
}

TEST(MjpegDecoder, AValidFrameDecodesAfterACorruptHeader) {
  // Regression: a bogus DHT left libjpeg-turbo's decompressor mid-header, and the next, valid
  // frame then failed with the same error.
  const int w = 32;
  const int h = 16;
  const auto jpeg = encode(test_image(w, h), w, h, 90);
  std::vector<uint8_t> bogus = jpeg;
  const std::size_t dht = [&] {
    for (std::size_t p = 2; p + 1 < bogus.size(); ++p) {
      if (bogus[p] == 0xFF && bogus[p + 1] == 0xC4) return p;
    }
    return std::size_t{0};
  }();
  ASSERT_GT(dht, 0u);
  for (int i = 0; i < 16; ++i) bogus[dht + 5 + i] = 0xFF;  // code counts summing far past 256
  MjpegDecoder dec;
  std::vector<uint8_t> out(static_cast<std::size_t>(w) * h * 4);
  EXPECT_FALSE(dec.decode_rgba(bogus.data(), bogus.size(), w, h, out.data(), out.size(), w * 4));
  EXPECT_NE(std::string(dec.error()).find("Huffman"), std::string::npos) << dec.error();
  EXPECT_TRUE(dec.decode_rgba(jpeg.data(), jpeg.size(), w, h, out.data(), out.size(), w * 4))
      << dec.error();
}

}  // namespace
}  // namespace hd::drivers

// Randomized robustness run for the YUYV and MJPEG converters (the sanitizer build runs it too):
// random sizes, strides and lengths, random bytes, and mutated valid JPEGs. Pass = no crash, no
// sanitizer report, and every rejection leaves a message.
#include <gtest/gtest.h>
#include <turbojpeg.h>

#include <cstdio>
#include <random>
#include <vector>

#include "drivers/convert/mjpeg_decoder.h"
#include "drivers/convert/mjpeg_huffman_tables.h"
#include "drivers/convert/yuyv_to_rgba.h"

namespace hd::drivers {
namespace {

TEST(ConverterFuzz, YuyvRandomGeometryAndBytes) {
  std::mt19937_64 rng(0xC0FFEE);
  std::vector<uint8_t> src(64 * 1024);
  std::vector<uint8_t> dst(128 * 1024);
  for (auto& b : src) b = static_cast<uint8_t>(rng());
  constexpr int kRuns = 900'000;
  int accepted = 0;
  for (int i = 0; i < kRuns; ++i) {
    const int w = static_cast<int>(rng() % 40) - 4;  // includes odd, zero and negative
    const int h = static_cast<int>(rng() % 20) - 2;
    const int src_stride = w * 2 + static_cast<int>(rng() % 9) - 2;
    const int dst_stride = w * 4 + static_cast<int>(rng() % 9) - 2;
    const std::size_t src_len = rng() % 4000;
    const std::size_t dst_len = rng() % 8000;
    // Feed from a random offset so the source bytes differ each run; stay inside the arrays so a
    // reported overrun is the converter's, not this test's.
    const std::size_t src_off = rng() % (src.size() - src_len);
    const std::size_t dst_off = rng() % (dst.size() - dst_len);
    if (yuyv_to_rgba(src.data() + src_off, src_len, w, h, src_stride, dst.data() + dst_off, dst_len,
                     dst_stride)) {
      ++accepted;
    }
  }
  // The generator produces both valid and invalid inputs; both paths must have run.
  EXPECT_GT(accepted, kRuns / 20);
  EXPECT_LT(accepted, kRuns);
}

std::vector<uint8_t> encode(std::mt19937_64& rng, int w, int h, int subsamp, int quality) {
  std::vector<uint8_t> rgba(static_cast<std::size_t>(w) * h * 4);
  for (std::size_t i = 0; i < rgba.size(); ++i) rgba[i] = static_cast<uint8_t>((i * 7) ^ rng());
  tjhandle tj = tjInitCompress();
  unsigned char* out = nullptr;
  unsigned long len = 0;
  std::vector<uint8_t> jpeg;
  if (tjCompress2(tj, rgba.data(), w, w * 4, h, TJPF_RGBA, &out, &len, subsamp, quality, 0) == 0) {
    jpeg.assign(out, out + len);
  }
  tjFree(out);
  tjDestroy(tj);
  return jpeg;
}

TEST(ConverterFuzz, MjpegMutatedFrames) {
  std::mt19937_64 rng(0xBEEF);
  struct Seed {
    int w, h;
    std::vector<uint8_t> jpeg;
  };
  std::vector<Seed> seeds;
  const int sub[] = {TJSAMP_444, TJSAMP_422, TJSAMP_420, TJSAMP_GRAY};
  for (int i = 0; i < 8; ++i) {
    const int w = 8 + static_cast<int>(rng() % 25);
    const int h = 8 + static_cast<int>(rng() % 17);
    seeds.push_back({w, h, encode(rng, w, h, sub[i % 4], 50 + i * 6)});
    ASSERT_FALSE(seeds.back().jpeg.empty());
  }
  MjpegDecoder dec(4096);
  std::vector<uint8_t> dst(64 * 64 * 4);
  std::vector<uint8_t> buf;
  buf.reserve(8192);
  constexpr int kRuns = 120'000;
  int decoded = 0;
  int rejected_without_message = 0;
  int valid_frames_refused = 0;
  for (int i = 0; i < kRuns; ++i) {
    const Seed& s = seeds[rng() % seeds.size()];
    buf.assign(s.jpeg.begin(), s.jpeg.end());
    bool unmodified = false;
    switch (rng() % 6) {
      case 0:  // random byte flips
        for (int k = 1 + static_cast<int>(rng() % 8); k > 0; --k)
          buf[rng() % buf.size()] ^= 1u << (rng() % 8);
        break;
      case 1:  // truncation
        buf.resize(rng() % buf.size());
        break;
      case 2:  // Huffman tables stripped, then maybe flipped
        buf = [&] {
          std::vector<uint8_t> out(buf.begin(), buf.begin() + 2);
          std::size_t p = 2;
          while (p + 4 <= buf.size() && buf[p + 1] != 0xDA) {
            const std::size_t seg = 2 + ((buf[p + 2] << 8) | buf[p + 3]);
            if (buf[p + 1] != 0xC4) out.insert(out.end(), buf.begin() + p, buf.begin() + p + seg);
            p += seg;
          }
          out.insert(out.end(), buf.begin() + p, buf.end());
          return out;
        }();
        if (rng() % 2) buf[rng() % buf.size()] = static_cast<uint8_t>(rng());
        break;
      case 3:  // header bytes overwritten (segment lengths, SOF dimensions)
        buf[2 + rng() % std::min<std::size_t>(buf.size() - 2, 200)] = static_cast<uint8_t>(rng());
        break;
      case 4:  // pure noise, sometimes with a JPEG start
        buf.resize(rng() % 600);
        for (auto& b : buf) b = static_cast<uint8_t>(rng());
        if (buf.size() >= 2 && rng() % 2) {
          buf[0] = 0xFF;
          buf[1] = 0xD8;
        }
        break;
      default:  // unmodified: must decode
        unmodified = true;
        break;
    }
    // Mostly the seed's true size; sometimes a wrong one.
    int w = s.w;
    int h = s.h;
    if (rng() % 8 == 0) w = 1 + static_cast<int>(rng() % 64);
    const bool ok = dec.decode_rgba(buf.data(), buf.size(), w, h, dst.data(), dst.size(), w * 4);
    // A valid frame must decode whatever garbage came before it (decoder state is reset).
    if (unmodified && w == s.w && !ok) ++valid_frames_refused;
    if (ok) {
      ++decoded;
    } else if (dec.error()[0] == '\0') {
      ++rejected_without_message;
    }
  }
  EXPECT_GT(decoded, kRuns / 8);
  EXPECT_EQ(rejected_without_message, 0);
  EXPECT_EQ(valid_frames_refused, 0);
  std::printf("MJPEG fuzz: %d inputs, %d decoded, %llu needed tables inserted\n", kRuns, decoded,
              static_cast<unsigned long long>(dec.tables_inserted()));
}

TEST(ConverterFuzz, JpegLayoutScannerOnRandomBytes) {
  std::mt19937_64 rng(42);
  std::vector<uint8_t> buf(256);
  std::vector<uint8_t> out(256 + standard_dht_segment().size());
  constexpr int kRuns = 200'000;
  for (int i = 0; i < kRuns; ++i) {
    const std::size_t n = rng() % buf.size();
    for (std::size_t k = 0; k < n; ++k)
      buf[k] = (rng() % 3 == 0) ? 0xFF : static_cast<uint8_t>(rng());
    if (n >= 2) {
      buf[0] = 0xFF;
      buf[1] = 0xD8;
    }
    const JpegLayout l = scan_jpeg_layout(buf.data(), n);
    ASSERT_TRUE(l.valid || l.error != nullptr);
    if (l.valid) {
      ASSERT_LT(l.sos_offset, n);
    }
    const std::size_t written =
        insert_standard_huffman_tables(buf.data(), n, out.data(), out.size());
    ASSERT_TRUE(written == 0 || written == n + standard_dht_segment().size());
  }
}

}  // namespace
}  // namespace hd::drivers

// scan_h264_access_unit / sei_recovery_frame_cnt on bytes assembled by hand (bit by bit, with
// the test's own emulation prevention) and on a real x264 intra-refresh access unit; malformed
// input is refused without reading outside it.
#include "drivers/rtp/h264_recovery_point.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <utility>
#include <vector>

namespace hd::drivers {
namespace {

using Bytes = std::vector<uint8_t>;

// Bits MSB first, padded with the rbsp stop bit's pattern by the caller.
struct BitWriter {
  Bytes bytes;
  int used = 8;
  void bit(int b) {
    if (used == 8) {
      bytes.push_back(0);
      used = 0;
    }
    if (b) bytes.back() |= uint8_t(0x80 >> used);
    ++used;
  }
  void ue(uint32_t v) {  // 9.1: zeros, then v + 1 in binary
    const uint64_t x = uint64_t(v) + 1;
    int n = 0;
    while ((x >> (n + 1)) != 0) ++n;
    for (int i = 0; i < n; ++i) bit(0);
    for (int i = n; i >= 0; --i) bit(int((x >> i) & 1));
  }
  void align_with_one() {  // bit_equal_to_one then zeros (SEI payload / rbsp trailing bits)
    bit(1);
    while (used != 8) bit(0);
  }
};

// A recovery point payload (D.1.8): recovery_frame_cnt, exact_match 1, broken_link 0,
// changing_slice_group_idc 0.
Bytes recovery_payload(uint32_t cnt) {
  BitWriter w;
  w.ue(cnt);
  w.bit(1);
  w.bit(0);
  w.bit(0);
  w.bit(0);
  w.align_with_one();
  return w.bytes;
}

// 7.4.1: 00 00 followed by 00..03 gets an 03 between.
Bytes escape(const Bytes& rbsp) {
  Bytes out;
  int zeros = 0;
  for (uint8_t b : rbsp) {
    if (zeros >= 2 && b <= 3) {
      out.push_back(3);
      zeros = 0;
    }
    out.push_back(b);
    zeros = b == 0 ? zeros + 1 : 0;
  }
  return out;
}

// An SEI NAL unit of (type, payload) messages.
Bytes sei(const std::vector<std::pair<uint32_t, Bytes>>& messages) {
  Bytes rbsp;
  for (const auto& [type, payload] : messages) {
    for (uint32_t t = type;; t -= 255) {
      if (t < 255) {
        rbsp.push_back(uint8_t(t));
        break;
      }
      rbsp.push_back(0xFF);
    }
    rbsp.push_back(uint8_t(payload.size()));
    rbsp.insert(rbsp.end(), payload.begin(), payload.end());
  }
  rbsp.push_back(0x80);
  Bytes nal{0x06};
  const Bytes e = escape(rbsp);
  nal.insert(nal.end(), e.begin(), e.end());
  return nal;
}

Bytes annex_b(const std::vector<Bytes>& nals) {
  Bytes au;
  for (const Bytes& n : nals) {
    au.insert(au.end(), {0, 0, 0, 1});
    au.insert(au.end(), n.begin(), n.end());
  }
  return au;
}

Bytes avc(const std::vector<Bytes>& nals) {
  Bytes au;
  for (const Bytes& n : nals) {
    const uint32_t s = uint32_t(n.size());
    au.insert(au.end(), {uint8_t(s >> 24), uint8_t(s >> 16), uint8_t(s >> 8), uint8_t(s)});
    au.insert(au.end(), n.begin(), n.end());
  }
  return au;
}

const Bytes kAud{0x09, 0x30}, kSlice{0x41, 0x9a, 0x00, 0x11}, kIdr{0x65, 0x88, 0x84, 0x00};

TEST(H264RecoveryPoint, HandAssembledSeiGivesItsCountInBothFramings) {
  for (uint32_t cnt : {0u, 14u, 29u, 300u, 65535u}) {
    const std::vector<Bytes> nals{kAud, sei({{6, recovery_payload(cnt)}}), kSlice};
    for (const auto& [au, framing] : {std::pair{annex_b(nals), H264Framing::kAnnexB},
                                      std::pair{avc(nals), H264Framing::kAvc}}) {
      const H264AccessUnitInfo i = scan_h264_access_unit(au, framing);
      ASSERT_TRUE(i.recovery_frame_cnt.has_value()) << cnt;
      EXPECT_EQ(*i.recovery_frame_cnt, cnt);
      EXPECT_FALSE(i.idr);
      EXPECT_FALSE(i.malformed);
    }
  }
}

TEST(H264RecoveryPoint, FindsItBehindAnotherMessageWithEmulationPreventionBytes) {
  // user_data_unregistered (type 5): a zero UUID, so the NAL unit carries 00 00 03 sequences the
  // sizes do not count; then the recovery point.
  Bytes user(20, 0);
  user[16] = 'x';
  const Bytes nal = sei({{5, user}, {6, recovery_payload(7)}});
  ASSERT_GT(nal.size(), 1 + 2 + user.size() + 2 + 2);  // escaping added bytes
  bool malformed = false;
  EXPECT_EQ(sei_recovery_frame_cnt(nal, &malformed), 7u);
  EXPECT_FALSE(malformed);
  // A type above 255 (FF then the rest) before it is skipped as well.
  EXPECT_EQ(sei_recovery_frame_cnt(sei({{300, Bytes{1, 2, 3}}, {6, recovery_payload(9)}})), 9u);
}

TEST(H264RecoveryPoint, IdrAndSeiWithoutRecoveryPoint) {
  const H264AccessUnitInfo i =
      scan_h264_access_unit(annex_b({kAud, sei({{5, Bytes(17, 1)}}), kIdr}), H264Framing::kAnnexB);
  EXPECT_TRUE(i.idr);
  EXPECT_FALSE(i.recovery_frame_cnt.has_value());
  EXPECT_FALSE(i.malformed);
  EXPECT_FALSE(scan_h264_access_unit(avc({kSlice}), H264Framing::kAvc).idr);
}

// The start of access unit 15 of `gst-launch-1.0 videotestsrc pattern=ball ! 640x480 30/1 !
// x264enc intra-refresh=true key-int-max=15 tune=zerolatency speed-preset=ultrafast bframes=0 !
// video/x-h264,stream-format=byte-stream,alignment=au` (GStreamer 1.22, x264 164): AUD, SPS, PPS,
// the recovery point SEI (06 06 02 1f 10 80: recovery_frame_cnt 14, a sweep of 15 frames) and
// the first bytes of a non-IDR slice.
const Bytes kX264RefreshStart{
    0x00, 0x00, 0x00, 0x01, 0x09, 0x30, 0x00, 0x00, 0x00, 0x01, 0x67, 0xf4, 0x00, 0x1e, 0x90,
    0xd9, 0x68, 0x0a, 0x03, 0xdb, 0x01, 0x6a, 0x0c, 0x0c, 0x0c, 0x80, 0x00, 0x00, 0x03, 0x00,
    0x80, 0x00, 0x00, 0x1e, 0x47, 0x8b, 0x17, 0x50, 0x00, 0x00, 0x00, 0x01, 0x68, 0xce, 0x31,
    0x92, 0x00, 0x00, 0x01, 0x06, 0x06, 0x02, 0x1f, 0x10, 0x80, 0x00, 0x00, 0x01, 0x41, 0x9b,
    0xe0, 0x09, 0xaa, 0x26, 0x28, 0x00, 0x03, 0x4b, 0xcc, 0x50, 0x00, 0x10};

TEST(H264RecoveryPoint, RealX264IntraRefreshAccessUnit) {
  const H264AccessUnitInfo i = scan_h264_access_unit(kX264RefreshStart, H264Framing::kAnnexB);
  ASSERT_TRUE(i.recovery_frame_cnt.has_value());
  EXPECT_EQ(*i.recovery_frame_cnt, 14u);
  EXPECT_FALSE(i.idr);
  EXPECT_FALSE(i.malformed);
}

TEST(H264RecoveryPoint, MalformedInputIsRefusedWithoutReadingPastIt) {
  bool malformed = false;
  // The size says 9 bytes, 2 follow.
  EXPECT_FALSE(sei_recovery_frame_cnt(Bytes{0x06, 0x06, 0x09, 0x1f, 0x10}, &malformed));
  EXPECT_TRUE(malformed);
  // ue(v) of 40 leading zeros.
  malformed = false;
  EXPECT_FALSE(
      sei_recovery_frame_cnt(Bytes{0x06, 0x06, 0x06, 0, 0, 0, 0, 0, 0x80, 0x80}, &malformed));
  EXPECT_TRUE(malformed);
  // A count above 65535 (H.264 forbids it).
  malformed = false;
  EXPECT_FALSE(sei_recovery_frame_cnt(sei({{6, recovery_payload(70000)}}), &malformed));
  EXPECT_TRUE(malformed);
  // Sizes of FF forever, truncated.
  malformed = false;
  EXPECT_FALSE(sei_recovery_frame_cnt(Bytes{0x06, 0xFF, 0xFF, 0xFF}, &malformed));
  EXPECT_TRUE(malformed);
  // Not an SEI, or empty: nothing, not malformed.
  malformed = false;
  EXPECT_FALSE(sei_recovery_frame_cnt(kSlice, &malformed));
  EXPECT_FALSE(sei_recovery_frame_cnt(Bytes{}, &malformed));
  EXPECT_FALSE(malformed);
  // AVC: a length past the end, and 3 bytes that cannot hold a length.
  Bytes au = avc({kAud, sei({{6, recovery_payload(3)}})});
  au[4 + 2 + 3] += 1;  // the SEI's length's low byte (after AUD's 4 + 2), one too long
  EXPECT_TRUE(scan_h264_access_unit(au, H264Framing::kAvc).malformed);
  EXPECT_TRUE(scan_h264_access_unit(Bytes{0, 0, 1}, H264Framing::kAvc).malformed);
  // Annex B without any start code.
  EXPECT_TRUE(scan_h264_access_unit(Bytes{0x41, 0x9a, 0x00}, H264Framing::kAnnexB).malformed);
  // Every prefix of a real access unit and of a hand-made AVC one: never a crash (ASan checks
  // the reads), and a recovery point only where the SEI is whole.
  for (std::size_t n = 0; n <= kX264RefreshStart.size(); ++n) {
    const H264AccessUnitInfo i = scan_h264_access_unit(
        std::span<const uint8_t>(kX264RefreshStart.data(), n), H264Framing::kAnnexB);
    if (i.recovery_frame_cnt) {
      EXPECT_EQ(*i.recovery_frame_cnt, 14u);
      EXPECT_GE(n, 54u);  // up to the SEI's payload, 1f 10
    }
  }
  const Bytes whole = avc({kAud, sei({{6, recovery_payload(5)}}), kSlice});
  for (std::size_t n = 0; n < whole.size(); ++n)
    scan_h264_access_unit(std::span<const uint8_t>(whole.data(), n), H264Framing::kAvc);
}

TEST(H264RecoveryPoint, WhichRtpPayloadsBeginAPicture) {
  EXPECT_TRUE(h264_payload_starts_picture(Bytes{0x09, 0x30}));                    // AUD
  EXPECT_TRUE(h264_payload_starts_picture(Bytes{0x67, 0x42}));                    // SPS
  EXPECT_TRUE(h264_payload_starts_picture(Bytes{0x06, 0x06, 0x02}));              // SEI
  EXPECT_TRUE(h264_payload_starts_picture(Bytes{0x41, 0x9a, 0x00}));              // slice, mb 0
  EXPECT_FALSE(h264_payload_starts_picture(Bytes{0x41, 0x20, 0x00}));             // slice, mb > 0
  EXPECT_TRUE(h264_payload_starts_picture(Bytes{0x18, 0x00, 0x02, 0x09, 0x30}));  // STAP-A: AUD
  EXPECT_TRUE(h264_payload_starts_picture(Bytes{0x7c, 0x85, 0x88, 0x84}));        // FU-A S, IDR
  EXPECT_FALSE(h264_payload_starts_picture(Bytes{0x7c, 0x05, 0x88, 0x84}));       // FU-A middle
  EXPECT_FALSE(h264_payload_starts_picture(Bytes{0x5c, 0x81, 0x20}));  // FU-A S, slice mb > 0
  EXPECT_FALSE(h264_payload_starts_picture(Bytes{}));
  EXPECT_FALSE(h264_payload_starts_picture(Bytes{0x18, 0x00}));  // STAP-A cut short
  EXPECT_FALSE(h264_payload_starts_picture(Bytes{0x41}));        // a slice without its header
}

}  // namespace
}  // namespace hd::drivers

#pragma once
// H.264 access units as rtph264depay outputs them, read for what healing after a loss needs: is
// it an IDR, and does it carry a recovery point SEI (payloadType 6: x264's intra refresh marks
// the start of each refresh cycle with one). Pure functions over bytes; malformed input gives
// "nothing found" and sets `malformed`, never reads outside the span.

#include <cstdint>
#include <optional>
#include <span>

namespace hd::drivers {

/// How NAL units are delimited: start codes (00 00 01 / 00 00 00 01, stream-format=byte-stream)
/// or a 4-byte big-endian length before each (stream-format=avc, as rtph264depay writes it).
enum class H264Framing : uint8_t { kAnnexB, kAvc };

struct H264AccessUnitInfo {
  bool idr = false;  ///< a coded slice of an IDR picture (NAL type 5)
  /// From the first recovery point SEI: the frame recovery_frame_cnt frames after this one (in
  /// output order, this one counting 0) is a whole picture if decoding starts here.
  std::optional<uint32_t> recovery_frame_cnt;
  bool malformed = false;  ///< a NAL length past the end, or an SEI that does not parse
};

/// recovery_frame_cnt of the recovery point message in one SEI NAL unit (`nal` starts with the
/// NAL header byte, type 6, emulation-prevention bytes still in). nullopt: no such message, or
/// the SEI is malformed (a size past the end, a ue(v) longer than 32 bits, a count above 65535,
/// which H.264 forbids: it is less than MaxFrameNum <= 2^16). `malformed` (optional) says which.
std::optional<uint32_t> sei_recovery_frame_cnt(std::span<const uint8_t> nal,
                                               bool* malformed = nullptr);

/// Scans every NAL unit of `au`.
H264AccessUnitInfo scan_h264_access_unit(std::span<const uint8_t> au, H264Framing framing);

/// Whether an RTP H.264 payload (RFC 6184: single NAL unit, STAP-A, FU-A) begins a picture: its
/// first NAL unit is an AUD, SPS, PPS or SEI (they precede a picture's slices, 7.4.1.2.3), or the
/// start of a slice with first_mb_in_slice 0 (the test rtph264depay makes too). The first packet
/// of a new RTP time after a gap that begins one shows the lost packets were not its own.
bool h264_payload_starts_picture(std::span<const uint8_t> payload);

}  // namespace hd::drivers

#pragma once
// Which H.264 encoder the remote site's send pipelines use: a hardware encoder when GStreamer
// offers one that works on this machine, else x264enc; chosen once at start and named.

#include <string>
#include <vector>

namespace hd::remote {

/// The GStreamer element names tried, hardware first (VA-API new and old, NVENC, Quick Sync),
/// then the software encoder every Debian GStreamer has (gst-plugins-ugly).
const std::vector<std::string>& h264_encoder_candidates();
inline constexpr const char* kSoftwareH264Encoder = "x264enc";

/// The encoder part of a send pipeline for `element` ("name=enc" and its low-latency settings:
/// no B-frames, a key frame every key_int_frames, constant bitrate; x264enc also tune=zerolatency,
/// speed-preset=ultrafast and a VBV of one frame) and the raw format it is given. intra_refresh:
/// x264enc intra-refresh=true (key_int_frames is then the refresh period); ignored by others.
std::string h264_encoder_description(const std::string& element, int bitrate_kbps,
                                     int key_int_frames, int vbv_buffer_ms,
                                     bool intra_refresh = false);
std::string h264_encoder_input_format(const std::string& element);  ///< "I420" or "NV12"

struct H264EncoderChoice {
  std::string element;  ///< what the pipelines use
  bool hardware = false;
  /// Why each candidate before it was not taken ("vah264enc: not installed; ..."), for the
  /// start report.
  std::string why_not_others;
};

/// `wanted`: "auto" (the first candidate that encodes two frames of a test picture with the
/// settings above within 5 s) or an element name (used if it works, else refused with why).
/// Throws std::runtime_error when nothing works (not even x264enc) or `wanted` does not.
H264EncoderChoice choose_h264_encoder(const std::string& wanted = "auto");

}  // namespace hd::remote

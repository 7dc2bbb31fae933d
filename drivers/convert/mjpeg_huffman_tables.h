#pragma once
// The standard Huffman tables (JPEG spec Annex K.3) that UVC MJPEG streams leave out.

#include <cstddef>
#include <cstdint>
#include <span>

namespace hd::drivers {

/// Where the markers of a JPEG stream lie, found without decoding it.
struct JpegLayout {
  bool valid = false;  ///< SOI, segment lengths that fit, an SOF with a nonzero size, then SOS
  bool has_huffman = false;    ///< a DHT segment precedes the first SOS
  std::size_t sos_offset = 0;  ///< offset of the 0xFF of the first SOS marker
  int width_px = 0;            ///< from the first SOF (frame header)
  int height_px = 0;
  const char* error = nullptr;  ///< why it is not valid (static string)
};

/// Walks the marker segments from SOI up to the first SOS.
JpegLayout scan_jpeg_layout(const uint8_t* jpeg, std::size_t len);

/// One DHT marker segment (0xFFC4, length, four tables: DC/AC luma, DC/AC chroma) holding the
/// standard tables; UVC cameras omit it to save bandwidth (the UVC MJPEG payload spec allows it).
std::span<const uint8_t> standard_dht_segment();

/// Copies `jpeg` to `out` with the standard DHT segment inserted before the first SOS, as libv4l
/// and ffmpeg do. Returns the bytes written, or 0 when `jpeg` is not valid or `out` is too small
/// (it needs len + standard_dht_segment().size()).
std::size_t insert_standard_huffman_tables(const uint8_t* jpeg, std::size_t len, uint8_t* out,
                                           std::size_t out_capacity);

}  // namespace hd::drivers

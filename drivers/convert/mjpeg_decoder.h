#pragma once
// MJPEG (V4L2_PIX_FMT_MJPEG) frames to the renderer's RGBA8, through libjpeg-turbo.

#include <cstddef>
#include <cstdint>
#include <vector>

namespace hd::drivers {

/// Decodes JPEG frames straight into an RGBA8 destination. The turbojpeg handle and the scratch
/// buffer for the Huffman-table fix-up are made once (constructor / reserve()), so decode() does
/// not allocate on our side (libjpeg's internal per-image pools are malloc'd by the library).
///
/// Frames without a DHT segment (UVC cameras omit the standard tables) get the standard tables
/// inserted first. Truncated or corrupt data is rejected (libjpeg warnings count as errors, so a
/// half-grey frame never reaches the screen). Not thread-safe: one decoder per capture thread.
class MjpegDecoder {
 public:
  /// `max_jpeg_bytes`: the largest compressed frame expected (V4L2's sizeimage); larger frames
  /// still decode but grow the scratch buffer once. Throws std::runtime_error if libturbojpeg
  /// cannot create a handle.
  explicit MjpegDecoder(std::size_t max_jpeg_bytes = 0);
  ~MjpegDecoder();
  MjpegDecoder(const MjpegDecoder&) = delete;
  MjpegDecoder& operator=(const MjpegDecoder&) = delete;

  /// Pre-sizes the scratch buffer for frames up to this many bytes.
  void reserve(std::size_t max_jpeg_bytes);

  /// Reads the image size from the header without decoding. False on bad input (see error()).
  bool read_size(const uint8_t* jpeg, std::size_t len, int& width_px, int& height_px);

  /// Decodes a JPEG whose size must be exactly width_px x height_px into `dst` (RGBA8, alpha 255).
  /// False on bad input, with the reason in error(); `dst` may then hold a partial image.
  bool decode_rgba(const uint8_t* jpeg, std::size_t len, int width_px, int height_px, uint8_t* dst,
                   std::size_t dst_len, int dst_stride_bytes);

  /// Why the last call failed (empty after success). Valid until the next call.
  const char* error() const { return error_; }

  /// Frames that needed the standard Huffman tables inserted.
  uint64_t tables_inserted() const { return tables_inserted_; }

 private:
  bool fail(const char* what, const char* detail);
  // Returns the stream to decode (the input, or scratch_ with tables inserted); null on error.
  const uint8_t* with_huffman_tables(const uint8_t* jpeg, std::size_t& len);

  void* handle_ = nullptr;  // tjhandle
  std::vector<uint8_t> scratch_;
  uint64_t tables_inserted_ = 0;
  char error_[256] = {};
};

}  // namespace hd::drivers

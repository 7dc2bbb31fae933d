#include "drivers/convert/mjpeg_decoder.h"

#include <turbojpeg.h>

#include <cstdio>
#include <stdexcept>

#include "drivers/convert/mjpeg_huffman_tables.h"

namespace hd::drivers {

MjpegDecoder::MjpegDecoder(std::size_t max_jpeg_bytes) : handle_(tjInitDecompress()) {
  if (handle_ == nullptr) {
    throw std::runtime_error(
        std::string("MJPEG decoder: libturbojpeg could not create a handle: ") +
        tjGetErrorStr2(nullptr));
  }
  reserve(max_jpeg_bytes);
}

MjpegDecoder::~MjpegDecoder() {
  if (handle_ != nullptr) tjDestroy(handle_);
}

void MjpegDecoder::reserve(std::size_t max_jpeg_bytes) {
  const std::size_t need = max_jpeg_bytes + standard_dht_segment().size();
  if (scratch_.size() < need) scratch_.resize(need);
}

bool MjpegDecoder::fail(const char* what, const char* detail) {
  std::snprintf(error_, sizeof(error_), "%s%s%s", what, detail[0] != '\0' ? ": " : "", detail);
  return false;
}

const uint8_t* MjpegDecoder::with_huffman_tables(const uint8_t* jpeg, std::size_t& len) {
  const JpegLayout layout = scan_jpeg_layout(jpeg, len);
  if (!layout.valid) {
    fail("corrupt JPEG", layout.error);
    return nullptr;
  }
  if (layout.has_huffman) return jpeg;
  reserve(len);  // allocates only for a frame larger than any before
  const std::size_t n = insert_standard_huffman_tables(jpeg, len, scratch_.data(), scratch_.size());
  if (n == 0) {
    fail("corrupt JPEG", "could not insert the standard Huffman tables");
    return nullptr;
  }
  ++tables_inserted_;
  len = n;
  return scratch_.data();
}

bool MjpegDecoder::read_size(const uint8_t* jpeg, std::size_t len, int& width_px, int& height_px) {
  error_[0] = '\0';
  const JpegLayout layout = scan_jpeg_layout(jpeg, len);
  if (!layout.valid) return fail("corrupt JPEG", layout.error);
  width_px = layout.width_px;
  height_px = layout.height_px;
  return true;
}

bool MjpegDecoder::decode_rgba(const uint8_t* jpeg, std::size_t len, int width_px, int height_px,
                               uint8_t* dst, std::size_t dst_len, int dst_stride_bytes) {
  error_[0] = '\0';
  if (jpeg == nullptr || dst == nullptr) return fail("MJPEG decode", "null buffer");
  if (width_px <= 0 || height_px <= 0 || dst_stride_bytes < width_px * 4) {
    return fail("MJPEG decode", "destination size or stride invalid");
  }
  const std::size_t need = static_cast<std::size_t>(height_px - 1) * dst_stride_bytes +
                           static_cast<std::size_t>(width_px) * 4;
  if (dst_len < need) return fail("MJPEG decode", "destination buffer too small");

  // The size comes from our own marker walk, not tjDecompressHeader3: in libjpeg-turbo 2.1 that
  // call does not reset the decompressor when the header is corrupt, and the stale state then
  // breaks the next, valid frame. tjDecompress2 aborts cleanly on every error.
  const JpegLayout layout = scan_jpeg_layout(jpeg, len);
  if (!layout.valid) return fail("corrupt JPEG", layout.error);
  const int w = layout.width_px;
  const int h = layout.height_px;
  if (w != width_px || h != height_px) {
    char detail[96];
    std::snprintf(detail, sizeof(detail), "frame is %dx%d, stream negotiated %dx%d", w, h, width_px,
                  height_px);
    return fail("MJPEG size mismatch", detail);
  }
  const uint8_t* stream = with_huffman_tables(jpeg, len);
  if (stream == nullptr) return false;
  // STOPONWARNING: a truncated frame is a libjpeg *warning* (it pads with grey); we drop it.
  // LIMITSCANS: a corrupt progressive stream cannot make us loop over thousands of scans.
  if (tjDecompress2(handle_, stream, static_cast<unsigned long>(len), dst, width_px,
                    dst_stride_bytes, height_px, TJPF_RGBA,
                    TJFLAG_STOPONWARNING | TJFLAG_LIMITSCANS) != 0) {
    return fail("corrupt JPEG data", tjGetErrorStr2(handle_));
  }
  return true;
}

}  // namespace hd::drivers

#include "drivers/gst/rgba_converter.h"

#include <cstddef>

namespace hd::drivers {

RgbaConverter::~RgbaConverter() {
  if (converter_ != nullptr) gst_video_converter_free(converter_);
}

// A GstVideoFrame over the Frame's memory, without a GstBuffer: the converter reads only a
// frame's info and plane pointers, and wrapping the memory in a buffer would allocate per frame.
// Rate and pixel aspect are the other side's: the converter changes neither (and refuses to).
bool RgbaConverter::describe(const Frame& f, const GstVideoInfo& other, GstVideoFrame& raw) {
  if (f.format != PixelFormat::kRgba8 || f.width <= 0 || f.height <= 0 ||
      f.stride_bytes < f.width * 4 ||
      f.data.size() < std::size_t(f.stride_bytes) * std::size_t(f.height))
    return false;
  raw = GstVideoFrame{};
  if (!gst_video_info_set_format(&raw.info, GST_VIDEO_FORMAT_RGBA, static_cast<guint>(f.width),
                                 static_cast<guint>(f.height)))
    return false;
  raw.info.fps_n = other.fps_n;
  raw.info.fps_d = other.fps_d;
  raw.info.par_n = other.par_n;
  raw.info.par_d = other.par_d;
  raw.info.stride[0] = f.stride_bytes;
  raw.info.size = std::size_t(f.stride_bytes) * std::size_t(f.height);
  raw.data[0] = const_cast<uint8_t*>(f.data.data());
  return true;
}

bool RgbaConverter::convert(const GstVideoFrame* in, GstVideoFrame* out) {
  if (GST_VIDEO_FRAME_WIDTH(in) != GST_VIDEO_FRAME_WIDTH(out) ||
      GST_VIDEO_FRAME_HEIGHT(in) != GST_VIDEO_FRAME_HEIGHT(out))
    return false;
  if (converter_ == nullptr || !gst_video_info_is_equal(&in->info, &in_) ||
      !gst_video_info_is_equal(&out->info, &out_)) {
    if (converter_ != nullptr) gst_video_converter_free(converter_);
    GstStructure* options = nullptr;
    if (threads_ > 1)
      options = gst_structure_new("options", GST_VIDEO_CONVERTER_OPT_THREADS, G_TYPE_UINT,
                                  static_cast<guint>(threads_), nullptr);
    converter_ = gst_video_converter_new(const_cast<GstVideoInfo*>(&in->info),
                                         const_cast<GstVideoInfo*>(&out->info), options);
    if (converter_ == nullptr) return false;
    in_ = in->info;
    out_ = out->info;
    ++built_;
  }
  gst_video_converter_frame(converter_, in, out);
  return true;
}

bool RgbaConverter::from_rgba(const Frame& f, GstVideoFrame* out) {
  GstVideoFrame raw;
  return describe(f, out->info, raw) && convert(&raw, out);
}

bool RgbaConverter::to_rgba(const GstVideoFrame* in, Frame& f) {
  GstVideoFrame raw;
  return describe(f, in->info, raw) && convert(in, &raw);
}

}  // namespace hd::drivers

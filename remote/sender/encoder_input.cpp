#include "remote/sender/encoder_input.h"

namespace hd::remote {

EncoderInput::~EncoderInput() {
  if (pool_ == nullptr) return;
  gst_buffer_pool_set_active(pool_, FALSE);
  gst_object_unref(pool_);
}

bool EncoderInput::configure(GstCaps* caps) {
  if (pool_ != nullptr || caps == nullptr || !gst_video_info_from_caps(&info_, caps)) return false;
  pool_ = gst_buffer_pool_new();
  GstStructure* config = gst_buffer_pool_get_config(pool_);
  gst_buffer_pool_config_set_params(config, caps, static_cast<guint>(GST_VIDEO_INFO_SIZE(&info_)),
                                    2, 0);
  if (!gst_buffer_pool_set_config(pool_, config) || !gst_buffer_pool_set_active(pool_, TRUE)) {
    gst_object_unref(pool_);
    pool_ = nullptr;
    return false;
  }
  return true;
}

GstBuffer* EncoderInput::convert(const drivers::Frame& f) {
  if (pool_ == nullptr || f.width != GST_VIDEO_INFO_WIDTH(&info_) ||
      f.height != GST_VIDEO_INFO_HEIGHT(&info_))
    return nullptr;
  GstBuffer* b = nullptr;
  if (gst_buffer_pool_acquire_buffer(pool_, &b, nullptr) != GST_FLOW_OK) return nullptr;
  GstVideoFrame out;
  bool ok = gst_video_frame_map(&out, &info_, b, GST_MAP_WRITE);
  if (ok) {
    ok = converter_.from_rgba(f, &out);
    gst_video_frame_unmap(&out);
  }
  if (!ok) {
    gst_buffer_unref(b);  // back to the pool
    return nullptr;
  }
  return b;
}

}  // namespace hd::remote

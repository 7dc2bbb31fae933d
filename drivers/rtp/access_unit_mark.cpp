// AccessUnitMark as a GstCustomMeta (GStreamer 1.20+): registered once, no tags (so decoders and
// converters copy it), copied by GStreamer's default custom transform.
#include "drivers/rtp/access_unit_mark.h"

namespace hd::drivers {
namespace {

constexpr const char* kMetaName = "HdAccessUnitMark";

const GstMetaInfo* meta_info() {
  static const GstMetaInfo* info = [] {
    static const gchar* tags[] = {nullptr};
    return gst_meta_register_custom(kMetaName, tags, nullptr, nullptr, nullptr);
  }();
  return info;
}

}  // namespace

void mark_access_unit(GstBuffer* buffer, const AccessUnitMark& mark) {
  meta_info();
  GstCustomMeta* meta = gst_buffer_get_custom_meta(buffer, kMetaName);
  if (meta == nullptr) meta = gst_buffer_add_custom_meta(buffer, kMetaName);
  if (meta == nullptr) return;
  gst_structure_set(gst_custom_meta_get_structure(meta), "pts", G_TYPE_UINT64,
                    static_cast<guint64>(mark.pts), "whole", G_TYPE_BOOLEAN, mark.whole, nullptr);
}

std::optional<AccessUnitMark> access_unit_mark(GstBuffer* buffer) {
  meta_info();
  GstCustomMeta* meta = gst_buffer_get_custom_meta(buffer, kMetaName);
  if (meta == nullptr) return std::nullopt;
  const GstStructure* s = gst_custom_meta_get_structure(meta);
  guint64 pts = 0;
  gboolean whole = FALSE;
  if (!gst_structure_get_uint64(s, "pts", &pts) || !gst_structure_get_boolean(s, "whole", &whole))
    return std::nullopt;
  return AccessUnitMark{pts, whole != FALSE};
}

}  // namespace hd::drivers

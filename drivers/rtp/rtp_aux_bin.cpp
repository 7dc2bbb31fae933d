#include "drivers/rtp/rtp_aux_bin.h"

namespace hd::drivers {

GstElement* make_rtp_aux_bin(const std::string& description, unsigned session) {
  GError* error = nullptr;
  GstElement* inner = gst_parse_bin_from_description(description.c_str(), TRUE, &error);
  if (inner == nullptr || error != nullptr) {
    g_clear_error(&error);
    if (inner != nullptr) gst_object_unref(inner);
    return nullptr;
  }
  // gst_parse_bin_from_description ghosts the pads as "sink" and "src"; rtpbin wants the
  // session's number in the names, so wrap it once more.
  GstElement* bin = gst_bin_new(nullptr);
  gst_bin_add(GST_BIN(bin), inner);
  const std::string n = std::to_string(session);
  for (const char* dir : {"sink", "src"}) {
    GstPad* target = gst_element_get_static_pad(inner, dir);
    if (target == nullptr) {
      gst_object_unref(gst_object_ref_sink(bin));
      return nullptr;
    }
    gst_element_add_pad(bin, gst_ghost_pad_new((std::string(dir) + "_" + n).c_str(), target));
    gst_object_unref(target);
  }
  return bin;
}

}  // namespace hd::drivers

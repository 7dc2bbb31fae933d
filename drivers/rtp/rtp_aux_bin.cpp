#include "drivers/rtp/rtp_aux_bin.h"

#include "drivers/gobject_ptr.h"
#include "drivers/gst/gst_ptr.h"

namespace hd::drivers {

GstElement* make_rtp_aux_bin(const std::string& description, unsigned session) {
  GErrorHolder error;
  GstElement* parsed = gst_parse_bin_from_description(description.c_str(), TRUE, error.out());
  const GstElementPtr inner(parsed != nullptr ? GST_ELEMENT(gst_object_ref_sink(parsed)) : nullptr);
  if (!inner || error) return nullptr;
  // gst_parse_bin_from_description ghosts the pads as "sink" and "src"; rtpbin wants the
  // session's number in the names, so wrap it once more.
  GstElementPtr bin(GST_ELEMENT(gst_object_ref_sink(gst_bin_new(nullptr))));
  gst_bin_add(GST_BIN(bin.get()), inner.get());  // the bin takes a reference of its own
  const std::string n = std::to_string(session);
  for (const char* dir : {"sink", "src"}) {
    const GstPadPtr target(gst_element_get_static_pad(inner.get(), dir));
    if (!target) return nullptr;
    gst_element_add_pad(bin.get(),
                        gst_ghost_pad_new((std::string(dir) + "_" + n).c_str(), target.get()));
  }
  // rtpbin's request-aux-receiver takes a floating reference (it adds the bin to itself).
  GstElement* out = bin.release();
  g_object_force_floating(G_OBJECT(out));
  return out;
}

}  // namespace hd::drivers

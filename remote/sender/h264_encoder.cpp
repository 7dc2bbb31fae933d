#include "remote/sender/h264_encoder.h"

#include <gst/gst.h>

#include <stdexcept>

#include "drivers/gobject_ptr.h"
#include "drivers/gst/bus_error.h"
#include "drivers/gst/gst_ptr.h"
#include "drivers/rtp/gstreamer_init.h"

namespace hd::remote {
namespace {

// Whether `element` with our settings encodes a short test clip here: installed is not enough
// (a VA-API plugin without a GPU, an NVENC plugin without the driver).
bool encodes(const std::string& element, std::string& why) {
  if (const drivers::GstObjectPtr<GstElementFactory> f{gst_element_factory_find(element.c_str())};
      !f) {
    why = "not installed";
    return false;
  }
  const std::string d =
      "videotestsrc num-buffers=2 ! video/x-raw,width=320,height=240,framerate=30/1 ! "
      "videoconvert ! video/x-raw,format=" +
      h264_encoder_input_format(element) + " ! " + h264_encoder_description(element, 1000, 30, 34) +
      " ! fakesink";
  drivers::GErrorHolder error;
  GstElement* parsed = gst_parse_launch(d.c_str(), error.out());
  const drivers::GstElementPtr p(parsed != nullptr ? GST_ELEMENT(gst_object_ref_sink(parsed))
                                                   : nullptr);
  if (!p || error) {
    why = std::string("refuses our settings: ") + (error ? error.message() : "unknown error");
    return false;
  }
  gst_element_set_state(p.get(), GST_STATE_PLAYING);
  const drivers::GstBusPtr bus(gst_element_get_bus(p.get()));
  const drivers::GstMessagePtr m(gst_bus_timed_pop_filtered(
      bus.get(), 5 * GST_SECOND, static_cast<GstMessageType>(GST_MESSAGE_EOS | GST_MESSAGE_ERROR)));
  bool ok = false;
  if (!m)
    why = "did not encode a test picture within 5 s";
  else if (const auto e = drivers::parse_bus_error(m.get()))
    why = "fails: " + e->text;
  else
    ok = true;
  gst_element_set_state(p.get(), GST_STATE_NULL);
  return ok;
}

}  // namespace

const std::vector<std::string>& h264_encoder_candidates() {
  static const std::vector<std::string> c{"vah264enc", "vaapih264enc", "nvh264enc", "qsvh264enc",
                                          kSoftwareH264Encoder};
  return c;
}

std::string h264_encoder_input_format(const std::string& element) {
  return element == kSoftwareH264Encoder ? "I420" : "NV12";
}

std::string h264_encoder_description(const std::string& element, int bitrate_kbps,
                                     int key_int_frames, int vbv_buffer_ms, bool intra_refresh) {
  const std::string rate = std::to_string(bitrate_kbps), gop = std::to_string(key_int_frames);
  if (element == "vah264enc")
    return "vah264enc name=enc rate-control=cbr bitrate=" + rate + " key-int-max=" + gop +
           " b-frames=0";
  if (element == "vaapih264enc")
    return "vaapih264enc name=enc rate-control=cbr bitrate=" + rate + " keyframe-period=" + gop +
           " max-bframes=0";
  if (element == "nvh264enc")
    return "nvh264enc name=enc rc-mode=cbr zerolatency=true bitrate=" + rate + " gop-size=" + gop +
           " bframes=0";
  if (element == "qsvh264enc")
    return "qsvh264enc name=enc rate-control=cbr low-latency=true bitrate=" + rate +
           " gop-size=" + gop + " b-frames=0";
  return std::string(kSoftwareH264Encoder) +
         " name=enc tune=zerolatency speed-preset=ultrafast bframes=0 key-int-max=" + gop +
         " vbv-buf-capacity=" + std::to_string(vbv_buffer_ms) + " bitrate=" + rate +
         (intra_refresh ? " intra-refresh=true" : "");
}

H264EncoderChoice choose_h264_encoder(const std::string& wanted) {
  drivers::ensure_gstreamer();
  H264EncoderChoice c;
  if (wanted != "auto") {
    std::string why;
    if (!encodes(wanted, why)) throw std::runtime_error("H.264 encoder " + wanted + ": " + why);
    c.element = wanted;
    c.hardware = wanted != kSoftwareH264Encoder;
    return c;
  }
  for (const std::string& e : h264_encoder_candidates()) {
    std::string why;
    if (encodes(e, why)) {
      c.element = e;
      c.hardware = e != kSoftwareH264Encoder;
      return c;
    }
    c.why_not_others += (c.why_not_others.empty() ? "" : "; ") + e + ": " + why;
  }
  throw std::runtime_error("no H.264 encoder works here (" + c.why_not_others + ")");
}

}  // namespace hd::remote

#include "drivers/rtp/srtp_elements.h"

namespace hd::drivers {

void set_srtp_encoder_key(GstElement* srtpenc, const SrtpKey& key) {
  GstBuffer* k = gst_buffer_new_memdup(key.bytes.data(), key.bytes.size());
  g_object_set(srtpenc, "key", k, nullptr);
  gst_buffer_unref(k);
}

namespace {

GstCaps* decoder_caps(GstElement*, guint, gpointer key_ptr) {
  const SrtpKey& key = *static_cast<const SrtpKey*>(key_ptr);
  GstBuffer* k = gst_buffer_new_memdup(key.bytes.data(), key.bytes.size());
  GstCaps* caps = gst_caps_new_simple("application/x-srtp", "srtp-key", GST_TYPE_BUFFER, k,
                                      "srtp-cipher", G_TYPE_STRING, "aes-128-gcm", "srtp-auth",
                                      G_TYPE_STRING, "null", "srtcp-cipher", G_TYPE_STRING,
                                      "aes-128-gcm", "srtcp-auth", G_TYPE_STRING, "null", nullptr);
  gst_buffer_unref(k);
  return caps;
}

}  // namespace

void answer_srtp_key_requests(GstElement* srtpdec, const SrtpKey& key) {
  g_signal_connect(srtpdec, "request-key", G_CALLBACK(&decoder_caps),
                   const_cast<SrtpKey*>(&key));  // only read back as const
}

}  // namespace hd::drivers

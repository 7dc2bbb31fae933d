#include "drivers/rtp/srtp_elements.h"

#include "drivers/gst/gst_ptr.h"

namespace hd::drivers {

void set_srtp_encoder_key(GstElement* srtpenc, const SrtpKey& key) {
  const GstBufferPtr k(gst_buffer_new_memdup(key.bytes.data(), key.bytes.size()));
  g_object_set(srtpenc, "key", k.get(), nullptr);  // takes its own reference
}

namespace {

GstCaps* decoder_caps(GstElement*, guint, gpointer key_ptr) {
  const SrtpKey& key = *static_cast<const SrtpKey*>(key_ptr);
  const GstBufferPtr k(gst_buffer_new_memdup(key.bytes.data(), key.bytes.size()));
  // The caps take their own reference to the key; srtpdec takes the caps.
  return gst_caps_new_simple("application/x-srtp", "srtp-key", GST_TYPE_BUFFER, k.get(),
                             "srtp-cipher", G_TYPE_STRING, "aes-128-gcm", "srtp-auth",
                             G_TYPE_STRING, "null", "srtcp-cipher", G_TYPE_STRING, "aes-128-gcm",
                             "srtcp-auth", G_TYPE_STRING, "null", nullptr);
}

}  // namespace

void answer_srtp_key_requests(GstElement* srtpdec, const SrtpKey& key) {
  g_signal_connect(srtpdec, "request-key", G_CALLBACK(&decoder_caps),
                   const_cast<SrtpKey*>(&key));  // only read back as const
}

}  // namespace hd::drivers

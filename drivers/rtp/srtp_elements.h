#pragma once
// How the key reaches GStreamer's SRTP elements, the same on both sites: srtpenc takes it as a
// property, srtpdec asks for it per SSRC in its "request-key" signal. AES-128-GCM with GCM's own
// authentication (no separate HMAC) for RTP and RTCP, as the key file's 28 bytes are cut for.
// The key's bytes go into GStreamer buffers only, never into a description or a message.

#include <gst/gst.h>

#include "drivers/rtp/srtp_key.h"

namespace hd::drivers {

/// The cipher properties of every srtpenc of ours, for a pipeline description.
inline constexpr const char* kSrtpEncoderCiphers =
    "rtp-cipher=aes-128-gcm rtp-auth=null rtcp-cipher=aes-128-gcm rtcp-auth=null";

/// Sets `key` on an srtpenc (before it runs).
void set_srtp_encoder_key(GstElement* srtpenc, const SrtpKey& key);

/// Answers an srtpdec's "request-key" for any SSRC with `key` (which must outlive the element):
/// one key for the stream's media, its retransmissions and both directions' RTCP. SRTP's IV
/// includes the SSRC, so two sources under one key never share a keystream (rtpbin renumbers a
/// colliding SSRC).
void answer_srtp_key_requests(GstElement* srtpdec, const SrtpKey& key);

}  // namespace hd::drivers

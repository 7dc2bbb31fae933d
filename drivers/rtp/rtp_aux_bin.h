#pragma once
// rtpbin's auxiliary elements (RTX sender/receiver, RFC 4588) built from a description string.

#include <gst/gst.h>

#include <string>

namespace hd::drivers {

/// A bin holding the elements of `description` (one chain, e.g. "rtprtxreceive …") with its
/// unlinked pads ghosted as sink_<session> and src_<session>, the names rtpbin links an aux
/// sender or receiver by. For rtpbin's request-aux-sender / request-aux-receiver handlers (which
/// hand rtpbin the floating reference). nullptr when the description does not parse.
GstElement* make_rtp_aux_bin(const std::string& description, unsigned session);

}  // namespace hd::drivers

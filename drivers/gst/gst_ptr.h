#pragma once
// Owning pointers for GStreamer's refcounted types (elements, pads, buses, messages, samples,
// buffers, caps), so that no code path forgets an unref: every gst_*_get_* that returns a reference
// is wrapped at once.

#include <gst/gst.h>

#include <memory>

namespace hd::drivers {

struct GstObjectUnref {
  void operator()(void* object) const {
    if (object != nullptr) gst_object_unref(object);
  }
};

/// GstObject subclasses (elements, pads, buses, clocks, element factories).
template <class T>
using GstObjectPtr = std::unique_ptr<T, GstObjectUnref>;
using GstElementPtr = GstObjectPtr<GstElement>;
using GstPadPtr = GstObjectPtr<GstPad>;
using GstBusPtr = GstObjectPtr<GstBus>;
using GstClockPtr = GstObjectPtr<GstClock>;

/// Mini objects: each has its own unref.
struct GstMessageUnref {
  void operator()(GstMessage* m) const {
    if (m != nullptr) gst_message_unref(m);
  }
};
struct GstSampleUnref {
  void operator()(GstSample* s) const {
    if (s != nullptr) gst_sample_unref(s);
  }
};
struct GstBufferUnref {
  void operator()(GstBuffer* b) const {
    if (b != nullptr) gst_buffer_unref(b);
  }
};
struct GstCapsUnref {
  void operator()(GstCaps* c) const {
    if (c != nullptr) gst_caps_unref(c);
  }
};
struct GstStructureFree {
  void operator()(GstStructure* s) const {
    if (s != nullptr) gst_structure_free(s);
  }
};
using GstMessagePtr = std::unique_ptr<GstMessage, GstMessageUnref>;
using GstSamplePtr = std::unique_ptr<GstSample, GstSampleUnref>;
using GstBufferPtr = std::unique_ptr<GstBuffer, GstBufferUnref>;
using GstCapsPtr = std::unique_ptr<GstCaps, GstCapsUnref>;
using GstStructurePtr = std::unique_ptr<GstStructure, GstStructureFree>;

/// A callback installed on a pad, removed when this is destroyed (or reset), and the reference
/// to the pad it needs for that. Remove probes only where no buffer can be in them any more
/// (the pipeline in NULL) or where the callback's data outlives the pad: gst_pad_remove_probe
/// does not wait for a callback running in a streaming thread.
class PadProbe {
 public:
  PadProbe() = default;
  /// Installs `callback` with `data` on `pad` (taking over the reference).
  PadProbe(GstPadPtr pad, GstPadProbeType type, GstPadProbeCallback callback, gpointer data)
      : pad_(std::move(pad)) {
    if (pad_) id_ = gst_pad_add_probe(pad_.get(), type, callback, data, nullptr);
  }
  ~PadProbe() { reset(); }
  PadProbe(PadProbe&& o) noexcept : pad_(std::move(o.pad_)), id_(o.id_) { o.id_ = 0; }
  PadProbe& operator=(PadProbe&& o) noexcept {
    if (this != &o) {
      reset();
      pad_ = std::move(o.pad_);
      id_ = o.id_;
      o.id_ = 0;
    }
    return *this;
  }
  PadProbe(const PadProbe&) = delete;
  PadProbe& operator=(const PadProbe&) = delete;

  /// Whether the probe is installed (gst_pad_add_probe returns 0 when it was not).
  bool installed() const { return id_ != 0; }
  GstPad* pad() const { return pad_.get(); }
  void reset() {
    if (pad_ && id_ != 0) gst_pad_remove_probe(pad_.get(), id_);
    id_ = 0;
    pad_.reset();
  }

 private:
  GstPadPtr pad_;
  gulong id_ = 0;
};

}  // namespace hd::drivers

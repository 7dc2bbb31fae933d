#pragma once
// Owning pointers for GLib things: GObject instances (Aravis cameras and streams, GStreamer's
// sockets and sessions), GError and g_malloc'd strings. GStreamer's own refcounted types have
// theirs in drivers/gst/gst_ptr.h.

#include <glib-object.h>

#include <memory>

namespace hd::drivers {

struct GObjectUnref {
  void operator()(void* object) const {
    if (object != nullptr) g_object_unref(object);
  }
};

template <class T>
using GObjectPtr = std::unique_ptr<T, GObjectUnref>;

struct GFree {
  void operator()(void* memory) const { g_free(memory); }
};

/// A string GLib allocated (g_inet_address_to_string, gst_object_get_name, ...).
using GCharPtr = std::unique_ptr<gchar, GFree>;

/// Owns a GError; `out()` hands its address to a GLib call.
class GErrorHolder {
 public:
  GErrorHolder() = default;
  ~GErrorHolder() { clear(); }
  GErrorHolder(const GErrorHolder&) = delete;
  GErrorHolder& operator=(const GErrorHolder&) = delete;
  GError** out() {
    clear();
    return &error_;
  }
  explicit operator bool() const { return error_ != nullptr; }
  const char* message() const { return error_ != nullptr ? error_->message : ""; }
  void clear() { g_clear_error(&error_); }

 private:
  GError* error_ = nullptr;
};

}  // namespace hd::drivers

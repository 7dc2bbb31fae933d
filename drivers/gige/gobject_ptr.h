#pragma once
// Owning pointer for GObject instances (Aravis cameras, streams, devices, buffers).

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

#pragma once
// A GStreamer pipeline built from a gst_parse_launch description and kept running: checked element
// lookup, pad probes that go with the pipeline, and a bus thread that rebuilds it after an error.

#include <gst/gst.h>

#include <atomic>
#include <cstdint>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "drivers/gst/gst_ptr.h"

namespace hd::drivers {

/// Owns one pipeline at a time. The pipeline runs on CLOCK_MONOTONIC (a system clock of that
/// type), the station's one clock, so buffer times plus base_time() are monotonic_now_ns() times.
///
/// Threads: build(), teardown(), play() and the probes' lifetime belong to one thread at a time:
/// the caller's until start(), the bus thread until stop() returns. find() and built() may be
/// called from any thread (the pipeline is swapped under a mutex, and a found element is a
/// reference of its own, so a concurrent teardown cannot free it); raw() is for callbacks in the
/// pipeline's own streaming threads, which run only while it is built.
class PipelineRunner {
 public:
  struct Settings {
    std::string owner;              ///< who runs it, for errors: "camera rtp://1.2.3.4:5000"
    std::string what = "pipeline";  ///< what it is, for errors: "receive pipeline"
    std::string description;        ///< for gst_parse_launch
    int64_t restart_delay_ns = 500'000'000;  ///< after an error, before the next build
    int64_t bus_poll_ns = 100'000'000;       ///< the longest between two on_turn calls
  };
  struct Hooks {
    /// After the parse, before PLAYING: connects signals, links request pads, installs probes
    /// (probe()). A DeviceError tears the pipeline down and fails the build.
    std::function<void(PipelineRunner&)> wire;
    /// Bus thread: an error (BusError::to_string()) or "end of stream", before the teardown.
    std::function<void(const std::string& text)> on_error;
    /// Bus thread: every turn while the pipeline is built (at least every bus_poll_ns).
    std::function<void()> on_turn;
  };

  PipelineRunner(Settings settings, Hooks hooks);
  ~PipelineRunner();  ///< stop(), teardown()
  PipelineRunner(const PipelineRunner&) = delete;
  PipelineRunner& operator=(const PipelineRunner&) = delete;

  /// Parses and wires the pipeline (nothing when built). Throws DeviceError "owner: cannot build
  /// the <what>: <GStreamer's reason>" or the wiring's.
  void build();
  /// To NULL, probes removed, pipeline released (nothing when not built).
  void teardown();
  /// build() and PLAYING. False (torn down, `why` the bus's newest error or "") when it refused.
  bool play(std::string& why);
  /// Starts the bus thread (after a play() that succeeded): errors are counted, reported through
  /// on_error and the pipeline rebuilt restart_delay_ns later, again until it plays.
  void start();
  /// Joins the bus thread; the pipeline goes to NULL but stays built (play() resumes it).
  void stop();
  bool running() const { return running_.load(std::memory_order_relaxed); }

  bool built() const;
  /// The element named `name`; throws DeviceError "owner: the <what> has no element NAME" when
  /// there is none (or nothing is built).
  GstElementPtr element(const char* name) const;
  /// The element named `name`, or null when there is none or nothing is built (any thread).
  GstElementPtr find(const char* name) const;
  /// Installs `callback` on element `element`'s static pad `pad` until the teardown. Throws
  /// DeviceError naming the element or "element.pad" when either is missing.
  void probe(const char* element, const char* pad, GstPadProbeCallback callback, gpointer data,
             GstPadProbeType type = GST_PAD_PROBE_TYPE_BUFFER);
  /// The pipeline (null when not built), borrowed: for its streaming threads' callbacks.
  GstElement* raw() const { return raw_.load(std::memory_order_acquire); }
  /// The pipeline's base time (ns on its clock; 0 when not built or not yet playing): a buffer
  /// time t ran at t + base_time() on CLOCK_MONOTONIC. For streaming-thread callbacks.
  GstClockTime base_time() const;

  /// Bus errors and ends of stream seen / rebuilds that reached PLAYING, since construction.
  uint64_t errors() const { return errors_.load(std::memory_order_relaxed); }
  uint64_t restarts() const { return restarts_.load(std::memory_order_relaxed); }
  /// The newest on_error text ("" none).
  std::string last_error() const;
  const Settings& settings() const { return settings_; }

 private:
  void bus_loop();
  std::string pending_error() const;

  Settings settings_;
  Hooks hooks_;
  mutable std::mutex mutex_;  // guards pipeline_ against find() from other threads
  GstElementPtr pipeline_;
  std::atomic<GstElement*> raw_{nullptr};
  std::vector<PadProbe> probes_;  // the building thread's; cleared after NULL, before release
  std::thread bus_thread_;
  std::atomic<bool> running_{false};
  std::atomic<uint64_t> errors_{0}, restarts_{0};
  mutable std::mutex error_mutex_;
  std::string last_error_;
};

}  // namespace hd::drivers

// PipelineRunner: the pipeline's life (build, wiring, play, teardown) and its bus thread.
#include "drivers/gst/pipeline_runner.h"

#include <chrono>

#include "drivers/camera_source.h"
#include "drivers/clock/monotonic_clock.h"
#include "drivers/gobject_ptr.h"
#include "drivers/gst/bus_error.h"

namespace hd::drivers {

PipelineRunner::PipelineRunner(Settings settings, Hooks hooks)
    : settings_(std::move(settings)), hooks_(std::move(hooks)) {}

PipelineRunner::~PipelineRunner() {
  stop();
  teardown();
}

bool PipelineRunner::built() const {
  std::lock_guard lock(mutex_);
  return pipeline_ != nullptr;
}

void PipelineRunner::build() {
  if (built()) return;
  GErrorHolder error;
  GstElement* parsed = gst_parse_launch(settings_.description.c_str(), error.out());
  // gst_parse_launch hands out a floating reference: sunk, so that the pointer below owns it.
  GstElementPtr p(parsed != nullptr ? GST_ELEMENT(gst_object_ref_sink(parsed)) : nullptr);
  if (!p || error) {
    throw DeviceError(settings_.owner + ": cannot build the " + settings_.what + ": " +
                      (error ? error.message() : "unknown error"));
  }
  if (GST_IS_PIPELINE(p.get())) {
    // Buffer times are read on this clock: CLOCK_MONOTONIC, the station's one clock.
    GstClockPtr clock(GST_CLOCK(
        g_object_new(GST_TYPE_SYSTEM_CLOCK, "clock-type", GST_CLOCK_TYPE_MONOTONIC, nullptr)));
    gst_pipeline_use_clock(GST_PIPELINE(p.get()), clock.get());
  }
  {
    std::lock_guard lock(mutex_);
    raw_.store(p.get(), std::memory_order_release);
    pipeline_ = std::move(p);
  }
  if (!hooks_.wire) return;
  try {
    hooks_.wire(*this);
  } catch (...) {
    teardown();
    throw;
  }
}

void PipelineRunner::teardown() {
  GstElementPtr p;
  {
    std::lock_guard lock(mutex_);
    p = std::move(pipeline_);
    raw_.store(nullptr, std::memory_order_release);
  }
  if (p) gst_element_set_state(p.get(), GST_STATE_NULL);  // joins the streaming threads
  probes_.clear();                                        // no buffer can be in a probe any more
}

bool PipelineRunner::play(std::string& why) {
  build();
  why.clear();
  if (gst_element_set_state(raw(), GST_STATE_PLAYING) != GST_STATE_CHANGE_FAILURE) return true;
  why = pending_error();
  teardown();
  return false;
}

void PipelineRunner::start() {
  if (running_.exchange(true)) return;
  bus_thread_ = std::thread([this] { bus_loop(); });
}

void PipelineRunner::stop() {
  if (!running_.exchange(false)) return;
  if (bus_thread_.joinable()) bus_thread_.join();
  if (GstElement* p = raw()) gst_element_set_state(p, GST_STATE_NULL);
}

// The mutex only guards taking a reference: the lookup takes every element's object lock in
// turn, and a streaming thread that holds a GStreamer lock may call find() too (a pad probe).
// Looked up under the mutex, a caller waiting for an element's lock held the mutex against it:
// the network camera's stats() and the jitter buffer's timer thread (its NACK probe) deadlocked
// so, with the CPUs busy.
GstElementPtr PipelineRunner::find(const char* name) const {
  GstElementPtr pipeline;
  {
    std::lock_guard lock(mutex_);
    if (!pipeline_ || !GST_IS_BIN(pipeline_.get())) return nullptr;
    pipeline.reset(GST_ELEMENT(gst_object_ref(pipeline_.get())));
  }
  return GstElementPtr(gst_bin_get_by_name(GST_BIN(pipeline.get()), name));
}

GstElementPtr PipelineRunner::element(const char* name) const {
  GstElementPtr e = find(name);
  if (!e)
    throw DeviceError(settings_.owner + ": the " + settings_.what + " has no element " + name);
  return e;
}

void PipelineRunner::probe(const char* element_name, const char* pad_name,
                           GstPadProbeCallback callback, gpointer data, GstPadProbeType type) {
  const GstElementPtr e = element(element_name);
  GstPadPtr pad(gst_element_get_static_pad(e.get(), pad_name));
  if (!pad) {
    throw DeviceError(settings_.owner + ": the " + settings_.what + " has no pad " + element_name +
                      "." + pad_name);
  }
  probes_.emplace_back(std::move(pad), type, callback, data);
}

GstClockTime PipelineRunner::base_time() const {
  GstElement* p = raw();
  return p != nullptr ? gst_element_get_base_time(p) : 0;
}

std::string PipelineRunner::last_error() const {
  std::lock_guard lock(error_mutex_);
  return last_error_;
}

std::string PipelineRunner::pending_error() const {
  GstElement* p = raw();
  if (p == nullptr) return "";
  GstBusPtr bus(gst_element_get_bus(p));
  std::string text;
  while (GstMessagePtr m{gst_bus_pop_filtered(bus.get(), GST_MESSAGE_ERROR)})
    if (const auto e = parse_bus_error(m.get())) text = e->text;
  return text;
}

void PipelineRunner::bus_loop() {
  int64_t restart_at_ns = 0;
  while (running_.load(std::memory_order_relaxed)) {
    const int64_t now = monotonic_now_ns();
    GstElement* p = raw();  // this thread is the only one that builds or tears down now
    if (p == nullptr) {
      if (now >= restart_at_ns) {
        try {
          std::string why;
          if (play(why))
            restarts_.fetch_add(1, std::memory_order_relaxed);
          else
            restart_at_ns = now + settings_.restart_delay_ns;
        } catch (const DeviceError&) {
          restart_at_ns = now + settings_.restart_delay_ns;
        }
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(50));  // waiting to retry, not a sync
      continue;
    }
    const GstBusPtr bus(gst_element_get_bus(p));
    const GstMessagePtr m(gst_bus_timed_pop_filtered(
        bus.get(), GstClockTime(settings_.bus_poll_ns),
        static_cast<GstMessageType>(GST_MESSAGE_ERROR | GST_MESSAGE_EOS)));
    if (m) {
      const auto error = parse_bus_error(m.get());
      const std::string text = error ? error->to_string() : "end of stream";
      errors_.fetch_add(1, std::memory_order_relaxed);
      {
        std::lock_guard lock(error_mutex_);
        last_error_ = text;
      }
      if (hooks_.on_error) hooks_.on_error(text);
      teardown();
      restart_at_ns = monotonic_now_ns() + settings_.restart_delay_ns;
      continue;
    }
    if (hooks_.on_turn) hooks_.on_turn();
  }
}

}  // namespace hd::drivers

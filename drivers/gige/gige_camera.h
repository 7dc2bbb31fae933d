#pragma once
// A GigE Vision camera through Aravis 0.8, as a CameraSource.

#include <arv.h>

#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "drivers/camera_source.h"
#include "drivers/clock/device_clock_mapper.h"
#include "drivers/format_watch.h"
#include "drivers/gige/frame_accounting.h"
#include "drivers/gige/gige_config.h"
#include "drivers/gige/gige_feature_setup.h"
#include "drivers/gige/gige_stats.h"
#include "drivers/gige/stream_watchdog.h"
#include "drivers/gobject_ptr.h"
#include "drivers/spsc_ring.h"

namespace hd::drivers {

class GvcpLivenessProbe;

/// Streams one GigE camera: open() negotiates region, pixel format, frame rate and packet size
/// and sizes the mailbox; start() starts acquisition and a thread that pops Aravis buffers,
/// converts them to RGBA8 into the mailbox and hands the buffer straight back to Aravis.
///
/// Format: binning, then the region, are set only where the camera's own limits (Width/Height
/// bounds and increments, with Aravis's range check on) allow them, and every value is read back;
/// negotiate() returns that answer (what was refused, and the camera's limits), open() throws
/// when a configured region was not delivered. The negotiated size and pixel format are fixed
/// for the run: a frame of another one, or a reconnect that cannot restore it, makes the state
/// kFormatMismatch (with a FormatEvent) and publishes nothing; every 0.5 s the camera is released
/// and opened again with the configuration until it delivers the negotiated format.
///
/// Time: the arrival stamp is the buffer's system timestamp (taken by Aravis when the leader
/// packet landed) moved onto CLOCK_MONOTONIC; the device timestamp is mapped onto it with a
/// DeviceClockMapper, and the frame's host time is that mapped exposure time.
///
/// Liveness: no frame for `stall_timeout_ns` makes the state kStalled and sends a GVCP probe;
/// a refused or unanswered probe, or Aravis's "control-lost" signal, makes it kDisconnected.
/// A disconnected camera is probed every 0.5 s and reopened (same configuration, same mailbox)
/// when it answers; frame sequence numbers continue from the last frame before the loss.
class GigeCamera final : public CameraSource {
 public:
  explicit GigeCamera(GigeConfig config);
  ~GigeCamera() override;
  GigeCamera(const GigeCamera&) = delete;
  GigeCamera& operator=(const GigeCamera&) = delete;

  std::string id() const override { return config_.device_id; }
  void open() override;  ///< throws DeviceError, also when a configured region is not delivered
  /// The request's size (keeping the camera's offsets, see GigeRoi), first pixel format we can
  /// convert and rate replace the configuration's; the camera's answer is returned. Before
  /// start() only (throws DeviceError otherwise).
  FormatNegotiation negotiate(const CameraFormatRequest& wanted) override;
  CameraFormat format() const override { return format_; }
  bool pop_format_event(FormatEvent& out) override { return format_watch_.pop(out); }
  void start() override;
  void stop() override;
  SourceState state() const override { return state_.load(std::memory_order_acquire); }
  uint64_t dropped_frames() const override;
  /// Valid after open(); open() replaces it with one sized for the negotiated image.
  Mailbox<Frame>& frames() override { return *mailbox_; }

  GigeStats stats() const;
  /// Oldest unread hand-off timing (bounded queue; overflow is counted and dropped).
  bool pop_timing(GigeHandoffTiming& out) { return timings_.pop(out); }

  // What open() negotiated (the camera's answers, read back).
  int width_px() const { return width_px_; }
  int height_px() const { return height_px_; }
  double frame_rate_hz() const { return frame_rate_hz_; }
  int packet_size_bytes() const { return packet_size_bytes_; }
  int socket_buffer_bytes() const { return socket_buffer_bytes_; }
  std::size_t payload_bytes() const { return payload_bytes_; }
  int buffer_count() const { return buffer_count_; }
  const std::string& address() const { return address_; }
  int binning_x() const { return binning_x_; }  ///< read back; 1 when the camera has no binning
  int binning_y() const { return binning_y_; }
  int offset_x_px() const { return offset_x_px_; }
  int offset_y_px() const { return offset_y_px_; }

 private:
  // camera_ opened and configured (configure_gige_features()), what it delivers read back.
  GigeFeatureAnswer open_device();
  void open_stream();  // packet size, payload, stream and buffers for camera_
  void close();
  void retire();
  void adopt(const CameraFormat& f);  // sizes, stream and mailbox for what open_device() found
  void release_live();
  bool reconnect();
  void enter_mismatch(FormatEventCause cause, const CameraFormat& seen, int64_t now_ns);
  void leave_mismatch(FormatEventCause cause, int64_t now_ns);
  void stream_loop();
  void handle_buffer(ArvBuffer* buffer, int64_t popped_ns);
  void look_after_camera(int64_t now_ns, GvcpLivenessProbe& probe);
  static void on_control_lost(ArvDevice* device, gpointer self);

  GigeConfig config_;
  GObjectPtr<ArvCamera> camera_;
  GObjectPtr<ArvStream> stream_;
  std::vector<GObjectPtr<ArvStream>> retired_streams_;
  std::vector<GObjectPtr<ArvCamera>> retired_cameras_;
  gulong control_lost_handler_ = 0;
  std::unique_ptr<Mailbox<Frame>> mailbox_;
  std::string address_;

  int width_px_ = 0;
  int height_px_ = 0;
  double frame_rate_hz_ = 0.0;
  int packet_size_bytes_ = 0;
  int socket_buffer_bytes_ = 0;
  std::size_t payload_bytes_ = 0;
  int buffer_count_ = 0;
  ArvPixelFormat arv_format_ = 0;
  PixelFormat pixel_format_ = PixelFormat::kMono8;  // the one set (of the acceptable ones)
  std::vector<PixelFormat> acceptable_formats_;     // empty: config_.pixel_format
  int binning_x_ = 1, binning_y_ = 1;
  int offset_x_px_ = 0, offset_y_px_ = 0;
  CameraFormat format_;  // negotiated at open; the mailbox is sized for it

  std::thread thread_;
  std::atomic<bool> running_{false};
  std::atomic<bool> control_lost_{false};
  std::atomic<SourceState> state_{SourceState::kClosed};

  GigeCounters counters_;  // the stream thread adds, stats() reads from any thread
  // Owned by the stream thread while it runs (start() resets them before it starts it).
  FrameAccounting accounting_{counters_};
  StreamWatchdog watchdog_;
  DeviceClockMapper clock_mapper_;
  SpscRing<GigeHandoffTiming, 1024> timings_;
  FormatWatch format_watch_;  // capture thread; the station pops its events
};

}  // namespace hd::drivers

// GigeCamera: one GigE Vision camera's lifecycle (open, negotiate, stream, reconnect) on Aravis.
#include "drivers/gige/gige_camera.h"

#include <time.h>

#include <algorithm>
#include <string_view>
#include <thread>

#include "drivers/clock/monotonic_clock.h"
#include "drivers/convert/bayer_to_rgba.h"
#include "drivers/convert/mono8_to_rgba.h"
#include "drivers/convert/rgb8_to_rgba.h"
#include "drivers/gige/arv_pixel_format.h"
#include "drivers/gige/gige_prober.h"
#include "drivers/gige/gvcp_liveness_probe.h"
#include "drivers/gige/stream_sizing.h"

namespace hd::drivers {

namespace {

constexpr int64_t kPopTimeoutUs = 20'000;  // bounds how late stop() and stall checks react
constexpr int64_t kReconnectPeriodNs = 500'000'000;  // how often a lost camera is looked for

// Aravis reports device timestamps already scaled to ns on a 64-bit counter.
DeviceClockMapper new_clock_mapper() {
  return DeviceClockMapper(DeviceClockMapperConfig{64, 1.0, 200.0, 100'000'000});
}

int64_t clock_ns(clockid_t id) {
  timespec ts{};
  clock_gettime(id, &ts);
  return static_cast<int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

std::string ipv4_of(ArvCamera* camera) {
  ArvDevice* device = arv_camera_get_device(camera);
  if (device == nullptr || !ARV_IS_GV_DEVICE(device)) return {};
  GSocketAddress* socket_address = arv_gv_device_get_device_address(ARV_GV_DEVICE(device));
  if (socket_address == nullptr || !G_IS_INET_SOCKET_ADDRESS(socket_address)) return {};
  GInetAddress* inet =
      g_inet_socket_address_get_address(G_INET_SOCKET_ADDRESS(socket_address));  // transfer none
  gchar* text = g_inet_address_to_string(inet);
  std::string out = text != nullptr ? text : "";
  g_free(text);
  return out;
}

}  // namespace

GigeCamera::GigeCamera(GigeConfig config)
    : config_(std::move(config)),
      mailbox_(std::make_unique<Mailbox<Frame>>()),
      watchdog_(StreamWatchdog::Config{config_.stall_timeout_ns, kReconnectPeriodNs}),
      clock_mapper_(new_clock_mapper()) {}

GigeCamera::~GigeCamera() {
  stop();
  close();
}

GigeFeatureAnswer GigeCamera::open_device() {
  const std::string& id = config_.device_id;
  // Once negotiated, a reopen asks for that format only: the mailbox and the converter are set
  // up for it.
  const std::vector<PixelFormat> candidates =
      format_.known()               ? std::vector<PixelFormat>{format_.pixel_format}
      : acceptable_formats_.empty() ? std::vector<PixelFormat>{config_.pixel_format}
                                    : acceptable_formats_;
  if (std::none_of(candidates.begin(), candidates.end(), gige_converts)) {
    throw DeviceError("GigE camera '" + id + "': pixel format " +
                      std::string(to_string(candidates.front())) +
                      " is not supported (expected Mono8, RGB8, BayerRG8/GR8/GB8/BG8)");
  }
  if (config_.buffer_count < 0 || config_.buffer_count == 1) {
    throw DeviceError("GigE camera '" + id + "': buffer_count must be 0 (auto) or >= 2, got " +
                      std::to_string(config_.buffer_count));
  }
  GErrorHolder error;
  camera_.reset(arv_camera_new(id.c_str(), error.out()));
  if (!camera_ || error) {
    const std::string why = error ? error.message() : "no such device";
    camera_.reset();
    std::string found;
    for (const DeviceInfo& d : probe_gige_devices()) found += (found.empty() ? "" : ", ") + d.id;
    throw DeviceError("GigE camera '" + id + "' could not be opened: " + why +
                      "; GigE devices found: " + (found.empty() ? "none" : found));
  }
  if (!arv_camera_is_gv_device(camera_.get())) {
    camera_.reset();
    throw DeviceError("device '" + id + "' is not a GigE Vision camera");
  }
  // Aravis writes out-of-range values by default; a camera that silently clamps or ignores them
  // would then deliver something else than asked. With the check on, Aravis refuses them.
  arv_camera_set_range_check_policy(camera_.get(), ARV_RANGE_CHECK_POLICY_ENABLE);
  address_ = ipv4_of(camera_.get());
  GigeFeatureAnswer a;
  try {
    a = configure_gige_features(camera_.get(), config_, candidates);
  } catch (const DeviceError&) {
    camera_.reset();
    throw;
  }
  arv_format_ = a.arv_format;
  pixel_format_ = a.format.pixel_format;
  binning_x_ = a.binning_x;
  binning_y_ = a.binning_y;
  offset_x_px_ = a.offset_x_px;
  offset_y_px_ = a.offset_y_px;
  return a;
}

void GigeCamera::open_stream() {
  const std::string& id = config_.device_id;
  GErrorHolder error;
  const auto fail = [&](std::string_view what) {
    std::string msg = "GigE camera '" + id + "': " + std::string(what) + ": " + error.message();
    camera_.reset();
    throw DeviceError(msg);
  };
  ArvCamera* cam = camera_.get();
  if (config_.packet_size_bytes > 0) {
    arv_camera_gv_set_packet_size(cam, config_.packet_size_bytes, error.out());
    if (error) fail("setting packet size " + std::to_string(config_.packet_size_bytes));
  } else {
    arv_camera_gv_auto_packet_size(cam, error.out());
    if (error) fail("negotiating packet size");
  }
  packet_size_bytes_ = static_cast<int>(arv_camera_gv_get_packet_size(cam, error.out()));
  if (error) fail("reading packet size");
  payload_bytes_ = arv_camera_get_payload(cam, error.out());
  if (error) fail("reading payload size");
  const int w = width_px_, h = height_px_;
  const std::size_t needed = static_cast<std::size_t>(w) * static_cast<std::size_t>(h) *
                             static_cast<std::size_t>(bytes_per_pixel(pixel_format_));
  if (payload_bytes_ < needed) {
    camera_.reset();
    throw DeviceError("GigE camera '" + id + "': payload " + std::to_string(payload_bytes_) +
                      " bytes is smaller than a " + std::to_string(w) + "x" + std::to_string(h) +
                      " " + std::string(to_string(pixel_format_)) + " image");
  }

  const bool loopback = address_.rfind("127.", 0) == 0;
  arv_camera_gv_set_stream_options(cam, (!config_.allow_packet_socket || loopback)
                                            ? ARV_GV_STREAM_OPTION_PACKET_SOCKET_DISABLED
                                            : ARV_GV_STREAM_OPTION_NONE);
  stream_.reset(arv_camera_create_stream(cam, nullptr, nullptr, error.out()));
  if (!stream_ || error) {
    stream_.reset();
    fail("creating the stream");
  }
  const double rate = frame_rate_hz_ > 0.0 ? frame_rate_hz_ : 60.0;
  socket_buffer_bytes_ = socket_buffer_bytes_for(config_.socket_buffer_bytes, payload_bytes_, rate);
  g_object_set(stream_.get(), "socket-buffer", ARV_GV_STREAM_SOCKET_BUFFER_FIXED,
               "socket-buffer-size", socket_buffer_bytes_, "packet-resend",
               ARV_GV_STREAM_PACKET_RESEND_ALWAYS, "frame-retention",
               static_cast<guint>(frame_retention_us_for(config_.frame_retention_ns)), nullptr);
  buffer_count_ = buffer_count_for(config_.buffer_count, rate, config_.frame_retention_ns);
  for (int i = 0; i < buffer_count_; ++i) {
    arv_stream_push_buffer(stream_.get(), arv_buffer_new(payload_bytes_, nullptr));
  }
  control_lost_.store(false);
  control_lost_handler_ = g_signal_connect(arv_camera_get_device(cam), "control-lost",
                                           G_CALLBACK(&GigeCamera::on_control_lost), this);
}

void GigeCamera::open() {
  if (camera_) return;
  const GigeFeatureAnswer a = open_device();
  const GigeRoi& roi = config_.roi;
  if (roi.width_px > 0 && roi.height_px > 0 &&
      (a.format.width_px != roi.width_px || a.format.height_px != roi.height_px)) {
    camera_.reset();
    throw DeviceError("GigE camera '" + config_.device_id + "' delivers " +
                      size_text(a.format.width_px, a.format.height_px) + ", not the configured " +
                      size_text(roi.width_px, roi.height_px) +
                      (a.refused.empty() ? "" : " (" + a.refused + ")"));
  }
  adopt(a.format);
}

FormatNegotiation GigeCamera::negotiate(const CameraFormatRequest& wanted) {
  if (running_.load()) {
    throw DeviceError("GigE camera '" + config_.device_id + "': negotiate() while streaming");
  }
  if (wanted.width_px > 0 && wanted.height_px > 0) {
    config_.roi = {-1, -1, wanted.width_px, wanted.height_px};
  }
  acceptable_formats_.clear();
  for (PixelFormat f : wanted.pixel_formats) {
    if (gige_converts(f)) acceptable_formats_.push_back(f);
  }
  if (!wanted.pixel_formats.empty() && acceptable_formats_.empty()) {
    std::string asked;
    for (PixelFormat f : wanted.pixel_formats) asked += " " + std::string(to_string(f));
    throw DeviceError("GigE camera '" + config_.device_id + "': none of the pixel formats" + asked +
                      " is one this driver converts (Mono8, RGB8, BayerRG8/GR8/GB8/BG8)");
  }
  if (wanted.frame_rate_hz > 0.0) config_.frame_rate_hz = wanted.frame_rate_hz;
  close();  // opened before: release it, the request replaces its configuration
  format_ = CameraFormat{};
  const GigeFeatureAnswer a = open_device();
  adopt(a.format);
  return {a.format, a.refused, a.limits, a.detail};
}

void GigeCamera::adopt(const CameraFormat& f) {
  width_px_ = f.width_px;
  height_px_ = f.height_px;
  frame_rate_hz_ = f.frame_rate_hz;
  format_ = f;
  format_watch_.forget();
  open_stream();
  // Sized here, before start(): the consumer takes frames() after open, and it never changes
  // while the camera streams (a reconnect must deliver this size again).
  if (mailbox_->write_slot().width != width_px_ || mailbox_->write_slot().height != height_px_) {
    Frame prototype;
    prototype.allocate_rgba(width_px_, height_px_);
    mailbox_ = std::make_unique<Mailbox<Frame>>(prototype);
  }
  state_.store(SourceState::kClosed, std::memory_order_release);
}

void GigeCamera::on_control_lost(ArvDevice*, gpointer self) {
  // Called on Aravis's heartbeat thread: only flag it, the stream thread acts.
  static_cast<GigeCamera*>(self)->control_lost_.store(true, std::memory_order_release);
}

void GigeCamera::start() {
  if (!camera_) open();
  if (running_.load()) return;
  GErrorHolder error;
  accounting_.start();
  arv_camera_start_acquisition(camera_.get(), error.out());
  if (error) {
    throw DeviceError("GigE camera '" + config_.device_id +
                      "': starting acquisition: " + error.message());
  }
  watchdog_.restart(monotonic_now_ns());
  state_.store(SourceState::kStreaming, std::memory_order_release);
  running_.store(true, std::memory_order_release);
  thread_ = std::thread([this] { stream_loop(); });
}

void GigeCamera::stop() {
  if (!running_.exchange(false)) return;
  if (thread_.joinable()) thread_.join();
  if (camera_ && state() != SourceState::kDisconnected) {
    GErrorHolder error;  // a camera that went away cannot be told to stop; nothing to do then
    arv_camera_stop_acquisition(camera_.get(), error.out());
  }
  if (state() != SourceState::kDisconnected) state_.store(SourceState::kClosed);
}

void GigeCamera::retire() {
  if (camera_ && control_lost_handler_ != 0) {
    g_signal_handler_disconnect(arv_camera_get_device(camera_.get()), control_lost_handler_);
    control_lost_handler_ = 0;
  }
  // Releasing a dead camera blocks for seconds (Aravis retries giving up control), so objects
  // of a camera that went away wait here until close().
  if (stream_) retired_streams_.push_back(std::move(stream_));
  if (camera_) retired_cameras_.push_back(std::move(camera_));
}

void GigeCamera::close() {
  retire();
  retired_streams_.clear();  // releases each buffer pool with its stream
  retired_cameras_.clear();
}

void GigeCamera::release_live() {
  if (camera_ && control_lost_handler_ != 0) {
    g_signal_handler_disconnect(arv_camera_get_device(camera_.get()), control_lost_handler_);
    control_lost_handler_ = 0;
  }
  if (camera_ && stream_) {
    GErrorHolder error;  // it answers: stopping and releasing it does not wait on retries
    arv_camera_stop_acquisition(camera_.get(), error.out());
  }
  stream_.reset();
  camera_.reset();
}

bool GigeCamera::reconnect() {
  GigeCounters::bump(counters_.reopen_attempts);
  retire();
  GigeFeatureAnswer a;
  try {
    a = open_device();
  } catch (const DeviceError&) {
    retire();
    return false;
  }
  const int64_t now_ns = monotonic_now_ns();
  if (!a.format.same_image(format_)) {
    // It answers, with other settings it will not give up: unusable until it does. The
    // mailbox stays sized for the negotiated format, and nothing is published.
    release_live();
    enter_mismatch(FormatEventCause::kReconnect, a.format, now_ns);
    return false;
  }
  try {
    open_stream();
  } catch (const DeviceError&) {
    retire();
    return false;
  }
  GErrorHolder error;
  arv_camera_start_acquisition(camera_.get(), error.out());
  if (error) {
    retire();
    return false;
  }
  accounting_.reconnected();
  clock_mapper_ = new_clock_mapper();
  watchdog_.frame_at(now_ns);
  GigeCounters::bump(counters_.reconnects);
  leave_mismatch(FormatEventCause::kReconnect, now_ns);
  state_.store(SourceState::kStreaming, std::memory_order_release);
  return true;
}

void GigeCamera::enter_mismatch(FormatEventCause cause, const CameraFormat& seen, int64_t now_ns) {
  // State first: a consumer that sees the event must also see the camera as unusable.
  state_.store(SourceState::kFormatMismatch, std::memory_order_release);
  if (format_watch_.lost(now_ns, cause, format_, seen)) watchdog_.mismatch_at(now_ns);
}

void GigeCamera::leave_mismatch(FormatEventCause cause, int64_t now_ns) {
  format_watch_.restored(now_ns, cause, format_);
}

uint64_t GigeCamera::dropped_frames() const {
  return counters_.dropped();
}

GigeStats GigeCamera::stats() const {
  return counters_.snapshot();
}

void GigeCamera::stream_loop() {
  GvcpLivenessProbe probe(address_);
  while (running_.load(std::memory_order_acquire)) {
    ArvBuffer* buffer = nullptr;
    if (stream_) {
      buffer = arv_stream_timeout_pop_buffer(stream_.get(), kPopTimeoutUs);
    } else {
      // Released (a camera that came back with other settings): nothing to pop until reopened.
      std::this_thread::sleep_for(std::chrono::microseconds(kPopTimeoutUs));
    }
    const int64_t now_ns = monotonic_now_ns();
    if (buffer != nullptr) {
      handle_buffer(buffer, now_ns);
      arv_stream_push_buffer(stream_.get(), buffer);  // back into the pool at once
    }
    look_after_camera(now_ns, probe);
  }
}

void GigeCamera::look_after_camera(int64_t now_ns, GvcpLivenessProbe& probe) {
  const SourceState s = state();
  using Step = StreamWatchdog::Step;
  switch (watchdog_.next(now_ns, s, !stream_, control_lost_.load(std::memory_order_acquire))) {
    case Step::kNone:
      return;
    case Step::kProbeToReopen:
      if (probe.ping(config_.liveness_timeout_ns) == GvcpLivenessProbe::Answer::kAlive) {
        reconnect();
      } else if (s == SourceState::kFormatMismatch) {
        state_.store(SourceState::kDisconnected, std::memory_order_release);
      }
      return;
    case Step::kControlLost:
      state_.store(SourceState::kDisconnected, std::memory_order_release);
      return;
    case Step::kRestoreFormat:
      release_live();
      reconnect();
      return;
    case Step::kStalled:
      state_.store(SourceState::kStalled, std::memory_order_release);
      return;
    case Step::kStalledProbe: {
      state_.store(SourceState::kStalled, std::memory_order_release);
      GigeCounters::bump(counters_.liveness_probes);
      if (address_.empty()) return;
      const auto answer = probe.ping(config_.liveness_timeout_ns);
      if (answer == GvcpLivenessProbe::Answer::kRefused ||
          answer == GvcpLivenessProbe::Answer::kTimeout) {
        state_.store(SourceState::kDisconnected, std::memory_order_release);
      }
      return;
    }
  }
}

void GigeCamera::handle_buffer(ArvBuffer* buffer, int64_t popped_ns) {
  const ArvBufferStatus status = arv_buffer_get_status(buffer);
  if (status == ARV_BUFFER_STATUS_SIZE_MISMATCH) {
    // A frame larger than the negotiated payload: the camera's format changed under us.
    accounting_.wrong_format(arv_buffer_get_frame_id(buffer));
    enter_mismatch(FormatEventCause::kFrame, CameraFormat{}, popped_ns);
    return;
  }
  if (status != ARV_BUFFER_STATUS_SUCCESS) {
    accounting_.lost(arv_buffer_get_frame_id(buffer), static_cast<int>(status));
    return;
  }
  if (arv_buffer_get_payload_type(buffer) != ARV_BUFFER_PAYLOAD_TYPE_IMAGE) {
    accounting_.malformed();
    return;
  }
  const int buffer_w = arv_buffer_get_image_width(buffer);
  const int buffer_h = arv_buffer_get_image_height(buffer);
  const ArvPixelFormat buffer_format = arv_buffer_get_image_pixel_format(buffer);
  if (buffer_w != width_px_ || buffer_h != height_px_ || buffer_format != arv_format_) {
    accounting_.wrong_format(arv_buffer_get_frame_id(buffer));
    CameraFormat seen{buffer_w, buffer_h, pixel_format_, frame_rate_hz_};
    if (buffer_format != arv_format_ && !pixel_format_of(buffer_format, seen.pixel_format))
      seen.pixel_format = PixelFormat::kRgba8;  // none GigE sends: "another one"
    enter_mismatch(FormatEventCause::kFrame, seen, popped_ns);
    return;
  }
  std::size_t size = 0;
  const auto* data = static_cast<const uint8_t*>(arv_buffer_get_image_data(buffer, &size));
  if (data == nullptr) {
    accounting_.malformed();
    return;
  }
  const std::optional<uint64_t> camera_sequence =
      accounting_.admit(arv_buffer_get_frame_id(buffer));
  if (!camera_sequence) return;

  // Aravis stamps arrival on the realtime clock; move it onto CLOCK_MONOTONIC.
  const uint64_t system_ns = arv_buffer_get_system_timestamp(buffer);
  int64_t arrival_ns = popped_ns;
  if (system_ns != 0) {
    const int64_t realtime_minus_mono = clock_ns(CLOCK_REALTIME) - monotonic_now_ns();
    arrival_ns = std::min(popped_ns, static_cast<int64_t>(system_ns) - realtime_minus_mono);
  }

  Frame& f = mailbox_->write_slot();
  const int w = width_px_, h = height_px_;
  const int src_stride = w * bytes_per_pixel(pixel_format_);
  bool ok = false;
  switch (pixel_format_) {
    case PixelFormat::kMono8:
      ok =
          mono8_to_rgba(data, size, w, h, src_stride, f.data.data(), f.data.size(), f.stride_bytes);
      break;
    case PixelFormat::kRgb8:
      ok = rgb8_to_rgba(data, size, w, h, src_stride, f.data.data(), f.data.size(), f.stride_bytes);
      break;
    default:
      ok = bayer_to_rgba(pixel_format_, data, size, w, h, src_stride, f.data.data(), f.data.size(),
                         f.stride_bytes);
      break;
  }
  if (!ok) {
    accounting_.malformed();
    return;
  }
  const uint64_t device_ns = arv_buffer_get_timestamp(buffer);
  f.device_time_trusted = device_ns != 0;
  f.device_timestamp_ns = static_cast<int64_t>(device_ns);
  f.host_timestamp_ns =
      f.device_time_trusted ? clock_mapper_.map(device_ns, arrival_ns) : arrival_ns;
  // State first: a consumer that sees the new frame must also see the stream as live.
  watchdog_.frame_at(popped_ns);
  if (state() == SourceState::kStalled || state() == SourceState::kFormatMismatch) {
    leave_mismatch(FormatEventCause::kFrame, popped_ns);
    state_.store(SourceState::kStreaming);
  }
  f.sequence = accounting_.sequence_for(*camera_sequence);
  mailbox_->publish();
  const int64_t published_ns = monotonic_now_ns();
  accounting_.published();
  timings_.push(
      GigeHandoffTiming{accounting_.last_sequence(), arrival_ns, popped_ns, published_ns});
}

}  // namespace hd::drivers

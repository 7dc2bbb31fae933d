#include "station/app/camera_assembler.h"

#include <stdexcept>

#include "calib/replay_images.h"
#include "core/video_age.h"
#include "drivers/camera_factory.h"
#include "drivers/camera_format.h"
#include "drivers/rtp/rtp_camera.h"
#include "drivers/rtp/rtp_uri.h"
#include "drivers/rtp/srtp_key.h"
#include "station/app/report_text.h"

namespace hd::station {
namespace {

bool is_simulated(const std::string& id) {
  return id.rfind("sim:", 0) == 0;
}

// Why a camera that does not deliver its calibrated size is refused, and what to do about it.
std::string format_refusal(const drivers::CameraDescription& d,
                           const drivers::FormatNegotiation& got,
                           const drivers::FormatVerdict& verdict) {
  const std::string calibrated = drivers::size_text(d.p_c.width, d.p_c.height);
  const std::string delivered = drivers::size_text(got.delivered.width_px, got.delivered.height_px);
  std::string how = "give it the size " + calibrated;
  if (!is_simulated(d.id)) switch (drivers::camera_kind(d.id)) {
      case drivers::CameraKind::kGige:
        how = "set its region (Width, Height, and binning) so that it delivers " + calibrated;
        break;
      case drivers::CameraKind::kV4l2:
        how = "use a camera with a " + calibrated + " mode (v4l2-ctl -d " + d.id +
              " --list-formats-ext lists them)";
        break;
      case drivers::CameraKind::kMock:
        how = "give it the id mock:" + calibrated;
        break;
      case drivers::CameraKind::kRtp:
        how = "make the sender send " + calibrated;
        break;
      case drivers::CameraKind::kReplay:
        how = "replay pictures of " + calibrated;
        break;
    }
  const std::string source = d.calibration_file.empty() ? "its scene" : d.calibration_file;
  return "calibrated at " + calibrated + " (" + source + "), but the camera " + verdict.problem +
         ". Recalibrate it at " + delivered +
         " (hybrid-calib intrinsics and pose with this camera), or " + how;
}

// The device for `d`, with its link and what the link adds to a frame's age (s).
struct OpenedDevice {
  std::unique_ptr<drivers::CameraSource> owned;
  drivers::CameraSource* source = nullptr;
  drivers::CameraLink* link = nullptr;
  double link_delay_s = 0.0;
  std::string what;  ///< how the report describes it
};

OpenedDevice make_device(const drivers::CameraDescription& d, const CameraAssemblyContext& ctx) {
  OpenedDevice out;
  if (is_simulated(d.id)) {
    out.source = ctx.simulated ? ctx.simulated(d.id) : nullptr;
    if (out.source == nullptr)
      throw std::invalid_argument("no simulated camera " + d.id +
                                  " (simulated cameras exist only in a scene run)");
    out.what = "simulated, ";
    return out;
  }
  if (drivers::is_rtp_id(d.id)) {
    std::string why;
    drivers::RtpReceiveConfig rc;
    const auto address = drivers::parse_rtp_uri(d.id, why);
    if (!address) throw std::invalid_argument("malformed id " + d.id + ": " + why);
    rc.listen = *address;
    if (!d.key_file.empty()) rc.srtp_key = drivers::read_srtp_key_file(d.key_file);
    if (d.clock_synchronized) {
      rc.clock = drivers::RtpReceiveConfig::Clock::kSynchronized;
      rc.clock_error_ns = static_cast<int64_t>(d.clock_error_ms * 1e6);
    }
    // With a known frame rate, what the link adds to a frame's age at most in the normal case:
    // the jitter buffer and one frame time each for encoding and decoding. Unknown: the
    // default bound's 100 ms floor covers it.
    if (d.rate_hz > 0.0) out.link_delay_s = 1e-3 * rc.jitter_buffer_latency_ms + 2.0 / d.rate_hz;
    auto rtp = std::make_unique<drivers::RtpCamera>(std::move(rc));
    out.link = rtp.get();
    out.what = "network camera " + rtp->id() + ", ";
    out.owned = std::move(rtp);
  } else {
    out.owned = drivers::make_camera_source(d.id, calib::load_replay_images);
  }
  out.source = out.owned.get();
  return out;
}

}  // namespace

std::optional<StationCamera> assemble_camera(const drivers::CameraDescription& d, std::string name,
                                             const std::string& label,
                                             const CameraAssemblyContext& ctx,
                                             StartupReport& report) {
  OpenedDevice dev;
  try {
    dev = make_device(d, ctx);
  } catch (const std::exception& e) {
    report.missing("camera", label, e.what(), d.optional);
    return std::nullopt;
  }
  // No calibration: the frames bring theirs (a network camera whose sender streams it).
  const bool from_stream = !d.p_c.valid();
  CameraPipelineConfig pc;
  pc.p_c = d.p_c;
  pc.T_world_cam = d.T_world_cam;
  pc.compare_depth_m = d.d_m;
  pc.calibration_from_stream = from_stream;
  pc.model_period_s = ctx.model_period_s;
  StationCamera cam;
  cam.description = d;
  cam.name = std::move(name);
  cam.link = dev.link;
  cam.awaited = dev.link != nullptr && ctx.await_network_cameras;
  cam.device = std::move(dev.owned);
  cam.pipeline = std::make_unique<CameraPipeline>(*dev.source, pc);
  // The calibration fixes the size: the device is asked for it and must deliver exactly it
  // (drivers/camera_format.h, judge_format), so no frame is refused later for its size. A stream
  // cannot be asked: its answer is "unknown until the first frame", and a frame of another size
  // is never shown (drivers/rtp/rtp_camera.h).
  const drivers::CameraFormatRequest want{d.p_c.width, d.p_c.height, {}, 0.0};
  drivers::FormatNegotiation got;
  try {
    got = cam.pipeline->negotiate(want);
  } catch (const std::exception& e) {
    report.missing("camera", label, e.what(), d.optional);
    return std::nullopt;
  }
  const drivers::FormatVerdict verdict = drivers::judge_format(want, got);
  if (!verdict.ok) {
    report.missing("camera", label, format_refusal(d, got, verdict), d.optional);
    return std::nullopt;
  }

  const double rate_hz =
      got.delivered.frame_rate_hz > 0.0 ? got.delivered.frame_rate_hz : d.rate_hz;
  const double known_delay_s = ctx.known_delay_s + dev.link_delay_s;
  const double max_age_s = d.max_video_age_ms > 0.0
                               ? 1e-3 * d.max_video_age_ms
                               : core::default_max_video_age_s(rate_hz, known_delay_s);
  const core::VideoView view = ctx.video_view.value_or(d.video_view);
  cam.calibrated = {cam.pipeline.get(), d.p_c, d.T_world_cam, d.d_m, max_age_s, view};

  const std::string delivered =
      got.delivered.known() ? drivers::format_text(got.delivered)
      : from_stream         ? "size unknown until the first frame (its calibration's)"
                            : "size unknown until the first frame (" +
                          drivers::size_text(d.p_c.width, d.p_c.height) + " expected)";
  std::string calibration;
  const Eigen::Vector3d& c = d.T_world_cam.t;
  if (from_stream) {
    calibration = "calibration: from the stream (none yet: not shown until its sender's arrives)";
  } else {
    calibration = d.calibration_file.empty() ? "calibration: the scene's"
                                             : "calibration: from file " + d.calibration_file;
    if (dev.link != nullptr)
      calibration +=
          " (a calibration in the stream replaces it, with a warning when they differ by more "
          "than 0.5 px)";
    calibration += fmt(", centre (%.2f, %.2f, %.2f) m", c.x(), c.y(), c.z());
  }
  std::string age = fmt(", live while under %.0f ms old", 1e3 * max_age_s);
  if (d.max_video_age_ms <= 0.0)
    age += known_delay_s > 0.0
               ? fmt(" (3 frame periods, >= 100 ms, + %.0f ms known delay)", 1e3 * known_delay_s)
               : std::string(" (3 frame periods, >= 100 ms)");
  report.opened("camera", label,
                dev.what + delivered + (got.detail.empty() ? "" : " (" + got.detail + ")") + ", " +
                    calibration + fmt(", d = %g m", d.d_m) +
                    (view == core::VideoView::kPlane ? std::string()
                     : view == core::VideoView::kFittedPlane
                         ? std::string(", video view fitted-plane: d follows the model's depth")
                         : std::string(", video view model-depth: on the model's surfaces")) +
                    (from_stream                    ? ""
                     : cam.pipeline->undistorting() ? ", undistorted by the pipeline"
                                                    : ", no distortion") +
                    age);
  return cam;
}

}  // namespace hd::station

#include "drivers/camera_factory.h"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>

#include "drivers/clock/monotonic_clock.h"
#include "drivers/replay/replay_camera.h"

#ifdef HD_FACTORY_HAVE_V4L2
#include "drivers/v4l2/v4l2_camera.h"
#endif
#ifdef HD_FACTORY_HAVE_MOCK
#include "drivers/mock/mock_camera.h"
#endif
#ifdef HD_FACTORY_HAVE_RTP
#include "drivers/rtp/rtp_camera.h"
#endif
#include "drivers/rtp/rtp_uri.h"
#ifdef HD_FACTORY_HAVE_GIGE
#include <arv.h>

#include "drivers/gige/gige_camera.h"
#endif

namespace hd::drivers {

namespace {

constexpr const char* kV4l2Prefix = "/dev/video";
constexpr const char* kMockId = "mock";
constexpr const char* kReplayPrefix = "replay:";

// "WxH" with both sides positive and small enough that width * height * 4 cannot overflow.
bool parse_size(const std::string& s, int& w, int& h) {
  const auto x = s.find('x');
  if (x == std::string::npos || x == 0 || x + 1 >= s.size()) return false;
  auto number = [](const std::string& t, int& out) {
    if (t.empty() || t.size() > 5 || t.find_first_not_of("0123456789") != std::string::npos)
      return false;
    out = std::atoi(t.c_str());
    return out > 0 && out <= 16384;
  };
  return number(s.substr(0, x), w) && number(s.substr(x + 1), h);
}

// True when all of `s` is one finite number (strtod's syntax).
bool parse_number(const std::string& s, double& out) {
  if (s.empty()) return false;
  char* end = nullptr;
  out = std::strtod(s.c_str(), &end);
  return end == s.c_str() + s.size() && std::isfinite(out);
}

// Every replay camera of this program exposes on one grid, as cameras on one trigger would: t = 0
// is the first replay camera's start, so a left and a right camera started a few milliseconds
// apart still take picture k at the same instant.
int64_t replay_rig_epoch_ns() {
  static const int64_t epoch_ns = monotonic_now_ns();
  return epoch_ns;
}

[[noreturn, maybe_unused]] void not_built(const std::string& id, const char* driver) {
  throw DeviceError("camera " + id + ": the " + driver + " driver is not built into this program");
}

}  // namespace

ReplayId parse_replay_id(const std::string& id) {
  const auto bad = [&](const std::string& why) {
    return std::invalid_argument("malformed id " + id + ": " + why +
                                 "; expected replay:DIR/GLOB[@RATE_HZ[+-OFFSET_MS]], e.g. "
                                 "replay:data/left*.jpg@15 or replay:data/right*.jpg@15+50");
  };
  if (id.rfind(kReplayPrefix, 0) != 0) throw bad("not a replay id");
  std::string path = id.substr(std::string(kReplayPrefix).size());
  ReplayId r;
  const auto at = path.rfind('@');
  if (at != std::string::npos) {
    const std::string tail = path.substr(at + 1);
    path.resize(at);
    const auto sign = tail.find_first_of("+-", 1);
    const std::string rate = tail.substr(0, sign);
    if (!parse_number(rate, r.rate_hz) || !(r.rate_hz > 0 && r.rate_hz <= 1000))
      throw bad("rate '" + rate + "' is not a number of Hz in (0, 1000]");
    if (sign != std::string::npos) {
      const std::string offset = tail.substr(sign);
      if (!parse_number(offset, r.offset_ms) || std::abs(r.offset_ms) > 60000)
        throw bad("offset '" + offset + "' is not a number of ms within +-60000");
    }
  }
  if (path.empty()) throw bad("no folder or pictures named");
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    r.folder = path;
  } else {
    const std::filesystem::path p(path);
    r.folder = p.has_parent_path() ? p.parent_path().string() : ".";
    r.pattern = p.filename().string();
  }
  return r;
}

CameraKind camera_kind(const std::string& id) {
  if (id.rfind(kV4l2Prefix, 0) == 0) return CameraKind::kV4l2;
  if (id.rfind(kReplayPrefix, 0) == 0) return CameraKind::kReplay;
  if (is_rtp_id(id)) return CameraKind::kRtp;
  if (id == kMockId || id.rfind(std::string(kMockId) + ":", 0) == 0) return CameraKind::kMock;
  return CameraKind::kGige;
}

std::unique_ptr<CameraSource> make_camera_source(const std::string& id,
                                                 const ReplayImageLoader& load_replay) {
  switch (camera_kind(id)) {
    case CameraKind::kV4l2:
#ifdef HD_FACTORY_HAVE_V4L2
      return std::make_unique<V4l2Camera>(id);
#else
      not_built(id, "V4L2");
#endif
    case CameraKind::kMock: {
      // A calibration-sized default: the station's mock default (64x48) is too small to show a
      // board.
      int w = 640, h = 480;
      if (id.size() > 4 && !parse_size(id.substr(5), w, h))
        throw std::invalid_argument("malformed id " + id +
                                    ": expected mock or mock:WxH, e.g. mock:640x480");
#ifdef HD_FACTORY_HAVE_MOCK
      MockCameraConfig c;
      c.id = id;
      c.width = w;
      c.height = h;
      c.rate_hz = 30.0;
      return std::make_unique<MockCamera>(std::move(c));
#else
      not_built(id, "mock camera");
#endif
    }
    case CameraKind::kRtp: {
#ifdef HD_FACTORY_HAVE_RTP
      std::string why;
      const auto address = parse_rtp_uri(id, why);
      if (!address) throw std::invalid_argument("malformed id " + id + ": " + why);
      RtpReceiveConfig c;
      c.listen = *address;
      return std::make_unique<RtpCamera>(std::move(c));
#else
      not_built(id, "network camera (GStreamer RTP)");
#endif
    }
    case CameraKind::kReplay: {
      const ReplayId r = parse_replay_id(id);
      if (!load_replay)
        throw DeviceError("camera " + id +
                          ": this program reads no replay pictures (no picture loader given)");
      ReplayCameraConfig c;
      c.id = id;
      c.rate_hz = r.rate_hz;
      c.offset_ns = static_cast<int64_t>(std::llround(r.offset_ms * 1e6));
      c.load = [r, load_replay] { return load_replay(r); };
      c.epoch_ns = replay_rig_epoch_ns;
      return std::make_unique<ReplayCamera>(std::move(c));
    }
    case CameraKind::kGige: {
#ifdef HD_FACTORY_HAVE_GIGE
      GigeConfig c;
      c.device_id = id;
      // Mono8 is all the corner detector needs and the cheapest to carry; 0 keeps the camera's
      // own region and rate, so a calibration sees the sensor as the station will use it.
      c.pixel_format = PixelFormat::kMono8;
      c.frame_rate_hz = 0.0;
      return std::make_unique<GigeCamera>(std::move(c));
#else
      not_built(id, "GigE (Aravis)");
#endif
    }
  }
  throw std::logic_error("camera_kind returned an unknown kind");
}

void shutdown_camera_drivers() {
#ifdef HD_FACTORY_HAVE_GIGE
  arv_shutdown();
#endif
}

}  // namespace hd::drivers

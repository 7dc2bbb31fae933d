#include "calib/camera_factory.h"

#include <cstdlib>
#include <stdexcept>

#ifdef HD_CALIB_HAVE_V4L2
#include "drivers/v4l2/v4l2_camera.h"
#endif
#ifdef HD_CALIB_HAVE_MOCK
#include "drivers/mock/mock_camera.h"
#endif
#ifdef HD_CALIB_HAVE_RTP
#include "drivers/rtp/rtp_camera.h"
#endif
#include "drivers/rtp/rtp_uri.h"
#ifdef HD_CALIB_HAVE_GIGE
#include <arv.h>

#include "drivers/gige/gige_camera.h"
#endif

namespace hd::calib {

namespace {

constexpr const char* kV4l2Prefix = "/dev/video";
constexpr const char* kMockId = "mock";

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

[[noreturn, maybe_unused]] void not_built(const std::string& id, const char* driver) {
  throw drivers::DeviceError("camera " + id + ": the " + driver +
                             " driver is not built into this program");
}

}  // namespace

CameraKind camera_kind(const std::string& id) {
  if (id.rfind(kV4l2Prefix, 0) == 0) return CameraKind::kV4l2;
  if (drivers::is_rtp_id(id)) return CameraKind::kRtp;
  if (id == kMockId || id.rfind(std::string(kMockId) + ":", 0) == 0) return CameraKind::kMock;
  return CameraKind::kGige;
}

std::unique_ptr<drivers::CameraSource> make_camera_source(const std::string& id) {
  switch (camera_kind(id)) {
    case CameraKind::kV4l2:
#ifdef HD_CALIB_HAVE_V4L2
      return std::make_unique<drivers::V4l2Camera>(id);
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
#ifdef HD_CALIB_HAVE_MOCK
      drivers::MockCameraConfig c;
      c.id = id;
      c.width = w;
      c.height = h;
      c.rate_hz = 30.0;
      return std::make_unique<drivers::MockCamera>(std::move(c));
#else
      not_built(id, "mock camera");
#endif
    }
    case CameraKind::kRtp: {
#ifdef HD_CALIB_HAVE_RTP
      std::string why;
      const auto address = drivers::parse_rtp_uri(id, why);
      if (!address) throw std::invalid_argument("malformed id " + id + ": " + why);
      drivers::RtpReceiveConfig c;
      c.listen = *address;
      return std::make_unique<drivers::RtpCamera>(std::move(c));
#else
      not_built(id, "network camera (GStreamer RTP)");
#endif
    }
    case CameraKind::kGige: {
#ifdef HD_CALIB_HAVE_GIGE
      drivers::GigeConfig c;
      c.device_id = id;
      // Mono8 is all the corner detector needs and the cheapest to carry; 0 keeps the camera's
      // own region and rate, so a calibration sees the sensor as the station will use it.
      c.pixel_format = drivers::PixelFormat::kMono8;
      c.frame_rate_hz = 0.0;
      return std::make_unique<drivers::GigeCamera>(std::move(c));
#else
      not_built(id, "GigE (Aravis)");
#endif
    }
  }
  throw std::logic_error("camera_kind returned an unknown kind");
}

void shutdown_camera_drivers() {
#ifdef HD_CALIB_HAVE_GIGE
  arv_shutdown();
#endif
}

}  // namespace hd::calib

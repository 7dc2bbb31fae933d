#include "remote/app/remote_config.h"

#include "calib/calibration_file.h"
#include "core/config/yaml_fields.h"
#include "drivers/rtp/srtp_key.h"
#include "remote/sender/h264_encoder.h"

namespace hd::remote {
namespace {

using config::Range;
using config::YamlFields;

RemoteCameraConfig read_camera(const YamlFields& f, std::size_t index, const RemoteConfig& all,
                               int bitrate_kbps, double key_interval_s, bool intra_refresh) {
  RemoteCameraConfig c;
  c.line = f.line();
  c.name = f.optional_string("name", "camera" + std::to_string(index));
  c.id = f.required_string("id");
  if (c.id.empty()) f.fail("id", "empty; expected /dev/videoN, a GigE id or mock[:WxH]");
  if (c.id.rfind("rtp://", 0) == 0)
    f.fail("id", "'" + c.id +
                     "' is a network camera (the station's end); the remote site sends "
                     "cameras it captures: /dev/videoN, a GigE id or mock[:WxH]");
  c.calibration_file = f.required_path("calibration");
  const std::string to = f.required_string("to");
  std::string why;
  const auto address = drivers::parse_rtp_uri(to, why);
  if (!address) f.fail("to", "'" + to + "': " + why);
  c.to = *address;
  for (const RemoteCameraConfig& other : all.cameras)
    if (other.to.host == c.to.host && other.to.port == c.to.port)
      f.fail("to", "'" + to + "' is camera " + other.name + "'s destination too (line " +
                       std::to_string(other.line) + "); each camera needs its own port");
  c.rate_hz = f.optional_double("rate_hz", 30.0, Range::closed(1.0, 240.0));
  c.bitrate_kbps = f.optional_int("bitrate_kbps", bitrate_kbps, Range::closed(50, 100000));
  c.key_interval_s = f.optional_double("key_interval_s", key_interval_s, Range::closed(0.05, 10.0));
  c.intra_refresh = f.optional_bool("intra_refresh", intra_refresh);
  f.finish();
  calib::CalibrationFile cal;
  try {
    cal = calib::read_calibration_file(c.calibration_file);
  } catch (const calib::CalibrationFileError& e) {
    f.fail("calibration", e.what());
  }
  if (!cal.camera_pose)
    f.fail("calibration", c.calibration_file +
                              " has no camera pose (camera_pose_R / camera_pose_t: run "
                              "`hybrid-calib pose`); the station needs P_c as well as p_c");
  c.p_c = cal.pinhole;
  c.T_world_cam = *cal.camera_pose;
  return c;
}

RemoteConfig read_remote(const YamlFields& root) {
  RemoteConfig r;
  r.file = root.file();
  std::vector<std::string> encoders{"auto"};
  for (const std::string& e : h264_encoder_candidates()) encoders.push_back(e);
  r.encoder = encoders[root.optional_enum("encoder", encoders, 0)];
  const int bitrate = root.optional_int("bitrate_kbps", 4000, Range::closed(50, 100000));
  const double key_interval =
      root.optional_double("key_interval_s", 0.5, Range::closed(0.05, 10.0));
  const bool intra_refresh = root.optional_bool("intra_refresh", false);
  if (auto k = root.optional_path("key_file")) {
    try {
      drivers::read_srtp_key_file(*k);  // refused now, with the file's line, not at start
    } catch (const std::exception& e) {
      root.fail("key_file", e.what());
    }
    r.key_file = *k;
  }
  const std::vector<YamlFields> cams = root.required_list("cameras", 1);
  if (cams.size() > 255) root.fail("cameras", "at most 255 cameras (the camera index is a byte)");
  for (std::size_t i = 0; i < cams.size(); ++i)
    r.cameras.push_back(read_camera(cams[i], i, r, bitrate, key_interval, intra_refresh));
  root.finish();
  return r;
}

}  // namespace

RemoteConfig load_remote_config(const std::string& path) {
  return read_remote(config::load_yaml_fields(path));
}

RemoteConfig parse_remote_config(const std::string& text, const std::string& name) {
  return read_remote(YamlFields(config::parse_yaml(text, name), name));
}

}  // namespace hd::remote

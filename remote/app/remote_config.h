#pragma once
// remote.yaml: the remote site's cameras (by the station's driver ids, each with its calibration
// file and the station's address), codec and rate settings and the SRTP key (format: README
// "File formats", example remote/remote-example.yaml).

#include <string>
#include <vector>

#include "core/pinhole.h"
#include "core/pose.h"
#include "drivers/rtp/rtp_uri.h"

namespace hd::remote {

/// One camera: captured through drivers/ (the id as station.yaml takes it: /dev/videoN, a GigE
/// id such as Aravis-Fake-SERIAL, mock[:WxH]) and sent to `to` with its p_c and P_c.
struct RemoteCameraConfig {
  std::string name;              ///< for reports ("camera<i>" when not given)
  std::string id;                ///< driver id
  std::string calibration_file;  ///< resolved against remote.yaml's directory
  core::Pinhole p_c;             ///< from the file (core convention)
  core::Pose T_world_cam;        ///< from the file's camera_pose_R / camera_pose_t
  drivers::RtpAddress to;        ///< the station's rtp://HOST:PORT for this camera
  double rate_hz = 30.0;         ///< frames per second the stream is encoded for
  int bitrate_kbps = 4000;
  double key_interval_s = 0.5;
  bool intra_refresh = false;  ///< x264enc intra refresh (RtpSendConfig::intra_refresh)
  int line = 0;
};

struct RemoteConfig {
  std::string file;
  std::vector<RemoteCameraConfig> cameras;
  std::string encoder = "auto";  ///< auto, or an element of h264_encoder_candidates()
  std::string key_file;          ///< resolved; "" = no encryption
};

/// Reads and checks `path`. Any mistake -- YAML syntax, a missing or unknown key, a wrong type,
/// a value out of range, a malformed or repeated destination, an unreadable calibration file or
/// one without a pose, a key file others may read -- throws config::ConfigError naming the file,
/// line:column, field and value.
RemoteConfig load_remote_config(const std::string& path);
/// The same from text; `name` stands for the file, relative paths resolve against its directory.
RemoteConfig parse_remote_config(const std::string& text, const std::string& name);

}  // namespace hd::remote

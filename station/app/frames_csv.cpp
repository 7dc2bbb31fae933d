#include "station/app/frames_csv.h"

#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace hd::station {

const char* variant_name(core::Variant v) {
  switch (v) {
    case core::Variant::kVideo:
      return "video";
    case core::Variant::kHybrid:
      return "hybrid";
    case core::Variant::kSynthetic:
      return "synthetic";
  }
  return "?";
}

void write_frames_csv(const FrameLog& log, const std::vector<std::string>& camera_names,
                      const std::string& path) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream f(tmp, std::ios::trunc);
    if (!f) throw std::runtime_error(path + ": cannot open for writing");
    f << "frame,t_s,m,w_video,camera,camera_name,variant,missed_deadline,guidance,"
         "guidance_distance_m,guidance_dir_x,guidance_dir_y,head_x_m,head_y_m,head_z_m,video_age_"
         "ms,"
         "model_age_ms\n";
    char buf[320];
    char m_text[32], video_age[32], model_age[32];
    for (const FrameLogRow& row : log) {
      const station::FrameRow& r = row.decision;
      if (std::isfinite(r.m))
        std::snprintf(m_text, sizeof m_text, "%.4f", r.m);
      else
        std::snprintf(m_text, sizeof m_text, "inf");
      // An age that does not exist (no video on screen, the a-priori model) is an empty field.
      const auto age_text = [](char* out, std::size_t n, double ms) {
        if (std::isfinite(ms))
          std::snprintf(out, n, "%.3f", ms);
        else
          out[0] = 0;
      };
      age_text(video_age, sizeof video_age, r.video_age_ms);
      age_text(model_age, sizeof model_age, r.model_age_ms);
      const char* name = r.camera >= 0 && static_cast<std::size_t>(r.camera) < camera_names.size()
                             ? camera_names[static_cast<std::size_t>(r.camera)].c_str()
                             : "";
      std::snprintf(buf, sizeof buf,
                    "%" PRIu64 ",%.6f,%s,%.9f,%d,%s,%s,%d,%d,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%s,%s\n",
                    r.frame, row.t_s, m_text, r.w_video, r.camera, name, variant_name(r.variant),
                    int{row.missed_deadline}, int{r.guidance}, r.guidance_distance_m,
                    r.guidance_dir_x, r.guidance_dir_y, r.head_x_m, r.head_y_m, r.head_z_m,
                    video_age, model_age);
      f << buf;
    }
    if (!f.flush()) {
      std::error_code ec;
      std::filesystem::remove(tmp, ec);
      throw std::runtime_error(path + ": write failed");
    }
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::filesystem::remove(tmp, ec);
    throw std::runtime_error(path + ": cannot rename the temp file into place");
  }
}

}  // namespace hd::station

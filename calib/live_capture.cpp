#include "calib/live_capture.h"

#include <cmath>
#include <opencv2/imgproc.hpp>
#include <thread>

namespace hd::calib {

cv::Mat frame_to_gray(const drivers::Frame& f, std::string* why) {
  const int bpp = drivers::bytes_per_pixel(f.format);
  auto bad = [&](const std::string& s) {
    if (why) *why = s;
    return cv::Mat();
  };
  if (f.format != drivers::PixelFormat::kRgba8 && f.format != drivers::PixelFormat::kRgb8 &&
      f.format != drivers::PixelFormat::kMono8)
    return bad("pixel format " + std::string(drivers::to_string(f.format)) + " not supported");
  if (f.width <= 0 || f.height <= 0 || f.stride_bytes < f.width * bpp ||
      f.data.size() < static_cast<std::size_t>(f.stride_bytes) * static_cast<std::size_t>(f.height))
    return bad("frame geometry does not match its buffer");
  const cv::Mat view(f.height, f.width, CV_8UC(bpp), const_cast<uint8_t*>(f.data.data()),
                     static_cast<std::size_t>(f.stride_bytes));
  cv::Mat g;
  if (bpp == 4)
    cv::cvtColor(view, g, cv::COLOR_RGBA2GRAY);
  else if (bpp == 3)
    cv::cvtColor(view, g, cv::COLOR_RGB2GRAY);
  else
    g = view.clone();
  return g;
}

LiveResult collect_live_views(drivers::CameraSource& source, const Board& board,
                              const LiveOptions& opt,
                              const std::function<bool(const LiveStatus&)>& show) {
  LiveResult res;
  auto& box = source.frames();
  auto last_new = std::chrono::steady_clock::now();
  std::vector<std::vector<cv::Point2f>> kept;
  while (!res.enough) {
    if (!box.fetch()) {
      if (std::chrono::steady_clock::now() - last_new > opt.max_duration) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
      continue;
    }
    last_new = std::chrono::steady_clock::now();
    ++res.frames_examined;
    std::string why;
    cv::Mat gray = frame_to_gray(box.latest(), &why);
    LiveStatus st;
    if (gray.empty() || (res.image_size.area() > 0 && gray.size() != res.image_size)) {
      ++res.frames_rejected;
      st.message = "frame " + std::to_string(res.frames_examined) + " from " + source.id() +
                   " rejected: " + (why.empty() ? "size changed mid-session" : why);
      if (!show(st)) break;
      continue;
    }
    res.image_size = gray.size();
    const Detection det = detect_corners(gray, board, opt.detector);
    std::string verdict = det.describe();
    if (det.found()) {
      // Kept only if the board moved: near-duplicates add weight, not information.
      const double diag = std::hypot(gray.cols, gray.rows);
      double min_move = 1e9;
      for (const auto& k : kept) {
        double s = 0;
        for (std::size_t i = 0; i < k.size(); ++i) s += cv::norm(k[i] - det.corners[i]);
        min_move = std::min(min_move, s / static_cast<double>(k.size()));
      }
      if (min_move > opt.min_move_fraction * diag) {
        kept.push_back(det.corners);
        res.views.push_back({"frame" + std::to_string(res.frames_examined), det.corners});
        verdict += ", kept";
      } else {
        verdict += ", too close to a kept view";
      }
    }
    st.coverage = image_coverage(kept, res.image_size);
    const bool size_ok =
        st.coverage.board_size_min > 0 &&
        st.coverage.board_size_max >= opt.min_size_ratio * st.coverage.board_size_min;
    res.enough = static_cast<int>(kept.size()) >= opt.target_views &&
                 st.coverage.grid_fraction >= opt.min_grid_fraction && size_ok;
    st.enough = res.enough;
    st.message = "[" + std::to_string(kept.size()) + "/" + std::to_string(opt.target_views) +
                 "] frame " + std::to_string(res.frames_examined) + ": " + verdict +
                 "; grid covered " +
                 std::to_string(static_cast<int>(100 * st.coverage.grid_fraction)) + "%" +
                 (res.enough ? "; enough varied views" : "");
    st.gray = &gray;
    st.corners = &det.corners;
    if (!show(st)) break;
  }
  return res;
}

}  // namespace hd::calib

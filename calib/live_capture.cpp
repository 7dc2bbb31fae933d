// The live collectors (one camera: views; two cameras: pairs). Both are built from the same
// parts: FrameFeed (a camera's stream, and when it has gone silent), session_gray (a frame as a
// checked gray image), ViewSelection (which views to keep, and when the set is varied enough).
#include "calib/live_capture.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
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

namespace {

// How long the collectors wait before looking at an idle camera again: short next to a frame
// period, long enough not to spin a core.
constexpr auto kIdlePoll = std::chrono::milliseconds(2);

// One camera's stream: the newest frame when a new one arrived, and whether the camera went
// silent (its stream ended, or nothing new for max_silence).
class FrameFeed {
 public:
  enum class Poll { kFrame, kNothingNew, kSilent };

  FrameFeed(drivers::CameraSource& source, std::chrono::milliseconds max_silence)
      : source_(source), max_silence_(max_silence), last_new_(std::chrono::steady_clock::now()) {}

  Poll poll() {
    // The state is read before fetching: a source publishes its last frame before it says it
    // stopped, so "stopped and nothing to fetch" means nothing more will come.
    const bool stopped = source_.state() == drivers::SourceState::kClosed;
    if (source_.frames().fetch()) {
      last_new_ = std::chrono::steady_clock::now();
      ++taken_;
      measure_period(frame());
      return Poll::kFrame;
    }
    if (stopped) {
      why_silent_ = "stopped streaming";
      return Poll::kSilent;
    }
    if (std::chrono::steady_clock::now() - last_new_ > max_silence_) {
      char buf[80];
      std::snprintf(buf, sizeof buf, "delivered nothing new for %.1f s",
                    std::chrono::duration<double>(max_silence_).count());
      why_silent_ = buf;
      return Poll::kSilent;
    }
    return Poll::kNothingNew;
  }

  const drivers::Frame& frame() const { return source_.frames().latest(); }
  drivers::CameraSource& source() { return source_; }
  int taken() const { return taken_; }
  const std::string& why_silent() const { return why_silent_; }

  /// The frame period: the rate the camera reports, else the shortest seen between its frames
  /// (per sequence step, so frames the consumer skipped do not stretch it); 0 while unknown.
  int64_t period_ns() const {
    const double rate = source_.format().frame_rate_hz;
    if (rate > 0) return static_cast<int64_t>(std::llround(1e9 / rate));
    return measured_period_ns_;
  }

 private:
  void measure_period(const drivers::Frame& f) {
    if (taken_ > 1 && f.sequence > last_sequence_ && f.host_timestamp_ns > last_stamp_ns_) {
      const int64_t p = (f.host_timestamp_ns - last_stamp_ns_) /
                        static_cast<int64_t>(f.sequence - last_sequence_);
      if (measured_period_ns_ == 0 || p < measured_period_ns_) measured_period_ns_ = p;
    }
    last_sequence_ = f.sequence;
    last_stamp_ns_ = f.host_timestamp_ns;
  }

  drivers::CameraSource& source_;
  std::chrono::milliseconds max_silence_;
  std::chrono::steady_clock::time_point last_new_;
  int taken_ = 0;
  uint64_t last_sequence_ = 0;
  int64_t last_stamp_ns_ = 0;
  int64_t measured_period_ns_ = 0;
  std::string why_silent_;
};

// The newest frame as gray, if it is well formed and of the session's size (the camera's first
// good frame fixes it); else empty, and `why` says what was wrong.
cv::Mat session_gray(const drivers::Frame& f, cv::Size& session_size, std::string& why) {
  cv::Mat gray = frame_to_gray(f, &why);
  if (gray.empty()) return gray;
  if (session_size.area() > 0 && gray.size() != session_size) {
    why = "size changed mid-session";
    return {};
  }
  session_size = gray.size();
  return gray;
}

// The views kept from one camera: how far a new view is from each, and whether they are varied
// enough yet.
class ViewSelection {
 public:
  explicit ViewSelection(const LiveOptions& opt) : opt_(opt) {}

  /// Mean corner displacement from each kept view to `corners`, as a fraction of the diagonal.
  std::vector<double> moves(const std::vector<cv::Point2f>& corners, cv::Size size) const {
    const double diag = std::hypot(size.width, size.height);
    std::vector<double> m;
    for (const auto& k : kept_) {
      double s = 0;
      for (std::size_t i = 0; i < k.size(); ++i) s += cv::norm(k[i] - corners[i]);
      m.push_back(s / static_cast<double>(k.size()) / diag);
    }
    return m;
  }
  void keep(const std::vector<cv::Point2f>& corners) { kept_.push_back(corners); }
  std::size_t size() const { return kept_.size(); }
  Coverage coverage(cv::Size size) const { return image_coverage(kept_, size); }
  /// Enough views, spread over the image and in several sizes.
  bool enough(const Coverage& c) const {
    const bool size_ok =
        c.board_size_min > 0 && c.board_size_max >= opt_.min_size_ratio * c.board_size_min;
    return static_cast<int>(kept_.size()) >= opt_.target_views &&
           c.grid_fraction >= opt_.min_grid_fraction && size_ok;
  }

 private:
  const LiveOptions& opt_;
  std::vector<std::vector<cv::Point2f>> kept_;
};

// Near-duplicates add weight, not information: a view counts as new when every kept view is
// farther than min_move_fraction.
bool far_from_all(const std::vector<double>& moves, double min_move_fraction) {
  return std::all_of(moves.begin(), moves.end(), [&](double m) { return m > min_move_fraction; });
}

std::string percent(double fraction) {
  return std::to_string(static_cast<int>(100 * fraction)) + "%";
}

std::string ms_text(int64_t ns) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f ms", static_cast<double>(ns) / 1e6);
  return buf;
}

}  // namespace

LiveResult collect_live_views(drivers::CameraSource& source, const Board& board,
                              const LiveOptions& opt,
                              const std::function<bool(const LiveStatus&)>& show) {
  LiveResult res;
  FrameFeed feed(source, opt.max_duration);
  ViewSelection kept(opt);
  while (!res.enough) {
    const FrameFeed::Poll p = feed.poll();
    if (p == FrameFeed::Poll::kSilent) break;
    if (p == FrameFeed::Poll::kNothingNew) {
      std::this_thread::sleep_for(kIdlePoll);
      continue;
    }
    ++res.frames_examined;
    std::string why;
    cv::Mat gray = session_gray(feed.frame(), res.image_size, why);
    LiveStatus st;
    if (gray.empty()) {
      ++res.frames_rejected;
      st.message = "frame " + std::to_string(res.frames_examined) + " from " + source.id() +
                   " rejected: " + why;
      if (!show(st)) break;
      continue;
    }
    const Detection det = detect_corners(gray, board, opt.detector);
    std::string verdict = det.describe();
    if (det.found()) {
      if (far_from_all(kept.moves(det.corners, res.image_size), opt.min_move_fraction)) {
        kept.keep(det.corners);
        res.views.push_back({"frame" + std::to_string(res.frames_examined), det.corners});
        verdict += ", kept";
      } else {
        verdict += ", too close to a kept view";
      }
    }
    st.coverage = kept.coverage(res.image_size);
    res.enough = kept.enough(st.coverage);
    st.enough = res.enough;
    st.message = "[" + std::to_string(kept.size()) + "/" + std::to_string(opt.target_views) +
                 "] frame " + std::to_string(res.frames_examined) + ": " + verdict +
                 "; grid covered " + percent(st.coverage.grid_fraction) +
                 (res.enough ? "; enough varied views" : "");
    st.gray = &gray;
    st.corners = &det.corners;
    if (!show(st)) break;
  }
  return res;
}

StereoLiveResult collect_live_pairs(drivers::CameraSource& left, drivers::CameraSource& right,
                                    const Board& board, const LiveOptions& opt,
                                    const std::function<bool(const StereoLiveStatus&)>& show) {
  StereoLiveResult res;
  FrameFeed feeds[2] = {FrameFeed(left, opt.max_duration), FrameFeed(right, opt.max_duration)};
  ViewSelection kept[2] = {ViewSelection(opt), ViewSelection(opt)};
  cv::Size sizes[2];
  cv::Mat grays[2];  // the frame each camera has waiting for a partner (empty: none)
  int64_t stamps_ns[2] = {0, 0};
  const char* side_name[2] = {"left", "right"};
  StereoLiveStatus st;
  while (!res.enough) {
    // Take a frame from each camera that has none waiting.
    bool idle = true, silent = false;
    for (int s = 0; s < 2 && !silent; ++s) {
      if (!grays[s].empty()) continue;
      const FrameFeed::Poll p = feeds[s].poll();
      if (p == FrameFeed::Poll::kSilent) {
        res.stop_reason = "camera " + feeds[s].source().id() + " " + feeds[s].why_silent();
        silent = true;
      } else if (p == FrameFeed::Poll::kFrame) {
        idle = false;
        (s == 0 ? res.frames_left : res.frames_right)++;
        std::string why;
        grays[s] = session_gray(feeds[s].frame(), sizes[s], why);
        stamps_ns[s] = feeds[s].frame().host_timestamp_ns;
        if (grays[s].empty()) {
          ++res.frames_rejected;
          st.message = "frame " + std::to_string(feeds[s].taken()) + " from " +
                       feeds[s].source().id() + " rejected: " + why;
          if (!show(st)) return res;
        }
      }
    }
    if (silent) break;
    if (grays[0].empty() || grays[1].empty()) {
      if (idle) std::this_thread::sleep_for(kIdlePoll);
      continue;
    }
    if (sizes[0] != sizes[1]) {
      res.size_mismatch = "camera " + left.id() + " delivers " +
                          drivers::size_text(sizes[0].width, sizes[0].height) + " but camera " +
                          right.id() + " delivers " +
                          drivers::size_text(sizes[1].width, sizes[1].height);
      break;
    }
    res.image_size = sizes[0];
    // Synchronised? Within the tolerance of each other's exposure. Otherwise the older frame can
    // never find a partner (the other camera's later frames are later still): set it aside.
    int64_t tolerance_ns = opt.sync_tolerance_ns;
    if (tolerance_ns <= 0) {
      const int64_t pl = feeds[0].period_ns(), pr = feeds[1].period_ns();
      const int64_t shorter = pl > 0 && pr > 0 ? std::min(pl, pr) : std::max(pl, pr);
      tolerance_ns = shorter / 2;
    }
    const int64_t gap_ns = std::abs(stamps_ns[0] - stamps_ns[1]);
    if (tolerance_ns <= 0 || gap_ns > tolerance_ns) {
      const int older = stamps_ns[0] <= stamps_ns[1] ? 0 : 1;
      ++res.unsynchronised;
      st.message =
          "frame " + std::to_string(feeds[older].taken()) + " from " + side_name[older] +
          " camera " + feeds[older].source().id() + " set aside: unsynchronised, " +
          (tolerance_ns <= 0 ? "frame period not known yet"
                             : ms_text(gap_ns) + " from the other camera's frame (tolerance " +
                                   ms_text(tolerance_ns) + ")");
      grays[older].release();
      if (!show(st)) break;
      continue;
    }
    res.sync_tolerance_ns = tolerance_ns;
    ++res.pairs_examined;
    const Detection det[2] = {detect_corners(grays[0], board, opt.detector),
                              detect_corners(grays[1], board, opt.detector)};
    std::string verdict = det[0].describe() + " / " + det[1].describe();
    if (det[0].found() && det[1].found()) {
      // Kept when it differs from every kept pair in at least one of the two images.
      const auto ml = kept[0].moves(det[0].corners, res.image_size);
      const auto mr = kept[1].moves(det[1].corners, res.image_size);
      std::vector<double> pair_moves(ml.size());
      for (std::size_t k = 0; k < ml.size(); ++k) pair_moves[k] = std::max(ml[k], mr[k]);
      if (far_from_all(pair_moves, opt.min_move_fraction)) {
        const std::string name = "pair" + std::to_string(res.pairs_examined);
        for (int s = 0; s < 2; ++s) kept[s].keep(det[s].corners);
        res.left.push_back({name, det[0].corners});
        res.right.push_back({name, det[1].corners});
        verdict += ", kept";
      } else {
        ++res.too_similar;
        verdict += ", too close to a kept pair";
      }
    } else if (det[0].found() || det[1].found()) {
      ++res.board_in_one_only;
      verdict += ", board in one image only";
    } else {
      ++res.board_in_neither;
    }
    st.left = kept[0].coverage(res.image_size);
    st.right = kept[1].coverage(res.image_size);
    res.enough = kept[0].enough(st.left) && kept[1].enough(st.right);
    st.enough = res.enough;
    st.message = "[" + std::to_string(kept[0].size()) + "/" + std::to_string(opt.target_views) +
                 "] pair " + std::to_string(res.pairs_examined) + " (frames " +
                 std::to_string(feeds[0].taken()) + " + " + std::to_string(feeds[1].taken()) +
                 ", " + ms_text(gap_ns) + " apart): " + verdict + "; grid covered " +
                 percent(st.left.grid_fraction) + " / " + percent(st.right.grid_fraction) +
                 (res.enough ? "; enough varied pairs" : "");
    grays[0].release();
    grays[1].release();
    if (!show(st)) break;
  }
  if (res.enough) res.stop_reason = "enough varied pairs";
  return res;
}

}  // namespace hd::calib

#include "render/latency/latency_recorder.h"

#include <algorithm>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <stdexcept>

namespace hd::render {
namespace {

constexpr const char* kCsvHeader =
    "frame,pose_sample_ns,video_ns,video_is_exposure,texture_update_ns,render_start_ns,"
    "render_end_ns,swap_ns,predicted_display_ns,missed_deadline,model_capture_ns,"
    "video_encoded_ns,video_sent_ns,video_received_ns,video_decoded_ns,model_reconstructed_ns,"
    "model_published_ns";
constexpr int kCsvColumns = 17;

// Commits a finished temp file under its final name, or removes it and says why.
void commit_file(const std::string& tmp, const std::string& path) {
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::filesystem::remove(tmp, ec);
    throw std::runtime_error(path + ": cannot rename temp file into place");
  }
}

}  // namespace

LatencyRecorder::LatencyRecorder(std::size_t capacity)
    : records_(std::max<std::size_t>(capacity, 1)), scratch_(records_.size()) {}

void LatencyRecorder::record(const LatencyRecord& r) {
  records_[next_] = r;
  next_ = (next_ + 1) % records_.size();
  if (count_ < records_.size()) ++count_;
  ++total_;
  if (r.missed_deadline) ++missed_;
}

LatencyStats LatencyRecorder::stats_over(LatencyMetric m, std::size_t last_n) const {
  const std::size_t first = count_ > last_n ? count_ - last_n : 0;
  std::size_t n = 0;
  for (std::size_t i = first; i < count_; ++i) {
    int64_t v = 0;
    if (latency_of(at(i), m, v)) scratch_[n++] = v;
  }
  LatencyStats s;
  s.count = n;
  if (n == 0) return s;
  std::sort(scratch_.begin(), scratch_.begin() + static_cast<std::ptrdiff_t>(n));
  auto rank = [&](double p) {
    const auto k = static_cast<std::size_t>(std::ceil(p / 100.0 * static_cast<double>(n)));
    return static_cast<double>(scratch_[std::clamp<std::size_t>(k, 1, n) - 1]) * 1e-6;
  };
  s.p50_ms = rank(50);
  s.p95_ms = rank(95);
  s.p99_ms = rank(99);
  s.max_ms = static_cast<double>(scratch_[n - 1]) * 1e-6;
  double sum = 0;
  for (std::size_t i = 0; i < n; ++i) sum += static_cast<double>(scratch_[i]);
  s.mean_ms = sum / static_cast<double>(n) * 1e-6;
  return s;
}

LatencyStats LatencyRecorder::stats(LatencyMetric m) const {
  return stats_over(m, count_);
}

std::string_view LatencyRecorder::hud_line() const {
  if (count_ == 0) {
    std::snprintf(hud_.data(), hud_.size(), "no frames yet");
    return hud_.data();
  }
  const LatencyRecord& r = at(count_ - 1);
  int64_t swap = 0, disp = 0, age = 0, model = 0;
  const bool has_swap = latency_of(r, LatencyMetric::kMotionToSwap, swap);
  const bool has_disp = latency_of(r, LatencyMetric::kMotionToDisplay, disp);
  const bool has_age = latency_of(r, LatencyMetric::kVideoAge, age);
  const bool has_model = latency_of(r, LatencyMetric::kModelAge, model);
  const LatencyStats p_disp = stats_over(LatencyMetric::kMotionToDisplay, 128);
  std::snprintf(hud_.data(), hud_.size(),
                "frame %" PRIu64
                " | MTP swap %.1f ms | MTP display %.1f ms (p95 %.1f) | video age %s%.1f ms | "
                "model age %s%.0f ms | missed %" PRIu64,
                r.frame, has_swap ? swap * 1e-6 : 0.0, has_disp ? disp * 1e-6 : 0.0, p_disp.p95_ms,
                has_age ? "" : "n/a ", has_age ? age * 1e-6 : 0.0, has_model ? "" : "n/a ",
                has_model ? model * 1e-6 : 0.0, missed_);
  return hud_.data();
}

void LatencyRecorder::write_csv(const std::string& path) const {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream f(tmp, std::ios::trunc);
    if (!f) throw std::runtime_error(path + ": cannot open temp file for writing");
    f << kCsvHeader << "\n";
    for (std::size_t i = 0; i < count_; ++i) {
      const LatencyRecord& r = at(i);
      f << r.frame << ',' << r.pose_sample_ns << ',' << r.video_ns << ','
        << int{r.video_is_exposure} << ',' << r.texture_update_ns << ',' << r.render_start_ns << ','
        << r.render_end_ns << ',' << r.swap_ns << ',' << r.predicted_display_ns << ','
        << int{r.missed_deadline} << ',' << r.model_capture_ns << ',' << r.video_encoded_ns << ','
        << r.video_sent_ns << ',' << r.video_received_ns << ',' << r.video_decoded_ns << ','
        << r.model_reconstructed_ns << ',' << r.model_published_ns << "\n";
    }
    f.flush();
    if (!f) {
      std::error_code ec;
      std::filesystem::remove(tmp, ec);
      throw std::runtime_error(path + ": write failed");
    }
  }
  commit_file(tmp, path);
}

std::vector<LatencyRecord> LatencyRecorder::read_csv(const std::string& path) {
  std::ifstream f(path);
  if (!f) throw std::runtime_error(path + ": cannot open");
  std::string line;
  if (!std::getline(f, line) || line != kCsvHeader)
    throw std::runtime_error(path + ":1: expected header '" + std::string(kCsvHeader) + "'");
  std::vector<LatencyRecord> out;
  int line_no = 1;
  while (std::getline(f, line)) {
    ++line_no;
    if (line.empty()) continue;
    int64_t v[kCsvColumns];
    std::size_t pos = 0;
    for (int c = 0; c < kCsvColumns; ++c) {
      const std::size_t end = line.find(',', pos);
      const std::string cell =
          line.substr(pos, end == std::string::npos ? std::string::npos : end - pos);
      char* stop = nullptr;
      errno = 0;
      v[c] = std::strtoll(cell.c_str(), &stop, 10);
      if (cell.empty() || *stop != '\0' || errno != 0 ||
          ((c == 3 || c == 9) && v[c] != 0 && v[c] != 1))
        throw std::runtime_error(path + ":" + std::to_string(line_no) + ": column " +
                                 std::to_string(c + 1) + " is not a valid integer");
      if ((end == std::string::npos) != (c == kCsvColumns - 1))
        throw std::runtime_error(path + ":" + std::to_string(line_no) + ": expected " +
                                 std::to_string(kCsvColumns) + " columns");
      pos = end + 1;
    }
    LatencyRecord r;
    r.frame = static_cast<uint64_t>(v[0]);
    r.pose_sample_ns = v[1];
    r.video_ns = v[2];
    r.video_is_exposure = v[3] != 0;
    r.texture_update_ns = v[4];
    r.render_start_ns = v[5];
    r.render_end_ns = v[6];
    r.swap_ns = v[7];
    r.predicted_display_ns = v[8];
    r.missed_deadline = v[9] != 0;
    r.model_capture_ns = v[10];
    r.video_encoded_ns = v[11];
    r.video_sent_ns = v[12];
    r.video_received_ns = v[13];
    r.video_decoded_ns = v[14];
    r.model_reconstructed_ns = v[15];
    r.model_published_ns = v[16];
    out.push_back(r);
  }
  return out;
}

void LatencyRecorder::write_png(const std::string& path) const {
  constexpr int kW = 1400, kH = 560;
  cv::Mat img(kH, kW, CV_8UC3, cv::Scalar(255, 255, 255));
  const cv::Scalar black(0, 0, 0), grey(200, 200, 200);
  const cv::Scalar colours[3] = {cv::Scalar(200, 80, 0), cv::Scalar(0, 140, 0),
                                 cv::Scalar(0, 0, 210)};
  const LatencyMetric metrics[3] = {LatencyMetric::kMotionToSwap, LatencyMetric::kMotionToDisplay,
                                    LatencyMetric::kVideoAge};
  const char* names[3] = {"motion-to-photon (swap)", "motion-to-photon (predicted display)",
                          "video age"};
  const int font = cv::FONT_HERSHEY_SIMPLEX;

  double y_max_ms = 1.0;
  for (auto m : metrics) y_max_ms = std::max(y_max_ms, stats(m).max_ms);
  y_max_ms *= 1.1;
  const std::size_t n = std::max<std::size_t>(count_, 1);
  const uint64_t first_frame = count_ ? at(0).frame : 0;

  // Left panel: latency over time.
  const cv::Rect L(90, 50, 800, 430);
  cv::rectangle(img, L, black, 1);
  for (int k = 0; k <= 5; ++k) {
    const int y = L.y + L.height - k * L.height / 5;
    cv::line(img, {L.x, y}, {L.x + L.width, y}, grey, 1);
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.1f", y_max_ms * k / 5);
    cv::putText(img, buf, {L.x - 60, y + 5}, font, 0.45, black, 1, cv::LINE_AA);
    const int x = L.x + k * L.width / 5;
    std::snprintf(buf, sizeof buf, "%" PRIu64,
                  first_frame + static_cast<uint64_t>((n - 1) * k / 5));
    cv::putText(img, buf, {x - 15, L.y + L.height + 20}, font, 0.45, black, 1, cv::LINE_AA);
  }
  cv::putText(img, "frame", {L.x + L.width / 2 - 25, L.y + L.height + 45}, font, 0.55, black, 1,
              cv::LINE_AA);
  cv::putText(img, "latency [ms]", {10, L.y - 15}, font, 0.55, black, 1, cv::LINE_AA);
  cv::putText(img, "Latency over time", {L.x + 250, 25}, font, 0.7, black, 2, cv::LINE_AA);
  for (int mi = 0; mi < 3; ++mi) {
    cv::Point prev(-1, -1);
    for (std::size_t i = 0; i < count_; ++i) {
      int64_t v = 0;
      if (!latency_of(at(i), metrics[mi], v)) {
        prev = {-1, -1};
        continue;
      }
      const cv::Point p(
          L.x + static_cast<int>(static_cast<double>(i) /
                                 static_cast<double>(std::max<std::size_t>(n - 1, 1)) * L.width),
          L.y + L.height - static_cast<int>(v * 1e-6 / y_max_ms * L.height));
      if (prev.x >= 0) cv::line(img, prev, p, colours[mi], 1, cv::LINE_AA);
      prev = p;
    }
  }
  cv::rectangle(img, {L.x + 5, L.y + 5}, {L.x + 360, L.y + 70}, cv::Scalar(255, 255, 255),
                cv::FILLED);
  for (int mi = 0; mi < 3; ++mi) {
    cv::line(img, {L.x + 10, L.y + 15 + 20 * mi}, {L.x + 40, L.y + 15 + 20 * mi}, colours[mi], 2);
    cv::putText(img, names[mi], {L.x + 48, L.y + 20 + 20 * mi}, font, 0.45, black, 1, cv::LINE_AA);
  }

  // Right panel: histogram of motion-to-photon at the predicted display time.
  const cv::Rect R(1000, 50, 370, 430);
  cv::rectangle(img, R, black, 1);
  constexpr int kBins = 30;
  std::array<int, kBins> bins{};
  const LatencyStats sd = stats(LatencyMetric::kMotionToDisplay);
  const double h_max_ms = std::max(sd.max_ms * 1.05, 1.0);
  for (std::size_t i = 0; i < count_; ++i) {
    int64_t v = 0;
    if (!latency_of(at(i), LatencyMetric::kMotionToDisplay, v)) continue;
    bins[std::clamp(static_cast<int>(v * 1e-6 / h_max_ms * kBins), 0, kBins - 1)]++;
  }
  const int peak = std::max(1, *std::max_element(bins.begin(), bins.end()));
  for (int b = 0; b < kBins; ++b) {
    const int x0 = R.x + b * R.width / kBins, x1 = R.x + (b + 1) * R.width / kBins - 1;
    const int h = bins[b] * R.height / peak;
    cv::rectangle(img, {x0, R.y + R.height - h}, {x1, R.y + R.height}, colours[1], cv::FILLED);
  }
  for (int k = 0; k <= 4; ++k) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.1f", h_max_ms * k / 4);
    cv::putText(img, buf, {R.x + k * R.width / 4 - 12, R.y + R.height + 20}, font, 0.45, black, 1,
                cv::LINE_AA);
    std::snprintf(buf, sizeof buf, "%d", peak * k / 4);
    cv::putText(img, buf, {R.x - 40, R.y + R.height - k * R.height / 4 + 5}, font, 0.45, black, 1,
                cv::LINE_AA);
  }
  cv::putText(img, "motion-to-photon (display) [ms]", {R.x + 40, R.y + R.height + 45}, font, 0.55,
              black, 1, cv::LINE_AA);
  cv::putText(img, "frames", {R.x - 45, R.y - 15}, font, 0.55, black, 1, cv::LINE_AA);
  cv::putText(img, "Histogram", {R.x + 120, 25}, font, 0.7, black, 2, cv::LINE_AA);
  char summary[160];
  std::snprintf(summary, sizeof summary,
                "%zu frames, p50 %.2f  p95 %.2f  p99 %.2f  max %.2f ms, missed %" PRIu64, count_,
                sd.p50_ms, sd.p95_ms, sd.p99_ms, sd.max_ms, missed_);
  cv::putText(img, summary, {L.x, kH - 12}, font, 0.5, black, 1, cv::LINE_AA);
  // A network camera's video: its link stage by stage, p50 of each.
  const LatencyMetric stages[5] = {LatencyMetric::kLinkEncode, LatencyMetric::kLinkSend,
                                   LatencyMetric::kLinkNetwork, LatencyMetric::kLinkDecode,
                                   LatencyMetric::kLinkShow};
  LatencyStats st[5];
  for (int i = 0; i < 5; ++i) st[i] = stats(stages[i]);
  if (st[0].count > 0) {
    char link[200];
    std::snprintf(link, sizeof link,
                  "network video, p50 ms: capture -%.1f- encode -%.1f- send -%.1f- receive "
                  "-%.1f- decode -%.1f- shown (%zu frames)",
                  st[0].p50_ms, st[1].p50_ms, st[2].p50_ms, st[3].p50_ms, st[4].p50_ms,
                  st[0].count);
    cv::rectangle(img, {L.x + 5, L.y + 75}, {L.x + L.width - 5, L.y + 95},
                  cv::Scalar(255, 255, 255), cv::FILLED);
    cv::putText(img, link, {L.x + 10, L.y + 90}, font, 0.42, colours[2], 1, cv::LINE_AA);
  }
  // An updated model: its stages, p50 of each (reconstruction only over updates that had one).
  const LatencyStats recon = stats(LatencyMetric::kModelReconstruct),
                     in_model = stats(LatencyMetric::kModelPublish),
                     shown = stats(LatencyMetric::kModelAge);
  if (in_model.count > 0) {
    char line[200];
    if (recon.count > 0)
      std::snprintf(line, sizeof line,
                    "model, p50 ms after capture: reconstructed %.0f, in the model %.0f, shown "
                    "%.0f (%zu frames)",
                    recon.p50_ms, in_model.p50_ms, shown.p50_ms, in_model.count);
    else
      std::snprintf(line, sizeof line,
                    "model, p50 ms after capture: in the model %.0f, shown %.0f (%zu frames)",
                    in_model.p50_ms, shown.p50_ms, in_model.count);
    cv::rectangle(img, {L.x + 5, L.y + 97}, {L.x + L.width - 5, L.y + 117},
                  cv::Scalar(255, 255, 255), cv::FILLED);
    cv::putText(img, line, {L.x + 10, L.y + 112}, font, 0.42, black, 1, cv::LINE_AA);
  }

  // imwrite picks the encoder from the extension, so the temp name keeps ".png".
  const std::string tmp = path + ".tmp.png";
  bool ok = false;
  try {
    ok = cv::imwrite(tmp, img);
  } catch (const cv::Exception&) {
    ok = false;
  }
  if (!ok) {
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
    throw std::runtime_error(path + ": cannot write PNG");
  }
  commit_file(tmp, path);
}

}  // namespace hd::render

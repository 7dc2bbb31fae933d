#include "station/app/frame_recorder.h"

#include <cinttypes>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <stdexcept>

#include "station/app/output_file.h"

namespace hd::station {

FrameRecorder::FrameRecorder(int width, int height, FrameRecorderOptions options)
    : options_(std::move(options)), slots_(kSlots) {
  for (uint32_t i = 0; i < slots_.size(); ++i) {
    slots_[i].image.allocate(width, height);
    free_.push(i);
  }
  if (!options_.video_path.empty()) {
    // The temp name keeps the .avi suffix: OpenCV picks the container from it.
    video_tmp_ = options_.video_path + ".tmp.avi";
    // OpenCV's own MJPG-in-AVI writer: no GStreamer/FFmpeg plug-in needed, same on every machine.
    const bool ok =
        video_.open(video_tmp_, cv::CAP_OPENCV_MJPEG, cv::VideoWriter::fourcc('M', 'J', 'P', 'G'),
                    options_.video_fps, cv::Size(width, height), true);
    if (!ok) {
      std::error_code ec;
      std::filesystem::remove(video_tmp_, ec);
      throw std::runtime_error(options_.video_path +
                               ": cannot open a MJPG video writer (OpenCV videoio)");
    }
  }
  thread_ = std::thread([this] { run(); });
}

FrameRecorder::~FrameRecorder() {
  try {
    finish();
  } catch (...) {
    // A destructor must not throw; finish() reports failures through stats().error.
  }
}

void FrameRecorder::offer(const render::ImageRgba8& image, const FrameMeta& meta) {
  const bool video = video_.isOpened();
  const bool png = options_.png_every > 0 && meta.frame % options_.png_every == 0;
  const bool thumb = options_.thumbnails && options_.thumbnails->wants(meta.frame);
  if (!video && !png && !thumb) return;
  uint32_t i = 0;
  if (!free_.pop(i)) {
    dropped_.fetch_add(1, std::memory_order_relaxed);
    return;
  }
  Slot& s = slots_[i];
  if (s.image.width == image.width && s.image.height == image.height)
    std::memcpy(s.image.data.data(), image.data.data(), image.data.size());
  s.meta = meta;
  s.video = video;
  s.png = png;
  s.thumb = thumb;
  filled_.push(i);
}

void FrameRecorder::run() {
  for (;;) {
    uint32_t i = 0;
    if (filled_.pop(i)) {
      write(slots_[i]);
      free_.push(i);
      continue;
    }
    if (!running_.load(std::memory_order_acquire)) {
      // Stopped: take what was pushed before the flag flipped, then leave.
      if (!filled_.pop(i)) break;
      write(slots_[i]);
      free_.push(i);
      continue;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
}

void FrameRecorder::write(Slot& s) {
  try {
    if (s.video) {
      rgba_to_bgr(s.image, bgr_);
      video_.write(bgr_);
      ++stats_.video_frames;
    }
    if (s.png) {
      char name[48];
      std::snprintf(name, sizeof name, "/frame_%06" PRIu64 ".png", s.meta.frame);
      rgba_to_bgr(s.image, bgr_);
      write_png_atomically(bgr_, options_.png_dir + name);
      ++stats_.png_frames;
    }
    if (s.thumb) {
      options_.thumbnails->add(s.image, s.meta);
      ++stats_.thumbnails;
    }
  } catch (const std::exception& e) {
    if (stats_.error.empty()) stats_.error = e.what();
  }
}

FrameRecorderStats FrameRecorder::finish() {
  if (finished_) return stats_;
  finished_ = true;
  running_.store(false, std::memory_order_release);
  if (thread_.joinable()) thread_.join();
  stats_.dropped = dropped_.load(std::memory_order_relaxed);
  if (video_.isOpened()) {
    video_.release();
    std::error_code ec;
    std::filesystem::rename(video_tmp_, options_.video_path, ec);
    if (ec) {
      std::filesystem::remove(video_tmp_, ec);
      if (stats_.error.empty())
        stats_.error = options_.video_path + ": cannot rename the temp file into place";
    }
  }
  return stats_;
}

}  // namespace hd::station

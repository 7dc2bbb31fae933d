#pragma once
// Pictures leave the render thread through a preallocated ring to a writer thread that encodes
// the video, the PNG frames and the contact-sheet candidates, so encoding never delays a frame.

#include <atomic>
#include <cstdint>
#include <memory>
#include <opencv2/core.hpp>
#include <opencv2/videoio.hpp>
#include <string>
#include <thread>
#include <vector>

#include "drivers/spsc_ring.h"
#include "render/compositor/image_rgba8.h"
#include "station/app/contact_sheet.h"

namespace hd::station {

struct FrameRecorderOptions {
  std::string video_path;  ///< "" = no video; else MJPG in an AVI at `video_fps`
  double video_fps = 90.0;
  uint64_t png_every = 0;  ///< 0 = none; else frame_NNNNNN.png every N frames in `png_dir`
  std::string png_dir;
  ThumbnailSet* thumbnails = nullptr;  ///< contact-sheet candidates (owned by the caller)
};

/// What the writer did (read after finish()).
struct FrameRecorderStats {
  uint64_t video_frames = 0;  ///< frames in the video file
  uint64_t png_frames = 0;
  uint64_t thumbnails = 0;
  uint64_t dropped = 0;  ///< frames the writer could not take in time (ring full), never written
  std::string error;     ///< the first write failure, "" if none
};

class FrameRecorder {
 public:
  /// Sizes the ring for `width` x `height` pictures and starts the writer. The video goes to a
  /// temp file renamed into place by finish(). Throws std::runtime_error naming the video file
  /// when it cannot be opened.
  FrameRecorder(int width, int height, FrameRecorderOptions options);
  ~FrameRecorder();  ///< finish()
  FrameRecorder(const FrameRecorder&) = delete;
  FrameRecorder& operator=(const FrameRecorder&) = delete;

  /// Render thread, once per frame: copies the picture into a free slot if this frame is wanted
  /// by the video, a PNG or the contact sheet. Never allocates, locks or blocks; a full ring
  /// drops the frame (counted).
  void offer(const render::ImageRgba8& image, const FrameMeta& meta);

  /// Drains the ring, joins the writer and closes the video (renamed into place). Idempotent.
  FrameRecorderStats finish();

 private:
  struct Slot {
    render::ImageRgba8 image;
    FrameMeta meta;
    bool video = false, png = false, thumb = false;
  };
  static constexpr std::size_t kSlots = 16;

  void run();
  void write(Slot& slot);

  FrameRecorderOptions options_;
  std::vector<Slot> slots_;
  drivers::SpscRing<uint32_t, 32> free_;
  drivers::SpscRing<uint32_t, 32> filled_;
  cv::VideoWriter video_;
  std::string video_tmp_;
  cv::Mat bgr_;
  std::atomic<bool> running_{true};
  std::atomic<uint64_t> dropped_{0};
  FrameRecorderStats stats_;
  bool finished_ = false;
  std::thread thread_;
};

}  // namespace hd::station

#pragma once
// One frame of a run: the station frame (allocations counted after warm-up), its row logged and
// its picture handed to the recorder -- both into storage sized before the loop.

#include <cstdint>

#include "render/latency/latency_recorder.h"
#include "station/app/frame_log.h"
#include "station/app/frame_recorder.h"
#include "station/frame/station_frame.h"

namespace hd::station {

class RunWork final : public render::FrameWork {
 public:
  RunWork(station::StationFrame& frame, render::LatencyRecorder& latency, FrameLog& log,
          FrameRecorder& recorder, uint64_t warmup_frames)
      : frame_(frame), latency_(latency), log_(log), recorder_(recorder), warmup_(warmup_frames) {}

  void tick(const render::FrameTiming& t) override;

 private:
  station::StationFrame& frame_;
  render::LatencyRecorder& latency_;
  FrameLog& log_;
  FrameRecorder& recorder_;
  uint64_t warmup_;
  int64_t first_start_ns_ = 0;
};

}  // namespace hd::station

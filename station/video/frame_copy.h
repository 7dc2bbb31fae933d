#pragma once
// Checking and copying RGBA8 frames on the per-frame path (no allocation).

#include "drivers/frame.h"

namespace hd::station {

/// True when `f` is an RGBA8 frame of exactly w x h whose stride and buffer hold every row.
bool is_rgba_frame(const drivers::Frame& f, int w, int h);

/// Copies sequence, timestamps, trust flag, link stages and calibration (not pixels) from `src`
/// to `dst`.
void copy_frame_stamps(const drivers::Frame& src, drivers::Frame& dst);

/// Copies pixels and stamps of `src` into `dst` (both RGBA8 of the same size; strides may
/// differ) row by row without allocating. Returns false, leaving `dst` untouched, on a mismatch.
bool copy_frame(const drivers::Frame& src, drivers::Frame& dst);

}  // namespace hd::station

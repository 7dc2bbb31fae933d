// hybrid-bench-model: what the delayed model and the video pipeline cost, each beside a peer
// measured in the same run.
//  - Texture extraction of the default scene's model from both cameras' frames (the work of one
//    model update), from one camera, and the one-off texel mapping (prepare), beside a bare
//    CpuCompositor render of camera 0's view of the same model (the peer: one frame of the CPU
//    station's synthetic view).
//  - Undistortion of a 640 x 480 RGBA frame with the pipeline's fixed-point kernel, beside
//    cv::remap on the same maps (which allocates on every call) and a plain frame copy (the cost
//    of a camera without distortion).
//
//   build/bin/hybrid-bench-model --benchmark_min_time=0.5
#include <benchmark/benchmark.h>

#include <filesystem>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "core/opencv_pixels.h"
#include "render/compositor/cpu_compositor.h"
#include "sim/scene/scene_file.h"
#include "sim/simulation.h"
#include "station/model/texture_extractor.h"
#include "station/video/frame_copy.h"
#include "station/video/undistorter.h"

namespace {

using namespace hd::station;
using namespace hd::render;
using namespace hd::sim;
namespace core = hd::core;
namespace drivers = hd::drivers;

Scene default_scene() {
  // From the checkout the program was built from: __FILE__ is relative to the build folder
  // under ccache's base directory (scripts/test.sh), so it cannot be trusted from elsewhere.
  return load_scene((std::filesystem::path(HD_SOURCE_DIR) / "scenes" / "default.yaml").string());
}

// One frame of every camera of the default scene at t ~ 5 s (the block is being carried).
struct DefaultSetup {
  Simulation sim{default_scene()};
  std::vector<drivers::Frame> frames;
  std::vector<ExtractionView> views;
  DefaultSetup() {
    const std::size_t n = sim.camera_count();
    frames.resize(n);
    for (std::size_t c = 0; c < n; ++c) {
      const SceneCamera& cam = sim.scene().cameras[c];
      sim.render_frame(c, static_cast<uint64_t>(5.0 * cam.rate_hz), frames[c]);
    }
    for (std::size_t c = 0; c < n; ++c) {
      core::Pinhole k = sim.scene().cameras[c].p_c;
      k.distortion_count = 0;  // the pipeline hands the model undistorted frames
      views.push_back({&frames[c], k, sim.scene().cameras[c].T_world_cam});
    }
  }
};

void BM_ExtractDefaultScene(benchmark::State& state) {
  DefaultSetup s;
  const std::size_t cams = static_cast<std::size_t>(state.range(0));
  SyntheticScene model = s.sim.model();
  TextureExtractor ex;
  ex.prepare(model);
  for (auto _ : state) {
    ex.extract(model, std::span(s.views.data(), cams));
    benchmark::DoNotOptimize(model.meshes.data());
  }
  state.counters["texels_mapped"] = static_cast<double>(ex.last_stats().texels_mapped);
  state.counters["texels_updated"] = static_cast<double>(ex.last_stats().texels_updated);
  state.counters["cameras"] = static_cast<double>(cams);
}
BENCHMARK(BM_ExtractDefaultScene)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);

void BM_PrepareDefaultScene(benchmark::State& state) {
  DefaultSetup s;
  const SyntheticScene& model = s.sim.model();
  for (auto _ : state) {
    TextureExtractor ex;
    ex.prepare(model);
    benchmark::DoNotOptimize(&ex);
  }
}
BENCHMARK(BM_PrepareDefaultScene)->Unit(benchmark::kMillisecond);

// The peer: one CPU render of camera 0's view of the same model.
void BM_BareRenderCamera0(benchmark::State& state) {
  DefaultSetup s;
  const core::Pinhole& k = s.views[0].p_c;
  CpuCompositor cpu;
  ImageRgba8 out;
  out.allocate(k.width, k.height);
  CompositeRequest req;
  req.scene = &s.sim.model();
  req.eye = k;
  req.T_world_eye = s.views[0].T_world_cam;
  req.marking.style = core::MarkingStyle::kNone;
  req.viewport = {0, 0, k.width, k.height};
  for (auto _ : state) {
    cpu.draw(req, out);
    benchmark::DoNotOptimize(out.data.data());
  }
}
BENCHMARK(BM_BareRenderCamera0)->Unit(benchmark::kMillisecond);

core::Pinhole distorted_640x480() {
  core::Pinhole p = core::Pinhole::centred(420, 640, 480);
  p.distortion = {-0.12, 0.03, 0.0, 0.0, 0.0};
  p.distortion_count = 5;
  return p;
}

drivers::Frame noise_frame(int w, int h) {
  drivers::Frame f;
  f.allocate_rgba(w, h);
  uint32_t x = 12345;
  for (auto& b : f.data) {
    x = x * 1664525u + 1013904223u;
    b = static_cast<uint8_t>(x >> 24);
  }
  return f;
}

void BM_UndistortFixedPoint(benchmark::State& state) {
  const core::Pinhole p = distorted_640x480();
  const Undistorter u(p);
  const drivers::Frame src = noise_frame(p.width, p.height);
  drivers::Frame dst;
  dst.allocate_rgba(p.width, p.height);
  for (auto _ : state) {
    u.apply(src, dst);
    benchmark::DoNotOptimize(dst.data.data());
  }
}
BENCHMARK(BM_UndistortFixedPoint)->Unit(benchmark::kMicrosecond);

void BM_UndistortCvRemap(benchmark::State& state) {
  const core::Pinhole p = distorted_640x480();
  const core::OpenCvIntrinsics o = core::to_opencv(p);
  const cv::Matx33d K(o.fx, 0, o.cx, 0, o.fy, o.cy, 0, 0, 1);
  const cv::Mat D = (cv::Mat_<double>(1, 5) << p.distortion[0], p.distortion[1], 0, 0, 0);
  cv::Mat m1, m2;
  cv::initUndistortRectifyMap(K, D, cv::noArray(), K, {p.width, p.height}, CV_16SC2, m1, m2);
  drivers::Frame src = noise_frame(p.width, p.height);
  drivers::Frame dst;
  dst.allocate_rgba(p.width, p.height);
  const cv::Mat s(p.height, p.width, CV_8UC4, src.data.data());
  cv::Mat d(p.height, p.width, CV_8UC4, dst.data.data());
  for (auto _ : state) {
    cv::remap(s, d, m1, m2, cv::INTER_LINEAR, cv::BORDER_CONSTANT);
    benchmark::DoNotOptimize(dst.data.data());
  }
  state.counters["cv_threads"] = cv::getNumThreads();
}
BENCHMARK(BM_UndistortCvRemap)->Unit(benchmark::kMicrosecond);

void BM_CopyFrame(benchmark::State& state) {
  const drivers::Frame src = noise_frame(640, 480);
  drivers::Frame dst;
  dst.allocate_rgba(640, 480);
  for (auto _ : state) {
    copy_frame(src, dst);
    benchmark::DoNotOptimize(dst.data.data());
  }
}
BENCHMARK(BM_CopyFrame)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();

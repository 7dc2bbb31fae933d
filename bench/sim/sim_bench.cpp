// hybrid-bench-sim: what the simulator's effects cost. Frame generation of the default scene's
// camera 0 (640 x 480) with an empty effects list, beside the bare CpuCompositor render of the
// same view (the peer: an empty list must cost no more), then each effect alone, then the
// per-frame timing and per-sample tracker effects.
//
//   build/bin/hybrid-bench-sim --benchmark_min_time=0.5
#include <benchmark/benchmark.h>

#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include "render/compositor/cpu_compositor.h"
#include "sim/scene/scene_file.h"
#include "sim/sim_camera_renderer.h"
#include "sim/simulation.h"

namespace {

using namespace hd::sim;
using namespace hd::render;

Scene bare_scene() {
  // From the checkout the program was built from: __FILE__ is relative to the build folder
  // under ccache's base directory (scripts/test.sh), so it cannot be trusted from elsewhere.
  return load_scene((std::filesystem::path(HD_SOURCE_DIR) / "scenes" / "bare.yaml").string());
}

// The peer: one CpuCompositor draw of camera 0's view of the model.
void BM_BareCpuCompositorRender(benchmark::State& state) {
  Simulation sim(bare_scene());
  const SceneCamera& cam = sim.scene().cameras[0];
  CpuCompositor cpu;
  ImageRgba8 out;
  out.allocate(cam.p_c.width, cam.p_c.height);
  CompositeRequest req;
  req.scene = &sim.model();
  req.eye = cam.p_c;
  req.T_world_eye = cam.T_world_cam;
  req.marking.style = hd::core::MarkingStyle::kNone;
  req.viewport = {0, 0, cam.p_c.width, cam.p_c.height};
  for (auto _ : state) {
    cpu.draw(req, out);
    benchmark::DoNotOptimize(out.data.data());
  }
}
BENCHMARK(BM_BareCpuCompositorRender)->Unit(benchmark::kMillisecond);

// A simulated frame with the effects `configure` lists (none: the empty list).
template <typename Configure>
void frame_bench(benchmark::State& state, Configure configure) {
  Scene scene = bare_scene();
  configure(scene.effects);
  Simulation sim(std::move(scene));
  SimCameraRenderer renderer(sim, 0);
  hd::drivers::Frame frame;
  uint64_t seq = 0;
  for (auto _ : state) {
    frame.sequence = seq;
    renderer.render(frame, static_cast<double>(seq++) / 30.0);
    benchmark::DoNotOptimize(frame.data.data());
  }
}

void BM_SimFrame_EmptyList(benchmark::State& s) {
  frame_bench(s, [](SceneEffects&) {});
}
void BM_SimFrame_SensorNoise(benchmark::State& s) {
  frame_bench(s, [](SceneEffects& e) { e.sensor_noise = SensorNoiseEffect{2.0, 1}; });
}
void BM_SimFrame_Exposure(benchmark::State& s) {
  frame_bench(s, [](SceneEffects& e) { e.exposure = ExposureEffect{1.2, -10}; });
}
void BM_SimFrame_LensDistortion(benchmark::State& s) {
  frame_bench(s, [](SceneEffects& e) { e.lens_distortion = LensDistortionEffect{}; });
}
void BM_SimFrame_MotionBlur4(benchmark::State& s) {
  frame_bench(s, [](SceneEffects& e) { e.motion_blur = MotionBlurEffect{12.0, 4}; });
}
void BM_SimFrame_RollingShutter16(benchmark::State& s) {
  frame_bench(s, [](SceneEffects& e) { e.rolling_shutter = RollingShutterEffect{15.0, 16}; });
}
void BM_SimFrame_DelayDropsStaleness(benchmark::State& s) {
  // Timing effects act in the device thread, not on pixels: the frame costs the same.
  frame_bench(s, [](SceneEffects& e) {
    e.camera_delay = DelayEffect{30, 5, 3};
    e.network_delay = DelayEffect{10, 3, 4};
    e.dropped_frames = DroppedFramesEffect{0.05, 2};
    e.model_staleness = ModelStalenessEffect{2, 0.3};
  });
}
BENCHMARK(BM_SimFrame_EmptyList)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SimFrame_SensorNoise)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SimFrame_Exposure)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SimFrame_LensDistortion)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SimFrame_MotionBlur4)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SimFrame_RollingShutter16)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SimFrame_DelayDropsStaleness)->Unit(benchmark::kMillisecond);

void BM_FrameTiming(benchmark::State& state) {
  Scene scene = bare_scene();
  scene.effects.camera_delay = DelayEffect{30, 5, 3};
  scene.effects.network_delay = DelayEffect{10, 3, 4};
  scene.effects.dropped_frames = DroppedFramesEffect{0.05, 2};
  Simulation sim(std::move(scene));
  uint64_t seq = 0;
  for (auto _ : state) benchmark::DoNotOptimize(sim.frame_timing(0, seq++));
}
BENCHMARK(BM_FrameTiming);

template <typename Configure>
void head_bench(benchmark::State& state, Configure configure) {
  Scene scene = bare_scene();
  configure(scene.effects);
  Simulation sim(std::move(scene));
  uint64_t seq = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(sim.head_sample(static_cast<double>(seq) * 0.002, seq));
    ++seq;
  }
}
void BM_HeadSample_NoEffects(benchmark::State& s) {
  head_bench(s, [](SceneEffects&) {});
}
void BM_HeadSample_NoiseAndDrift(benchmark::State& s) {
  head_bench(s, [](SceneEffects& e) {
    e.tracker_noise = TrackerNoiseEffect{};
    e.tracker_drift = TrackerDriftEffect{};
  });
}
BENCHMARK(BM_HeadSample_NoEffects);
BENCHMARK(BM_HeadSample_NoiseAndDrift);

}  // namespace

BENCHMARK_MAIN();

// Each simulated effect changes exactly what it claims, measured against expectations computed
// independently (closed forms, OpenCV's projectPoints, a plain CpuCompositor render, binomial
// bounds), and nothing else.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <opencv2/calib3d.hpp>
#include <set>

#include "render/compositor/cpu_compositor.h"
#include "sim/scene/scene_file.h"
#include "sim/sim_camera_renderer.h"
#include "sim/simulation.h"

namespace hd::sim {
namespace {

// A small, fast camera (160 x 120) looking at a checker wall 2 m away, a box sliding across it
// from x = -0.4 (t = 0) to 0.4 (t = 1 s), and a small bright square (a "dot") off-centre.
std::string scene_text(const std::string& effects, const std::string& distortion = "") {
  return "workspace: {min: [-1, -1, 0.5], max: [1, 1, 2]}\n"
         "background: [20, 20, 20]\n"
         "geometry:\n"
         "  - {shape: quad, center: [0, 0, 2], size: [3, 2],\n"
         "     texture: {colors: [[150, 120, 90], [90, 110, 140]], cell_m: 0.1}}\n"
         "  - {shape: quad, center: [0.5, 0.35, 1], size: [0.06, 0.06],\n"
         "     texture: {colors: [[250, 250, 250], [250, 250, 250]]}}\n"
         "objects:\n"
         "  - name: box\n"
         "    shape: box\n"
         "    size: [0.2, 0.2, 0.2]\n"
         "    texture: {colors: [[200, 40, 40], [200, 40, 40]]}\n"
         "    keyframes: [{t: 0, position: [-0.4, 0, 1.5]}, {t: 1, position: [0.4, 0, 1.5]}]\n"
         "cameras:\n"
         "  - name: c0\n"
         "    rate_hz: 50\n"
         "    d_m: 2\n"
         "    intrinsics: {fx: 100, fy: 100, cx: 80, cy: 60, width: 160, height: 120}\n" +
         distortion +
         "    pose: {position: [0, 0, 0]}\n"
         "head:\n"
         "  keyframes: [{t: 0, position: [0, 0, 0]}, {t: 10, position: [0.5, 0, 0], ypr_deg: [20, "
         "0, 0]}]\n"
         "  smooth: false\n" +
         (effects.empty() ? "" : "effects:\n" + effects);
}

/// The same with the box standing still at x = -0.4.
std::string still_scene_text(const std::string& effects) {
  std::string text = scene_text(effects);
  const std::string moving = ", {t: 1, position: [0.4, 0, 1.5]}";
  text.erase(text.find(moving), moving.size());
  return text;
}

Scene scene_with(const std::string& effects, const std::string& distortion = "") {
  return parse_scene(scene_text(effects, distortion), "effects_test.yaml");
}

drivers::Frame render(Simulation& sim, uint64_t sequence) {
  drivers::Frame f;
  sim.render_frame(0, sequence, f);
  return f;
}

// ---- no effects ----

TEST(SimEffects, EmptyListIsExactlyAPlainCpuCompositorRender) {
  Simulation sim(scene_with(""));
  const drivers::Frame f = render(sim, 0);  // t = 0: the model as built
  render::CpuCompositor cpu;
  render::ImageRgba8 expected;
  const SceneCamera& cam = sim.scene().cameras[0];
  expected.allocate(cam.p_c.width, cam.p_c.height);
  render::CompositeRequest req;
  req.scene = &sim.model();
  req.eye = cam.p_c;
  req.T_world_eye = cam.T_world_cam;
  req.marking.style = core::MarkingStyle::kNone;
  req.viewport = {0, 0, cam.p_c.width, cam.p_c.height};
  cpu.draw(req, expected);
  ASSERT_EQ(f.data.size(), expected.data.size());
  EXPECT_TRUE(f.data == expected.data);
  EXPECT_EQ(f.host_timestamp_ns, 0);
  // Not a blank picture: the wall, the box and the dot are all there.
  std::set<uint32_t> colours;
  for (std::size_t i = 0; i < f.data.size(); i += 4)
    colours.insert(f.data[i] << 16 | f.data[i + 1] << 8 | f.data[i + 2]);
  EXPECT_GT(colours.size(), 4u);
}

// ---- delays ----

TEST(SimEffects, DelayShiftsDeliveryByTheMeanAndNothingElse) {
  Simulation plain(scene_with(""));
  Simulation delayed(scene_with("  - camera_delay: {mean_ms: 30, jitter_ms: 5, seed: 9}\n"));
  constexpr int kN = 4000;
  double sum = 0, sum2 = 0;
  for (uint64_t s = 0; s < kN; ++s) {
    const SimFrameTiming a = plain.frame_timing(0, s);
    const SimFrameTiming b = delayed.frame_timing(0, s);
    EXPECT_EQ(a.delivery_delay_ns, 0);
    ASSERT_EQ(a.exposure_offset_ns, b.exposure_offset_ns);
    ASSERT_EQ(b.exposure_offset_ns, static_cast<int64_t>(s) * 20'000'000);  // 50 Hz grid
    EXPECT_FALSE(b.dropped);
    const double ms = b.delivery_delay_ns * 1e-6;
    sum += ms;
    sum2 += ms * ms;
  }
  const double mean = sum / kN;
  const double sd = std::sqrt(sum2 / kN - mean * mean);
  EXPECT_NEAR(mean, 30.0, 4.5 * 5.0 / std::sqrt(kN));  // 4.5 standard errors
  EXPECT_NEAR(sd, 5.0, 5.0 * 4.5 / std::sqrt(2.0 * kN));
  // Pixels and exposure stamps are untouched.
  for (uint64_t s : {0u, 7u, 31u}) {
    const drivers::Frame a = render(plain, s);
    const drivers::Frame b = render(delayed, s);
    EXPECT_TRUE(a.data == b.data) << s;
    EXPECT_EQ(a.host_timestamp_ns, b.host_timestamp_ns);
  }
}

TEST(SimEffects, CameraAndNetworkDelaysAdd) {
  Simulation sim(
      scene_with("  - camera_delay: {mean_ms: 20, jitter_ms: 2}\n"
                 "  - network_delay: {mean_ms: 15, jitter_ms: 4}\n"));
  constexpr int kN = 4000;
  double sum = 0, sum2 = 0;
  for (uint64_t s = 0; s < kN; ++s) {
    const double ms = sim.frame_timing(0, s).delivery_delay_ns * 1e-6;
    sum += ms;
    sum2 += ms * ms;
  }
  const double mean = sum / kN;
  const double sd_expected = std::sqrt(2.0 * 2.0 + 4.0 * 4.0);  // independent draws
  EXPECT_NEAR(mean, 35.0, 4.5 * sd_expected / std::sqrt(kN));
  EXPECT_NEAR(std::sqrt(sum2 / kN - mean * mean), sd_expected,
              sd_expected * 4.5 / std::sqrt(2.0 * kN));
}

// ---- drops ----

TEST(SimEffects, DropsAtTheSetRateWithinBinomialBounds) {
  Simulation sim(scene_with("  - dropped_frames: {probability: 0.1, seed: 5}\n"));
  constexpr int kN = 20000;
  int dropped = 0;
  int longest_run = 0, run = 0;
  for (uint64_t s = 0; s < kN; ++s) {
    const SimFrameTiming t = sim.frame_timing(0, s);
    EXPECT_EQ(t.delivery_delay_ns, 0);
    dropped += t.dropped;
    run = t.dropped ? run + 1 : 0;
    longest_run = std::max(longest_run, run);
  }
  const double sd = std::sqrt(kN * 0.1 * 0.9);
  EXPECT_NEAR(dropped, 0.1 * kN, 4.5 * sd);
  EXPECT_LT(longest_run, 8);  // independent: P(run of 8 anywhere) ~ 2e4 * 1e-8
  Simulation plain(scene_with(""));
  EXPECT_TRUE(render(sim, 3).data == render(plain, 3).data);
}

// ---- sensor noise ----

TEST(SimEffects, NoiseHasTheSetSigmaAndZeroMeanAndLeavesTimestamps) {
  Simulation plain(scene_with(""));
  Simulation noisy(scene_with("  - sensor_noise: {sigma_dn: 6, seed: 11}\n"));
  double sum = 0, sum2 = 0;
  long n = 0;
  for (uint64_t s : {1u, 2u}) {
    const drivers::Frame a = render(plain, s);
    const drivers::Frame b = render(noisy, s);
    EXPECT_EQ(a.host_timestamp_ns, b.host_timestamp_ns);
    for (std::size_t i = 0; i < a.data.size(); ++i) {
      if (i % 4 == 3) {
        EXPECT_EQ(b.data[i], 255);  // alpha untouched
        continue;
      }
      if (a.data[i] < 40 || a.data[i] > 215) continue;  // away from clipping
      const double d = static_cast<double>(b.data[i]) - a.data[i];
      sum += d;
      sum2 += d * d;
      ++n;
    }
  }
  ASSERT_GT(n, 50000);
  const double mean = sum / n;
  const double sd = std::sqrt(sum2 / n - mean * mean);
  // Rounding to whole DN adds 1/12 DN^2 of variance.
  const double sd_expected = std::sqrt(36.0 + 1.0 / 12.0);
  EXPECT_NEAR(mean, 0.0, 4.5 * sd_expected / std::sqrt(static_cast<double>(n)));
  EXPECT_NEAR(sd, sd_expected, 0.03 * sd_expected);
  // A new draw per frame: two frames of a still view differ.
  Simulation still(parse_scene(still_scene_text("  - sensor_noise: {sigma_dn: 6}\n"), "s.yaml"));
  Simulation still_plain(parse_scene(still_scene_text(""), "s.yaml"));
  ASSERT_TRUE(render(still_plain, 5).data == render(still_plain, 6).data);
  EXPECT_FALSE(render(still, 5).data == render(still, 6).data);
}

// ---- exposure ----

TEST(SimEffects, ExposureIsGainOffsetAndClipPerChannel) {
  Simulation plain(scene_with(""));
  Simulation exposed(scene_with("  - exposure: {gain: 1.5, offset_dn: -20}\n"));
  const drivers::Frame a = render(plain, 4);
  const drivers::Frame b = render(exposed, 4);
  int clipped_high = 0;
  for (std::size_t i = 0; i < a.data.size(); ++i) {
    const double expected =
        i % 4 == 3 ? 255.0 : std::clamp(std::round(1.5 * a.data[i] - 20.0), 0.0, 255.0);
    ASSERT_EQ(b.data[i], expected) << i;
    clipped_high += (i % 4 != 3 && expected == 255.0);
  }
  EXPECT_GT(clipped_high, 0);  // the test covers the clipping
  EXPECT_EQ(a.host_timestamp_ns, b.host_timestamp_ns);
}

// ---- lens distortion ----

// Intensity-weighted centroid (continuous coordinates: pixel centres at +0.5) of pixels brighter
// than `threshold` in the red channel inside a window.
Eigen::Vector2d bright_centroid(const drivers::Frame& f, int x0, int y0, int x1, int y1,
                                int threshold) {
  double sx = 0, sy = 0, sw = 0;
  for (int y = std::max(0, y0); y < std::min(f.height, y1); ++y) {
    for (int x = std::max(0, x0); x < std::min(f.width, x1); ++x) {
      const int r = f.data[static_cast<std::size_t>(y) * f.stride_bytes + 4 * x];
      if (r <= threshold) continue;
      const double w = r - threshold;
      sx += w * (x + 0.5);
      sy += w * (y + 0.5);
      sw += w;
    }
  }
  return {sx / sw, sy / sw};
}

TEST(SimEffects, DistortionMovesADotToWhereProjectPointsSays) {
  const std::string dist = "    distortion: {k1: -0.25, k2: 0.08, p1: 0.002, p2: -0.003}\n";
  Simulation ideal(scene_with("", dist));
  Simulation distorted(scene_with("  - lens_distortion\n", dist));
  const Eigen::Vector3d dot(0.5, 0.35, 1.0);  // camera at the origin, identity pose
  const cv::Matx33d K(100, 0, 80, 0, 100, 60, 0, 0, 1);
  const std::vector<double> D = {-0.25, 0.08, 0.002, -0.003, 0.0};
  std::vector<cv::Point2d> projected;
  cv::projectPoints(std::vector<cv::Point3d>{{dot.x(), dot.y(), dot.z()}}, cv::Vec3d(0, 0, 0),
                    cv::Vec3d(0, 0, 0), K, D, projected);
  const Eigen::Vector2d expected(projected[0].x, projected[0].y);
  const Eigen::Vector2d pinhole(80 + 100 * 0.5, 60 + 100 * 0.35);  // (130, 95)
  ASSERT_GT((expected - pinhole).norm(), 5.0);                     // the lens moves it visibly
  // The dot (near white, 6 x 6 px) is the only thing brighter than 160 in red near those points
  // (the wall behind it is at most 150).
  const drivers::Frame a = render(ideal, 0);
  const drivers::Frame b = render(distorted, 0);
  const Eigen::Vector2d c_ideal = bright_centroid(a, 120, 85, 141, 106, 160);
  const Eigen::Vector2d c_dist = bright_centroid(
      b, static_cast<int>(expected.x()) - 10, static_cast<int>(expected.y()) - 10,
      static_cast<int>(expected.x()) + 11, static_cast<int>(expected.y()) + 11, 160);
  EXPECT_LT((c_ideal - pinhole).norm(), 0.25) << c_ideal.transpose();
  EXPECT_LT((c_dist - expected).norm(), 0.25)
      << c_dist.transpose() << " vs " << expected.transpose();
  // The station is told about the distortion only when the frames carry it.
  EXPECT_EQ(distorted.station_cameras()[0].p_c.distortion_count, 5);
  EXPECT_DOUBLE_EQ(distorted.station_cameras()[0].p_c.distortion[0], -0.25);
  EXPECT_EQ(ideal.station_cameras()[0].p_c.distortion_count, 0);
}

// ---- motion blur and rolling shutter ----

TEST(SimEffects, MotionBlurIsTheAverageOfRendersAcrossTheExposure) {
  Simulation plain(scene_with(""));
  Simulation blurred(scene_with("  - motion_blur: {exposure_ms: 40, samples: 4}\n"));
  SimCameraRenderer sharp(plain, 0);
  SimCameraRenderer blur(blurred, 0);
  const double t = 0.3;
  std::vector<int> sum;
  for (int k = 0; k < 4; ++k) {
    drivers::Frame f;
    f.sequence = 1;
    sharp.render(f, t + 0.040 * (k + 0.5) / 4);
    if (sum.empty()) sum.assign(f.data.size(), 0);
    for (std::size_t i = 0; i < f.data.size(); ++i) sum[i] += f.data[i];
  }
  drivers::Frame b;
  b.sequence = 1;
  blur.render(b, t);
  drivers::Frame single;
  single.sequence = 1;
  sharp.render(single, t);
  int changed = 0;
  for (std::size_t i = 0; i < b.data.size(); ++i) {
    ASSERT_EQ(b.data[i], (sum[i] + 2) / 4) << i;
    changed += b.data[i] != single.data[i];
  }
  EXPECT_GT(changed, 100);  // the box moves 32 mm (about 2 px at 1.5 m) in 40 ms
}

TEST(SimEffects, MotionBlurOfAStillSceneChangesNothing) {
  Simulation blurred(parse_scene(
      still_scene_text("  - motion_blur: {exposure_ms: 40, samples: 4}\n"), "still.yaml"));
  Simulation plain(parse_scene(still_scene_text(""), "still.yaml"));
  EXPECT_TRUE(render(blurred, 3).data == render(plain, 3).data);
}

TEST(SimEffects, RollingShutterExposesEachBandAtItsOwnTime) {
  Simulation plain(scene_with(""));
  Simulation rolling(scene_with("  - rolling_shutter: {readout_ms: 120, bands: 6}\n"));
  SimCameraRenderer sharp(plain, 0);
  SimCameraRenderer rs(rolling, 0);
  const double t = 0.2;
  drivers::Frame b;
  b.sequence = 0;
  rs.render(b, t);
  // Band k covers rows [20k, 20k + 20) and is exposed at t + (20k + 10) * 1 ms.
  int max_diff = 0;
  long differing = 0;
  for (int k = 0; k < 6; ++k) {
    drivers::Frame ref;
    ref.sequence = 0;
    sharp.render(ref, t + (20 * k + 10) * 1e-3);
    for (int y = 20 * k; y < 20 * k + 20; ++y) {
      for (int x = 0; x < 4 * 160; ++x) {
        const std::size_t i = static_cast<std::size_t>(y) * ref.stride_bytes + x;
        const int d = std::abs(static_cast<int>(b.data[i]) - ref.data[i]);
        max_diff = std::max(max_diff, d);
        differing += d != 0;
      }
    }
  }
  // A band is the same view drawn through a pinhole shifted by whole rows: equal up to the
  // rasteriser's rounding at a few edge pixels.
  EXPECT_LE(differing, 40);
  // And it differs from a global shutter: the box is skewed.
  drivers::Frame global;
  global.sequence = 0;
  sharp.render(global, t);
  long vs_global = 0;
  for (std::size_t i = 0; i < b.data.size(); ++i) vs_global += b.data[i] != global.data[i];
  EXPECT_GT(vs_global, 200);
  (void)max_diff;
}

// ---- tracker ----

TEST(SimEffects, TrackerNoiseHasTheSetSigmas) {
  Simulation noisy(scene_with(
      "  - tracker_noise: {position_sigma_m: 0.002, orientation_sigma_deg: 0.5, seed: 3}\n"));
  Simulation clean(scene_with(""));
  constexpr int kN = 20000;
  Eigen::Vector3d sp = Eigen::Vector3d::Zero(), sp2 = sp, sr = sp, sr2 = sp;
  for (int i = 0; i < kN; ++i) {
    const double t = i * 0.0005;
    const drivers::PoseSample a = clean.head_sample(t, static_cast<uint64_t>(i));
    const drivers::PoseSample b = noisy.head_sample(t, static_cast<uint64_t>(i));
    const Eigen::Vector3d dp = b.T_tracker_head.t - a.T_tracker_head.t;
    const Eigen::AngleAxisd dr(a.T_tracker_head.R.transpose() * b.T_tracker_head.R);  // head frame
    const Eigen::Vector3d rv = dr.axis() * dr.angle() * 180.0 / M_PI;
    sp += dp;
    sp2 += dp.cwiseProduct(dp);
    sr += rv;
    sr2 += rv.cwiseProduct(rv);
    ASSERT_EQ(a.angular_velocity_rad_s, b.angular_velocity_rad_s);
  }
  for (int k = 0; k < 3; ++k) {
    const double mp = sp[k] / kN, mr = sr[k] / kN;
    EXPECT_NEAR(mp, 0.0, 4.5 * 0.002 / std::sqrt(kN));
    EXPECT_NEAR(std::sqrt(sp2[k] / kN - mp * mp), 0.002, 0.002 * 0.03);
    EXPECT_NEAR(mr, 0.0, 4.5 * 0.5 / std::sqrt(kN));
    EXPECT_NEAR(std::sqrt(sr2[k] / kN - mr * mr), 0.5, 0.5 * 0.03);
  }
}

TEST(SimEffects, TrackerDriftRateFromARegression) {
  Simulation drifting(
      scene_with("  - tracker_drift: {position_m_s: 0.003, orientation_deg_s: 0.2, direction: [0, "
                 "0, 2], axis: [1, 0, 0]}\n"));
  Simulation clean(scene_with(""));
  // Least-squares slope of the error against time, over 10 s.
  double st = 0, st2 = 0, sz = 0, stz = 0, sa = 0, sta = 0, sxy = 0;
  constexpr int kN = 200;
  for (int i = 0; i < kN; ++i) {
    const double t = i * 0.05;
    const drivers::PoseSample a = clean.head_sample(t, static_cast<uint64_t>(i));
    const drivers::PoseSample b = drifting.head_sample(t, static_cast<uint64_t>(i));
    const Eigen::Vector3d dp = b.T_tracker_head.t - a.T_tracker_head.t;
    const Eigen::AngleAxisd dr(b.T_tracker_head.R *
                               a.T_tracker_head.R.transpose());  // tracker frame
    const double angle_deg = dr.angle() * 180.0 / M_PI * (dr.axis().x() >= 0 ? 1 : -1);
    st += t;
    st2 += t * t;
    sz += dp.z();
    stz += t * dp.z();
    sa += angle_deg;
    sta += t * angle_deg;
    sxy += std::abs(dp.x()) + std::abs(dp.y());
  }
  const double denom = kN * st2 - st * st;
  EXPECT_NEAR((kN * stz - st * sz) / denom, 0.003, 1e-9);
  EXPECT_NEAR((kN * sta - st * sa) / denom, 0.2, 1e-6);
  EXPECT_NEAR(sxy, 0.0, 1e-12);  // only along the given direction
}

TEST(SimEffects, ModelStalenessIsReportedOnlyWhenListed) {
  EXPECT_FALSE(Simulation(scene_with("")).model_staleness().has_value());
  Simulation sim(scene_with("  - model_staleness: {period_s: 1.5, delay_s: 0.25}\n"));
  ASSERT_TRUE(sim.model_staleness().has_value());
  EXPECT_DOUBLE_EQ(sim.model_staleness()->period_s, 1.5);
  EXPECT_DOUBLE_EQ(sim.model_staleness()->delay_s, 0.25);
  // It changes no pixel.
  Simulation plain(scene_with(""));
  EXPECT_TRUE(render(sim, 2).data == render(plain, 2).data);
}

TEST(SimEffects, TrackerDriftKeepsGrowingAcrossALoopedScene) {
  // Only the scripted motion starts over: drift is of the tracker, whose clock runs on.
  Scene drifting_scene = scene_with(
      "  - tracker_drift: {position_m_s: 0.003, orientation_deg_s: 0, direction: [0, "
      "0, 1]}\n");
  Scene clean_scene = scene_with("");
  drifting_scene.loop = clean_scene.loop = true;
  const double lap = clean_scene.duration_s;
  const Simulation drifting(std::move(drifting_scene));
  const Simulation clean(std::move(clean_scene));
  for (const double t : {1.0, lap + 1.0, 3 * lap + 1.0}) {
    const Eigen::Vector3d dp =
        drifting.head_sample(t, 0).T_tracker_head.t - clean.head_sample(t, 0).T_tracker_head.t;
    EXPECT_NEAR(dp.z(), 0.003 * t, 1e-9) << t;
    // And the clean head is on its first lap's pose.
    EXPECT_NEAR(
        (clean.head_sample(t, 0).T_tracker_head.t - clean.head_sample(1.0, 0).T_tracker_head.t)
            .norm(),
        0.0, 1e-9);
  }
}

}  // namespace
}  // namespace hd::sim

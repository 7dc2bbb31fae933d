// Per-frame conversion cost of the V4L2 formats at 1280x720, with OpenCV as the peer measured in
// the same run. Counters: max_abs_diff = largest channel difference between ours and OpenCV's.
#include <benchmark/benchmark.h>
#include <turbojpeg.h>

#include <algorithm>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <random>
#include <vector>

#include "drivers/convert/mjpeg_decoder.h"
#include "drivers/convert/yuyv_to_rgba.h"

namespace {

constexpr int kW = 1280;
constexpr int kH = 720;

std::vector<uint8_t> yuyv_frame() {
  std::vector<uint8_t> f(static_cast<std::size_t>(kW) * kH * 2);
  std::mt19937 rng(3);
  for (std::size_t i = 0; i < f.size(); ++i) f[i] = static_cast<uint8_t>(16 + rng() % 220);
  return f;
}

std::vector<uint8_t> jpeg_frame() {
  std::vector<uint8_t> rgba(static_cast<std::size_t>(kW) * kH * 4);
  for (int y = 0; y < kH; ++y) {
    for (int x = 0; x < kW; ++x) {
      uint8_t* p = &rgba[static_cast<std::size_t>((y * kW + x) * 4)];
      p[0] = static_cast<uint8_t>(x);
      p[1] = static_cast<uint8_t>(y);
      p[2] = static_cast<uint8_t>((x ^ y) & 0xFF);
      p[3] = 255;
    }
  }
  tjhandle tj = tjInitCompress();
  unsigned char* out = nullptr;
  unsigned long len = 0;
  tjCompress2(tj, rgba.data(), kW, kW * 4, kH, TJPF_RGBA, &out, &len, TJSAMP_422, 85, 0);
  std::vector<uint8_t> jpeg(out, out + len);
  tjFree(out);
  tjDestroy(tj);
  return jpeg;
}

void BM_YuyvToRgba_Ours(benchmark::State& state) {
  const auto src = yuyv_frame();
  std::vector<uint8_t> dst(static_cast<std::size_t>(kW) * kH * 4);
  for (auto _ : state) {
    hd::drivers::yuyv_to_rgba(src.data(), src.size(), kW, kH, kW * 2, dst.data(), dst.size(),
                              kW * 4);
    benchmark::DoNotOptimize(dst.data());
  }
  cv::Mat ref;
  cv::cvtColor(cv::Mat(kH, kW, CV_8UC2, const_cast<uint8_t*>(src.data())), ref,
               cv::COLOR_YUV2RGBA_YUYV);
  int worst = 0;
  for (std::size_t i = 0; i < dst.size(); ++i)
    worst = std::max(worst, std::abs(dst[i] - ref.data[i]));
  state.counters["max_abs_diff"] = worst;
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_YuyvToRgba_Ours)->Unit(benchmark::kMicrosecond);

void BM_YuyvToRgba_OpenCv(benchmark::State& state) {
  auto src = yuyv_frame();
  cv::Mat in(kH, kW, CV_8UC2, src.data());
  cv::Mat out(kH, kW, CV_8UC4);
  for (auto _ : state) {
    cv::cvtColor(in, out, cv::COLOR_YUV2RGBA_YUYV);
    benchmark::DoNotOptimize(out.data);
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_YuyvToRgba_OpenCv)->Unit(benchmark::kMicrosecond);

void BM_Mjpeg_Ours(benchmark::State& state) {
  const auto jpeg = jpeg_frame();
  hd::drivers::MjpegDecoder dec(jpeg.size());
  std::vector<uint8_t> dst(static_cast<std::size_t>(kW) * kH * 4);
  for (auto _ : state) {
    if (!dec.decode_rgba(jpeg.data(), jpeg.size(), kW, kH, dst.data(), dst.size(), kW * 4)) {
      state.SkipWithError(dec.error());
      break;
    }
    benchmark::DoNotOptimize(dst.data());
  }
  state.counters["jpeg_bytes"] = static_cast<double>(jpeg.size());
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_Mjpeg_Ours)->Unit(benchmark::kMicrosecond);

void BM_Mjpeg_OpenCvImdecodeToRgba(benchmark::State& state) {
  const auto jpeg = jpeg_frame();
  cv::Mat bgr;
  cv::Mat rgba;
  for (auto _ : state) {
    cv::imdecode(jpeg, cv::IMREAD_COLOR, &bgr);
    cv::cvtColor(bgr, rgba, cv::COLOR_BGR2RGBA);
    benchmark::DoNotOptimize(rgba.data);
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_Mjpeg_OpenCvImdecodeToRgba)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();

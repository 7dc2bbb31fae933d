// RgbaConverter against GStreamer's own videoconvert element on the same pictures: RGBA → I420
// (SD, where the default matrix is BT.601, and HD, BT.709) and back, byte for byte; a converter
// built once per format, and frames that do not fit refused.
#include "drivers/gst/rgba_converter.h"

#include <gst/app/gstappsink.h>
#include <gst/app/gstappsrc.h>
#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "drivers/gst/gst_ptr.h"

namespace hd::drivers {
namespace {

// A picture with edges, gradients and noise, so chroma subsampling and rounding matter.
Frame picture(int w, int h, int stride_px) {
  Frame f;
  f.allocate_rgba(w, h);
  f.stride_bytes = stride_px * 4;
  f.data.assign(std::size_t(f.stride_bytes) * h, 0);
  std::mt19937 rng(7);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      uint8_t* p = f.data.data() + std::size_t(y) * f.stride_bytes + std::size_t(x) * 4;
      p[0] = static_cast<uint8_t>((x * 255) / w);
      p[1] = static_cast<uint8_t>(((x / 16 + y / 16) % 2) * 200 + rng() % 40);
      p[2] = static_cast<uint8_t>((y * 255) / h);
      p[3] = 255;
    }
  return f;
}

std::string caps_text(const char* format, int w, int h) {
  return std::string("video/x-raw,format=") + format + ",width=" + std::to_string(w) +
         ",height=" + std::to_string(h) + ",framerate=30/1";
}

// `in` (bytes of caps `from`) through appsrc ! videoconvert ! `to` ! appsink: the sample.
GstSamplePtr through_videoconvert(const std::string& from, const std::string& to, const uint8_t* in,
                                  std::size_t size) {
  gst_init(nullptr, nullptr);
  const std::string d = "appsrc name=src format=time caps=\"" + from +
                        "\" ! videoconvert ! capsfilter caps=\"" + to +
                        "\" ! appsink name=sink sync=false";
  GError* error = nullptr;
  GstElementPtr pipeline(gst_parse_launch(d.c_str(), &error));
  EXPECT_EQ(error, nullptr) << (error ? error->message : "");
  if (error != nullptr) g_clear_error(&error);
  GstElementPtr src(gst_bin_get_by_name(GST_BIN(pipeline.get()), "src"));
  GstElementPtr sink(gst_bin_get_by_name(GST_BIN(pipeline.get()), "sink"));
  gst_element_set_state(pipeline.get(), GST_STATE_PLAYING);
  GstBuffer* b = gst_buffer_new_memdup(in, size);
  GST_BUFFER_PTS(b) = 0;
  gst_app_src_push_buffer(GST_APP_SRC(src.get()), b);
  gst_app_src_end_of_stream(GST_APP_SRC(src.get()));
  GstSamplePtr s(gst_app_sink_pull_sample(GST_APP_SINK(sink.get())));
  gst_element_set_state(pipeline.get(), GST_STATE_NULL);
  return s;
}

// RGBA rows of `f` without their padding.
std::vector<uint8_t> packed(const Frame& f) {
  std::vector<uint8_t> out;
  for (int y = 0; y < f.height; ++y) {
    const uint8_t* row = f.data.data() + std::size_t(y) * f.stride_bytes;
    out.insert(out.end(), row, row + std::size_t(f.width) * 4);
  }
  return out;
}

void round_trip_matches_videoconvert(int w, int h) {
  gst_init(nullptr, nullptr);
  const Frame rgba = picture(w, h, w + 8);  // padded rows: the stride is honoured
  const std::vector<uint8_t> tight = packed(rgba);
  // RGBA → I420: ours into a buffer of the encoder's caps, the element's from the same picture.
  GstVideoInfo i420;
  GstCapsPtr caps(gst_caps_from_string(caps_text("I420", w, h).c_str()));
  ASSERT_TRUE(gst_video_info_from_caps(&i420, caps.get()));
  GstBufferPtr ours(gst_buffer_new_allocate(nullptr, GST_VIDEO_INFO_SIZE(&i420), nullptr));
  RgbaConverter converter;
  GstVideoFrame out;
  ASSERT_TRUE(gst_video_frame_map(&out, &i420, ours.get(), GST_MAP_WRITE));
  ASSERT_TRUE(converter.from_rgba(rgba, &out));
  gst_video_frame_unmap(&out);
  const GstSamplePtr theirs = through_videoconvert(caps_text("RGBA", w, h), caps_text("I420", w, h),
                                                   tight.data(), tight.size());
  ASSERT_TRUE(theirs);
  GstMapInfo a, b;
  ASSERT_TRUE(gst_buffer_map(ours.get(), &a, GST_MAP_READ));
  ASSERT_TRUE(gst_buffer_map(gst_sample_get_buffer(theirs.get()), &b, GST_MAP_READ));
  ASSERT_EQ(a.size, b.size);
  int differing = 0;
  for (std::size_t i = 0; i < a.size; ++i) differing += a.data[i] != b.data[i];
  EXPECT_EQ(differing, 0) << "of " << a.size << " I420 bytes";
  // I420 → RGBA: ours into a Frame, the element's from the same I420 bytes.
  Frame back;
  back.allocate_rgba(w, h);
  GstVideoFrame in;
  ASSERT_TRUE(gst_video_frame_map(&in, &i420, ours.get(), GST_MAP_READ));
  ASSERT_TRUE(converter.to_rgba(&in, back));
  gst_video_frame_unmap(&in);
  const GstSamplePtr theirs_back =
      through_videoconvert(caps_text("I420", w, h), caps_text("RGBA", w, h), a.data, a.size);
  gst_buffer_unmap(gst_sample_get_buffer(theirs.get()), &b);
  gst_buffer_unmap(ours.get(), &a);
  ASSERT_TRUE(theirs_back);
  ASSERT_TRUE(gst_buffer_map(gst_sample_get_buffer(theirs_back.get()), &b, GST_MAP_READ));
  ASSERT_EQ(b.size, back.data.size());
  differing = 0;
  for (std::size_t i = 0; i < b.size; ++i) differing += b.data[i] != back.data[i];
  gst_buffer_unmap(gst_sample_get_buffer(theirs_back.get()), &b);
  EXPECT_EQ(differing, 0) << "of " << back.data.size() << " RGBA bytes";
}

TEST(RgbaConverter, StandardDefinitionMatchesVideoconvertByteForByteBothWays) {
  round_trip_matches_videoconvert(640, 480);
}

TEST(RgbaConverter, HighDefinitionMatchesVideoconvertByteForByteBothWays) {
  round_trip_matches_videoconvert(1280, 720);
}

TEST(RgbaConverter, OneConverterPerFormatAndFramesThatDoNotFitAreRefused) {
  gst_init(nullptr, nullptr);
  GstVideoInfo i420;
  gst_video_info_set_format(&i420, GST_VIDEO_FORMAT_I420, 320, 240);
  GstBufferPtr buffer(gst_buffer_new_allocate(nullptr, GST_VIDEO_INFO_SIZE(&i420), nullptr));
  GstVideoFrame out;
  ASSERT_TRUE(gst_video_frame_map(&out, &i420, buffer.get(), GST_MAP_WRITE));
  RgbaConverter c;
  const Frame f = picture(320, 240, 320);
  for (int i = 0; i < 5; ++i) ASSERT_TRUE(c.from_rgba(f, &out));
  EXPECT_EQ(c.converters_built(), 1);
  EXPECT_FALSE(c.from_rgba(picture(320, 200, 320), &out));  // another size
  Frame short_data = f;
  short_data.data.resize(100);
  EXPECT_FALSE(c.from_rgba(short_data, &out));  // less memory than its size says
  Frame mono = f;
  mono.format = PixelFormat::kMono8;
  EXPECT_FALSE(c.from_rgba(mono, &out));
  EXPECT_EQ(c.converters_built(), 1);
  gst_video_frame_unmap(&out);
}

}  // namespace
}  // namespace hd::drivers

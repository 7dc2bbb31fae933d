// AccessUnitMark through a real x264enc → avdec_h264 → videoconvert pipeline: every decoded RGBA
// frame carries its access unit's mark, also when the decoder's input PTS go backwards (which
// GstVideoDecoder answers by holding its output PTS: the case PTS matching failed on).
#include "drivers/rtp/access_unit_mark.h"

#include <gst/app/gstappsink.h>
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "drivers/rtp/gstreamer_init.h"

namespace hd::drivers {
namespace {

TEST(AccessUnitMark, ABufferWithoutOneHasNoneAndASecondMarkReplacesTheFirst) {
  ensure_gstreamer();
  GstBuffer* b = gst_buffer_new();
  EXPECT_FALSE(access_unit_mark(b).has_value());
  mark_access_unit(b, {42, true});
  mark_access_unit(b, {43, false});
  const auto m = access_unit_mark(b);
  ASSERT_TRUE(m.has_value());
  EXPECT_EQ(m->pts, 43u);
  EXPECT_FALSE(m->whole);
  gst_buffer_unref(b);
}

struct Marks {
  uint64_t in = 0;                  // access units marked
  std::vector<AccessUnitMark> out;  // marks on the RGBA frames, in order
  std::vector<uint64_t> out_pts;    // their PTS
  uint64_t unmarked = 0;
};

TEST(AccessUnitMark, EveryDecodedFrameCarriesItsAccessUnitsMarkWhenInputPtsGoBackwards) {
  ensure_gstreamer();
  constexpr int kFrames = 12;
  GError* error = nullptr;
  GstElement* pipeline = gst_parse_launch(
      "videotestsrc num-buffers=12 ! video/x-raw,width=160,height=120,framerate=30/1 ! "
      "x264enc tune=zerolatency key-int-max=4 ! h264parse ! "
      "avdec_h264 name=dec max-threads=1 ! videoconvert ! video/x-raw,format=RGBA ! "
      "appsink name=sink sync=false",
      &error);
  ASSERT_EQ(error, nullptr) << error->message;
  Marks marks;
  GstElement* dec = gst_bin_get_by_name(GST_BIN(pipeline), "dec");
  GstPad* sink_pad = gst_element_get_static_pad(dec, "sink");
  gst_pad_add_probe(
      sink_pad, GST_PAD_PROBE_TYPE_BUFFER,
      [](GstPad*, GstPadProbeInfo* info, gpointer data) {
        auto& m = *static_cast<Marks*>(data);
        GstBuffer* b = gst_buffer_make_writable(GST_PAD_PROBE_INFO_BUFFER(info));
        // Input PTS that fall by about a second per access unit (within x264enc's segment, which
        // starts at 1000 h); the mark numbers them.
        GST_BUFFER_PTS(b) += (100 - m.in) * GST_SECOND;
        mark_access_unit(b, {m.in, m.in % 3 != 0});
        ++m.in;
        GST_PAD_PROBE_INFO_DATA(info) = b;
        return GST_PAD_PROBE_OK;
      },
      &marks, nullptr);
  gst_object_unref(sink_pad);
  gst_object_unref(dec);
  GstElement* sink = gst_bin_get_by_name(GST_BIN(pipeline), "sink");
  ASSERT_NE(gst_element_set_state(pipeline, GST_STATE_PLAYING), GST_STATE_CHANGE_FAILURE);
  // The appsink answers pulls once it is PAUSED (prerolled on the first frame).
  ASSERT_EQ(gst_element_get_state(pipeline, nullptr, nullptr, GST_CLOCK_TIME_NONE),
            GST_STATE_CHANGE_SUCCESS);
  while (GstSample* s = gst_app_sink_pull_sample(GST_APP_SINK(sink))) {  // until EOS
    GstBuffer* b = gst_sample_get_buffer(s);
    if (const auto m = access_unit_mark(b)) {
      marks.out.push_back(*m);
      marks.out_pts.push_back(GST_BUFFER_PTS(b));
    } else {
      ++marks.unmarked;
    }
    gst_sample_unref(s);
  }
  gst_element_set_state(pipeline, GST_STATE_NULL);
  gst_object_unref(sink);
  gst_object_unref(pipeline);

  EXPECT_EQ(marks.in, uint64_t(kFrames));
  EXPECT_EQ(marks.unmarked, 0u);
  ASSERT_EQ(marks.out.size(), std::size_t(kFrames));
  for (int i = 0; i < kFrames; ++i) {
    EXPECT_EQ(marks.out[i].pts, uint64_t(i)) << "frame " << i;
    EXPECT_EQ(marks.out[i].whole, i % 3 != 0) << "frame " << i;
  }
  // What PTS matching would have had: the decoder held its output PTS at the first one out.
  EXPECT_EQ(marks.out_pts.back(), marks.out_pts.front());
}

}  // namespace
}  // namespace hd::drivers

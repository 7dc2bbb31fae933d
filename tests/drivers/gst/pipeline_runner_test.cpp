// PipelineRunner on a small live pipeline (videotestsrc → fakesink): checked lookups that name
// what is missing, probes that see buffers and go with the teardown, the bus thread's turns, and
// the rebuild after an error posted on the bus.
#include "drivers/gst/pipeline_runner.h"

#include <gtest/gtest.h>

#include <atomic>
#include <mutex>
#include <string>

#include "drivers/camera_source.h"
#include "test_wait.h"

namespace hd::drivers {
namespace {

constexpr const char* kLive = "videotestsrc is-live=true name=src ! fakesink name=sink sync=false";

PipelineRunner::Settings settings(const char* description = kLive) {
  gst_init(nullptr, nullptr);
  PipelineRunner::Settings s;
  s.owner = "test camera";
  s.what = "test pipeline";
  s.description = description;
  s.restart_delay_ns = 1'000'000;  // the test waits for the rebuild, not for this delay
  return s;
}

int probe_count(GstPad* pad) {  // as in pad_probe_test.cpp: the pad's hook list, read
  int n = 0;
  GST_OBJECT_LOCK(pad);
  for (GHook* h = g_hook_first_valid(&pad->probes, TRUE); h != nullptr;
       h = g_hook_next_valid(&pad->probes, h, TRUE))
    ++n;
  GST_OBJECT_UNLOCK(pad);
  return n;
}

std::string thrown_by(const std::function<void()>& f) {
  try {
    f();
  } catch (const DeviceError& e) {
    return e.what();
  }
  return "(nothing thrown)";
}

TEST(PipelineRunner, AMissingElementOrPadIsADeviceErrorNamingIt) {
  PipelineRunner r(settings(), {});
  r.build();
  ASSERT_TRUE(r.built());
  EXPECT_NE(r.element("sink"), nullptr);
  EXPECT_EQ(r.find("rtpbin"), nullptr);
  EXPECT_EQ(thrown_by([&] { r.element("rtpbin"); }),
            "test camera: the test pipeline has no element rtpbin");
  EXPECT_EQ(thrown_by([&] {
              r.probe(
                  "sink", "src",
                  [](GstPad*, GstPadProbeInfo*, gpointer) { return GST_PAD_PROBE_OK; }, nullptr);
            }),
            "test camera: the test pipeline has no pad sink.src");
  r.teardown();
  EXPECT_FALSE(r.built());
  EXPECT_EQ(r.find("sink"), nullptr);  // nothing built: nothing found, nothing thrown
}

TEST(PipelineRunner, ABadDescriptionOrAFailedWiringLeavesNothingBuilt) {
  PipelineRunner bad(settings("videotestsrc ! no_such_element_here"), {});
  const std::string why = thrown_by([&] { bad.build(); });
  EXPECT_EQ(why.rfind("test camera: cannot build the test pipeline: ", 0), 0u) << why;
  EXPECT_NE(why.find("no_such_element_here"), std::string::npos) << why;
  EXPECT_FALSE(bad.built());

  PipelineRunner::Hooks hooks;
  hooks.wire = [](PipelineRunner& p) { p.element("depay"); };
  PipelineRunner unwired(settings(), hooks);
  EXPECT_EQ(thrown_by([&] { unwired.build(); }),
            "test camera: the test pipeline has no element depay");
  EXPECT_FALSE(unwired.built());
}

TEST(PipelineRunner, ProbesSeeBuffersAndTheTeardownRemovesThemAndReleasesThePipeline) {
  std::atomic<int> buffers{0};
  PipelineRunner::Hooks hooks;
  hooks.wire = [&](PipelineRunner& p) {
    p.probe(
        "sink", "sink",
        [](GstPad*, GstPadProbeInfo*, gpointer n) {
          static_cast<std::atomic<int>*>(n)->fetch_add(1);
          return GST_PAD_PROBE_OK;
        },
        &buffers);
  };
  PipelineRunner r(settings(), hooks);
  std::string why;
  ASSERT_TRUE(r.play(why)) << why;
  EXPECT_EQ(why, "");
  ASSERT_TRUE(eventually([&] { return buffers.load() >= 3; }));
  EXPECT_NE(r.base_time(), 0u);  // playing: a base time on the monotonic clock
  GstPadPtr pad(gst_element_get_static_pad(r.element("sink").get(), "sink"));
  EXPECT_EQ(probe_count(pad.get()), 1);
  r.teardown();
  EXPECT_EQ(probe_count(pad.get()), 0);
  // The pipeline, its elements and the probe's reference are gone: this one is the last.
  EXPECT_EQ(GST_OBJECT_REFCOUNT_VALUE(pad.get()), 1);
  EXPECT_EQ(r.raw(), nullptr);
  EXPECT_EQ(r.base_time(), 0u);
}

TEST(PipelineRunner, APipelineThatCannotPlayIsTornDownWithTheBusError) {
  PipelineRunner r(settings("filesrc location=/nonexistent/hd-test ! fakesink"), {});
  std::string why;
  EXPECT_FALSE(r.play(why));
  EXPECT_FALSE(why.empty());
  EXPECT_FALSE(r.built());
}

TEST(PipelineRunner, AnErrorOnTheBusIsCountedReportedAndThePipelineRebuilt) {
  std::atomic<int> wired{0}, turns{0};
  std::mutex m;
  std::string reported;
  PipelineRunner::Hooks hooks;
  hooks.wire = [&](PipelineRunner&) { ++wired; };
  hooks.on_error = [&](const std::string& text) {
    std::lock_guard lock(m);
    reported = text;
  };
  hooks.on_turn = [&] { ++turns; };
  PipelineRunner r(settings(), hooks);
  std::string why;
  ASSERT_TRUE(r.play(why)) << why;
  r.start();
  EXPECT_TRUE(r.running());
  ASSERT_TRUE(eventually([&] { return turns.load() >= 2; }));
  EXPECT_EQ(r.errors(), 0u);
  {
    const GstElementPtr src = r.element("src");
    GError* e = g_error_new_literal(GST_STREAM_ERROR, GST_STREAM_ERROR_FAILED, "boom");
    gst_element_post_message(src.get(), gst_message_new_error(GST_OBJECT(src.get()), e, "x.c"));
    g_error_free(e);
  }
  ASSERT_TRUE(eventually([&] { return r.restarts() >= 1; }));
  EXPECT_EQ(r.errors(), 1u);
  EXPECT_EQ(r.restarts(), 1u);
  EXPECT_EQ(r.last_error(), "src: boom");
  {
    std::lock_guard lock(m);
    EXPECT_EQ(reported, "src: boom");
  }
  EXPECT_EQ(wired.load(), 2);  // built twice: at play() and after the error
  EXPECT_TRUE(r.built());
  r.stop();
  EXPECT_FALSE(r.running());
  EXPECT_TRUE(r.built());  // stopped, not torn down: play() resumes it
  GstState state = GST_STATE_VOID_PENDING;
  gst_element_get_state(r.raw(), &state, nullptr, 0);
  EXPECT_EQ(state, GST_STATE_NULL);
}

}  // namespace
}  // namespace hd::drivers

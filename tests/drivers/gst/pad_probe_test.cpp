// PadProbe: installed on construction, removed on destruction, reset or move-assignment, and the
// pad's reference released with it.
#include <gtest/gtest.h>

#include "drivers/gst/gst_ptr.h"

namespace hd::drivers {
namespace {

// The probes installed on `pad` now. GStreamer has no call for it; its hook list is in the
// pad's (documented private) fields, read here only to check what the wrapper promises.
int probe_count(GstPad* pad) {
  int n = 0;
  GST_OBJECT_LOCK(pad);
  for (GHook* h = g_hook_first_valid(&pad->probes, TRUE); h != nullptr;
       h = g_hook_next_valid(&pad->probes, h, TRUE))
    ++n;
  GST_OBJECT_UNLOCK(pad);
  return n;
}

GstPadProbeReturn pass(GstPad*, GstPadProbeInfo*, gpointer) {
  return GST_PAD_PROBE_OK;
}

GstPadPtr new_pad() {
  return GstPadPtr(GST_PAD(gst_object_ref_sink(gst_pad_new("src", GST_PAD_SRC))));
}

TEST(PadProbe, IsRemovedWhenDestroyedAndReleasesItsPadReference) {
  gst_init(nullptr, nullptr);
  const GstPadPtr pad = new_pad();
  EXPECT_EQ(GST_OBJECT_REFCOUNT_VALUE(pad.get()), 1);
  {
    PadProbe probe(GstPadPtr(GST_PAD(gst_object_ref(pad.get()))), GST_PAD_PROBE_TYPE_BUFFER, &pass,
                   nullptr);
    EXPECT_TRUE(probe.installed());
    EXPECT_EQ(probe.pad(), pad.get());
    EXPECT_EQ(probe_count(pad.get()), 1);
    EXPECT_EQ(GST_OBJECT_REFCOUNT_VALUE(pad.get()), 2);
  }
  EXPECT_EQ(probe_count(pad.get()), 0);
  EXPECT_EQ(GST_OBJECT_REFCOUNT_VALUE(pad.get()), 1);
}

TEST(PadProbe, ResetAndMovesRemoveEachProbeExactlyOnce) {
  gst_init(nullptr, nullptr);
  const GstPadPtr pad = new_pad();
  auto ref = [&] { return GstPadPtr(GST_PAD(gst_object_ref(pad.get()))); };
  PadProbe a(ref(), GST_PAD_PROBE_TYPE_BUFFER, &pass, nullptr);
  PadProbe b(ref(), GST_PAD_PROBE_TYPE_BUFFER, &pass, nullptr);
  EXPECT_EQ(probe_count(pad.get()), 2);
  PadProbe moved(std::move(a));  // still one probe: ownership moved, nothing removed
  EXPECT_FALSE(a.installed());   // NOLINT(bugprone-use-after-move): the moved-from state
  EXPECT_EQ(probe_count(pad.get()), 2);
  moved = std::move(b);  // moved's own probe goes, b's stays
  EXPECT_EQ(probe_count(pad.get()), 1);
  moved.reset();
  EXPECT_FALSE(moved.installed());
  EXPECT_EQ(probe_count(pad.get()), 0);
  EXPECT_EQ(GST_OBJECT_REFCOUNT_VALUE(pad.get()), 1);
}

TEST(PadProbe, ANullPadInstallsNothing) {
  PadProbe p(nullptr, GST_PAD_PROBE_TYPE_BUFFER, &pass, nullptr);
  EXPECT_FALSE(p.installed());
}

}  // namespace
}  // namespace hd::drivers

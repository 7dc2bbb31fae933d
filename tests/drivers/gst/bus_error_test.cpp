// parse_bus_error on real GstMessages: an error posted by a named element, one without a source,
// and messages that are not errors.
#include "drivers/gst/bus_error.h"

#include <gtest/gtest.h>

#include "drivers/gst/gst_ptr.h"

namespace hd::drivers {
namespace {

GstMessagePtr error_message(GstObject* source, const char* text, const char* debug) {
  GError* e = g_error_new_literal(GST_RESOURCE_ERROR, GST_RESOURCE_ERROR_OPEN_READ, text);
  GstMessagePtr m(gst_message_new_error(source, e, debug));
  g_error_free(e);
  return m;
}

TEST(BusError, AnErrorMessageGivesItsSourceNameTextAndDebug) {
  gst_init(nullptr, nullptr);
  const GstElementPtr source(
      GST_ELEMENT(gst_object_ref_sink(gst_element_factory_make("fakesrc", "rtp_src"))));
  ASSERT_TRUE(source);
  const GstMessagePtr m =
      error_message(GST_OBJECT(source.get()), "Could not open resource", "gstudpsrc.c(1234)");
  const std::optional<BusError> e = parse_bus_error(m.get());
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(e->source, "rtp_src");
  EXPECT_EQ(e->text, "Could not open resource");
  EXPECT_EQ(e->debug, "gstudpsrc.c(1234)");
  EXPECT_EQ(e->to_string(), "rtp_src: Could not open resource");
}

TEST(BusError, AMessageWithoutSourceOrDebugGivesTheTextAlone) {
  gst_init(nullptr, nullptr);
  const GstMessagePtr m = error_message(nullptr, "no source", nullptr);
  const std::optional<BusError> e = parse_bus_error(m.get());
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(e->source, "");
  EXPECT_EQ(e->text, "no source");
  EXPECT_EQ(e->debug, "");
  EXPECT_EQ(e->to_string(), "no source");
}

TEST(BusError, MessagesThatAreNotErrorsGiveNothing) {
  gst_init(nullptr, nullptr);
  const GstMessagePtr eos(gst_message_new_eos(nullptr));
  EXPECT_FALSE(parse_bus_error(eos.get()).has_value());
  GError* w = g_error_new_literal(GST_CORE_ERROR, GST_CORE_ERROR_FAILED, "only a warning");
  const GstMessagePtr warning(gst_message_new_warning(nullptr, w, nullptr));
  g_error_free(w);
  EXPECT_FALSE(parse_bus_error(warning.get()).has_value());
  EXPECT_FALSE(parse_bus_error(nullptr).has_value());
}

}  // namespace
}  // namespace hd::drivers

// probe_v4l2_devices over a temporary /dev-like directory, with the fake device behind the seam.
#include "drivers/v4l2/v4l2_prober.h"

#include <gtest/gtest.h>

#include <cerrno>
#include <fstream>

#include "fake_v4l2_device.h"

namespace hd::drivers {
namespace {

namespace fs = std::filesystem;

class TempDevDir : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("hd_v4l2_probe_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  void touch(const std::string& name) { std::ofstream(dir_ / name).put('x'); }
  fs::path dir_;
};

TEST_F(TempDevDir, NoNodesGivesAnEmptyList) {
  touch("null");
  touch("videox");
  testing::FakeV4l2Device fake({});
  EXPECT_TRUE(probe_v4l2_devices(fake, dir_).empty());
  EXPECT_TRUE(probe_v4l2_devices(fake, dir_ / "does-not-exist").empty());
}

TEST_F(TempDevDir, ThisMachineProbesWithoutThrowing) {
  std::vector<DeviceInfo> found;
  EXPECT_NO_THROW(found = probe_v4l2_devices());
  if (!fs::exists("/dev/video0")) {
    EXPECT_TRUE(found.empty());
  }
  for (const auto& d : found) EXPECT_EQ(d.kind, "v4l2");
}

TEST_F(TempDevDir, ListsACaptureNodeWithItsFormats) {
  touch("video2");
  testing::FakeV4l2Config cfg;
  cfg.path = (dir_ / "video2").string();
  cfg.modes = {{V4L2_PIX_FMT_YUYV, 32, 16, {{1, 30}}}, {V4L2_PIX_FMT_MJPEG, 32, 16, {{1, 30}}}};
  testing::FakeV4l2Device fake(cfg);
  const auto found = probe_v4l2_devices(fake, dir_);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(found[0].kind, "v4l2");
  EXPECT_EQ(found[0].id, cfg.path);
  EXPECT_TRUE(found[0].openable) << found[0].reason;
  EXPECT_NE(found[0].description.find("Fake UVC Camera"), std::string::npos);
  EXPECT_NE(found[0].description.find("YUYV"), std::string::npos);
  EXPECT_NE(found[0].description.find("MJPG"), std::string::npos);
  EXPECT_EQ(fake.open_fds(), 0);
}

TEST_F(TempDevDir, PermissionDeniedPointsAtUdevRulesAndVideoGroup) {
  touch("video0");
  touch("video10");
  testing::FakeV4l2Config cfg;
  cfg.open_errno = EACCES;
  testing::FakeV4l2Device fake(cfg);
  const auto found = probe_v4l2_devices(fake, dir_);
  ASSERT_EQ(found.size(), 2u);
  EXPECT_EQ(found[0].id, (dir_ / "video0").string());  // numeric order
  EXPECT_EQ(found[1].id, (dir_ / "video10").string());
  for (const auto& d : found) {
    EXPECT_FALSE(d.openable);
    EXPECT_NE(d.reason.find("udev"), std::string::npos) << d.reason;
    EXPECT_NE(d.reason.find("'video' group"), std::string::npos) << d.reason;
  }
}

TEST_F(TempDevDir, MetadataNodeIsListedAsNotUsable) {
  touch("video1");
  testing::FakeV4l2Config cfg;
  cfg.path = (dir_ / "video1").string();
  cfg.device_caps = V4L2_CAP_META_CAPTURE | V4L2_CAP_STREAMING;
  testing::FakeV4l2Device fake(cfg);
  const auto found = probe_v4l2_devices(fake, dir_);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_FALSE(found[0].openable);
  EXPECT_NE(found[0].reason.find("not a video capture node"), std::string::npos);
}

}  // namespace
}  // namespace hd::drivers

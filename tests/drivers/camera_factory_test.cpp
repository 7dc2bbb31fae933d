// The camera id -> driver factory: which driver an id names, malformed ids refused, and replay ids
// played from the picture loader the caller passes (here pictures from memory, no files).
#include "drivers/camera_factory.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace hd::drivers {
namespace {

TEST(CameraFactory, ChoosesTheDriverFromTheId) {
  EXPECT_EQ(camera_kind("/dev/video0"), CameraKind::kV4l2);
  EXPECT_EQ(camera_kind("/dev/video12"), CameraKind::kV4l2);
  EXPECT_EQ(camera_kind("mock"), CameraKind::kMock);
  EXPECT_EQ(camera_kind("mock:320x240"), CameraKind::kMock);
  EXPECT_EQ(camera_kind("Aravis-Fake-CALIB"), CameraKind::kGige);
  EXPECT_EQ(camera_kind("192.168.1.20"), CameraKind::kGige);
  EXPECT_EQ(camera_kind("mockery"), CameraKind::kGige);  // not "mock" nor "mock:"
  EXPECT_EQ(camera_kind("replay:data/left*.jpg"), CameraKind::kReplay);
  EXPECT_EQ(make_camera_source("/dev/video7")->id(), "/dev/video7");
  EXPECT_EQ(make_camera_source("Aravis-Fake-CALIB")->id(), "Aravis-Fake-CALIB");
  EXPECT_EQ(make_camera_source("mock:320x240")->id(), "mock:320x240");
  EXPECT_EQ(camera_kind("rtp://127.0.0.1:5600"), CameraKind::kRtp);
  EXPECT_EQ(make_camera_source("rtp://127.0.0.1:5600")->id(), "rtp://127.0.0.1:5600");
  for (const char* bad :
       {"mock:", "mock:0x240", "mock:320x", "mock:x240", "mock:32ax240", "mock:99999x99999",
        "rtp://127.0.0.1", "rtp://127.0.0.1:5601", "replay:data/*.png@0", "replay:data/*.png@15+x"})
    EXPECT_THROW(make_camera_source(bad), std::invalid_argument) << bad;
}

TEST(CameraFactory, AReplayIdWithoutAPictureLoaderIsRefusedNamingTheId) {
  try {
    make_camera_source("replay:data/left*.jpg@15");
    FAIL() << "accepted";
  } catch (const DeviceError& e) {
    EXPECT_EQ(std::string(e.what()),
              "camera replay:data/left*.jpg@15: this program reads no replay pictures (no picture "
              "loader given)");
  }
}

TEST(CameraFactory, AReplayIdPlaysWhatTheLoaderGivesForItsFolderAndPattern) {
  std::vector<ReplayId> asked;
  const ReplayImageLoader load = [&asked](const ReplayId& id) {
    asked.push_back(id);
    std::vector<ReplayImage> images(3);
    for (std::size_t k = 0; k < images.size(); ++k) {
      images[k].name = "p" + std::to_string(k);
      images[k].width = 4;
      images[k].height = 2;
      images[k].gray.assign(8, static_cast<uint8_t>(10 * k));
    }
    return images;
  };
  auto cam = make_camera_source("replay:pics/left*.png@200", load);
  EXPECT_TRUE(asked.empty());  // the pictures are read by open(), not by the factory
  cam->open();
  ASSERT_EQ(asked.size(), 1u);
  EXPECT_EQ(asked[0].folder, "pics");
  EXPECT_EQ(asked[0].pattern, "left*.png");
  EXPECT_DOUBLE_EQ(asked[0].rate_hz, 200.0);
  EXPECT_EQ(cam->format().width_px, 4);
  EXPECT_EQ(cam->format().height_px, 2);
  cam->start();
  std::vector<uint8_t> firsts;  // each frame's first pixel's gray level (RGBA: R = G = B)
  for (;;) {
    const bool ended = cam->state() == SourceState::kClosed;
    if (cam->frames().fetch()) {
      firsts.push_back(cam->frames().latest().data[0]);
    } else if (ended) {
      break;
    } else {
      std::this_thread::yield();
    }
  }
  cam->stop();
  EXPECT_EQ(firsts, (std::vector<uint8_t>{0, 10, 20}));
}

}  // namespace
}  // namespace hd::drivers

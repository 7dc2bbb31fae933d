// SRTP (AES-128-GCM) between hybrid-remote and the network camera: the right key is shown; a
// wrong key and a missing key are rejected and counted, never shown; a key file others can read
// is refused, and no message ever contains the key.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <thread>

#include "drivers/rtp/gst_launch_sender.h"
#include "drivers/rtp/rtp_camera.h"
#include "drivers/rtp/srtp_key.h"
#include "remote/sender/rtp_send_config.h"
#include "test_paths.h"
#include "test_wait.h"

namespace hd::drivers {
namespace {

namespace fs = std::filesystem;

constexpr const char* kKeyHex = "000102030405060708090a0b0c0d0e0f101112131415161718191a1b";
constexpr const char* kOtherHex = "f00102030405060708090a0b0c0d0e0f101112131415161718191a1b";

class RemoteSrtp : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("remote_srtp_test_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    port_ = testing::free_rtp_port();
    ASSERT_NE(port_, 0);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  fs::path key_file(const std::string& name, const char* hex, mode_t mode = 0600) {
    const fs::path p = dir_ / name;
    const int fd = ::open(p.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
    EXPECT_GE(fd, 0);
    EXPECT_EQ(::write(fd, hex, 56), 56);
    EXPECT_EQ(::write(fd, "\n", 1), 1);
    ::fchmod(fd, mode);
    ::close(fd);
    return p;
  }
  std::unique_ptr<RtpCamera> camera(const char* hex) {
    RtpReceiveConfig c;
    c.listen = {"127.0.0.1", port_};
    if (hex != nullptr) c.srtp_key = read_srtp_key_file(key_file("station.key", hex));
    auto cam = std::make_unique<RtpCamera>(c);
    cam->negotiate({640, 480, {}, 0.0});
    cam->start();
    return cam;
  }
  std::vector<std::string> remote(const char* hex) {
    std::vector<std::string> a{hd::test::remote_bin(), "--scene",
                               std::string(hd::test::source_dir()) + "/scenes/default.yaml", "--to",
                               "rtp://127.0.0.1:" + std::to_string(port_)};
    if (hex != nullptr) {
      a.push_back("--key-file");
      a.push_back(key_file("remote.key", hex).string());
    }
    return a;
  }
  fs::path dir_;
  uint16_t port_ = 0;
};

TEST_F(RemoteSrtp, TheRightKeyIsShown) {
  auto cam = camera(kKeyHex);
  EXPECT_NE(cam->pipeline_description().find("srtpdec"), std::string::npos);
  EXPECT_EQ(cam->pipeline_description().find(kKeyHex), std::string::npos);
  testing::ChildProcess sender(remote(kKeyHex));
  ASSERT_TRUE(eventually([&] { return cam->stats().stamped_frames >= 5; }))
      << cam->stats().packets << " packets, " << cam->stats().srtp_rejected << " rejected";
  EXPECT_GT(cam->stats().srtp_decrypted, 0u);
  EXPECT_EQ(cam->state(), SourceState::kStreaming);
  // The station's view feedback, tagged with the key, is taken by the sender: "not needed"
  // spaces the frames out to the low rate (untagged feedback is refused there).
  cam->set_view_needed(false);
  const int64_t low_period_ns = int64_t(remote::RtpSendConfig{}.low_rate_divider / 30.0 * 1e9);
  int64_t previous = 0;
  ASSERT_TRUE(eventually([&] {
    if (!cam->frames().fetch()) return false;
    const int64_t before = previous;
    previous = cam->frames().latest().host_timestamp_ns;
    return before != 0 && previous - before >= low_period_ns * 8 / 10;
  }));
  EXPECT_GE(cam->feedback().view_feedback_sent, 1u);
  // The station's receiver reports go out as SRTCP and are read by the sender (whose srtpdec
  // passes only what the key protects): it measures the round trip and stamps it into its
  // frames, and the station's clock mapping becomes a measured one.
  ASSERT_TRUE(
      eventually([&] { return cam->clock_mapping().kind == ClockMapping::Kind::kMeasured; }));
}

TEST_F(RemoteSrtp, AWrongKeyIsRejectedCountedAndNeverShown) {
  auto cam = camera(kOtherHex);
  testing::ChildProcess sender(remote(kKeyHex));
  ASSERT_TRUE(eventually([&] { return cam->stats().srtp_rejected >= 200; }));
  EXPECT_EQ(cam->stats().srtp_decrypted, 0u);
  EXPECT_EQ(cam->stats().frames_published, 0u);
  EXPECT_FALSE(cam->frames().fetch());
  EXPECT_NE(cam->state(), SourceState::kStreaming);
}

TEST_F(RemoteSrtp, AStreamWithoutEncryptionIsRejectedWhereAKeyIsRequired) {
  auto cam = camera(kKeyHex);
  testing::ChildProcess sender(remote(nullptr));
  ASSERT_TRUE(eventually([&] { return cam->stats().srtp_rejected >= 200; }));
  EXPECT_EQ(cam->stats().srtp_decrypted, 0u);
  EXPECT_EQ(cam->stats().frames_published, 0u);
  EXPECT_FALSE(cam->frames().fetch());
}

TEST_F(RemoteSrtp, AKeyFileOthersCanReadIsRefusedAndNoMessageShowsTheKey) {
  const fs::path open_file = key_file("open.key", kKeyHex, 0644);
  try {
    read_srtp_key_file(open_file.string());
    FAIL() << "an others-readable key file was accepted";
  } catch (const DeviceError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(open_file.string()), std::string::npos) << m;
    EXPECT_NE(m.find("mode 0644"), std::string::npos) << m;
    EXPECT_NE(m.find("chmod 600"), std::string::npos) << m;
    EXPECT_EQ(m.find(kKeyHex), std::string::npos) << m;
  }
  // hybrid-remote refuses it too (exit 2), without printing the key.
  const std::string cmd = std::string("'") + hd::test::remote_bin() + "' --scene '" +
                          hd::test::source_dir() + "/scenes/default.yaml' --key-file '" +
                          open_file.string() + "' > '" + (dir_ / "out.txt").string() + "' 2>&1";
  const int status = std::system(cmd.c_str());
  EXPECT_EQ(WIFEXITED(status) ? WEXITSTATUS(status) : -1, 2);
  std::string why;
  EXPECT_FALSE(parse_srtp_key_text("00112233", why));
  EXPECT_NE(why.find("expected 56 hex digits"), std::string::npos) << why;
  std::string bad(kKeyHex);
  bad[10] = 'x';
  EXPECT_FALSE(parse_srtp_key_text(bad, why));
  EXPECT_NE(why.find("character 11 is not a hex digit"), std::string::npos) << why;
  EXPECT_EQ(why.find(bad), std::string::npos);
  const auto k = parse_srtp_key_text(std::string(" ") + kKeyHex + "\n", why);
  ASSERT_TRUE(k) << why;
  EXPECT_EQ(k->bytes[0], 0x00);
  EXPECT_EQ(k->bytes[27], 0x1b);
}

}  // namespace
}  // namespace hd::drivers

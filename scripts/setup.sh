#!/usr/bin/env bash
# Installs every Debian 12 package the station, its tools and its tests use.
# Idempotent; run as root (or with sudo). Nothing is downloaded from elsewhere.
set -euo pipefail

packages=(
  # toolchain
  build-essential python3 cmake ninja-build pkg-config ccache clang clang-format libclang-rt-14-dev
  # a CPU load beside the tests (scripts/test-under-load.sh)
  stress-ng
  # core + tools
  libeigen3-dev nlohmann-json3-dev libyaml-cpp-dev libcli11-dev libspdlog-dev
  # tests and benchmarks
  libgtest-dev libgmock-dev librapidcheck-dev libbenchmark-dev
  # images, calibration, video
  libopencv-dev libjpeg-dev libturbojpeg0-dev libpng-dev libtiff-dev
  # display: GL 3.3 through libepoxy, GLFW windows, Mesa llvmpipe + Xvfb for headless runs
  libepoxy-dev libglfw3-dev libgl1-mesa-dri libegl-mesa0 libegl-dev xvfb xauth
  # devices: HID head trackers, USB enumeration/hotplug, GigE (Aravis 0.8 + fake camera), V4L2 headers
  libhidapi-dev libusb-1.0-0-dev libaravis-dev aravis-tools linux-libc-dev libv4l-dev
  # the network hop: GStreamer 1.22 (rtpbin, RTP header extensions, x264, libav, srtp, netsim)
  libgstreamer1.0-dev libgstreamer-plugins-base1.0-dev libgstreamer-plugins-bad1.0-dev
  gstreamer1.0-tools gstreamer1.0-plugins-base gstreamer1.0-plugins-good gstreamer1.0-plugins-bad
  gstreamer1.0-plugins-ugly gstreamer1.0-libav
)

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#packages[@]} packages already installed"
  exit 0
fi
echo "setup: installing ${#missing[@]} packages: ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -q
$SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"

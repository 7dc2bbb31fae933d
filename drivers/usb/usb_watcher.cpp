#include "drivers/usb/usb_watcher.h"

#include <libusb.h>

#include "drivers/usb/usb_access_message.h"

namespace hd::drivers {
namespace {

bool wanted(const std::vector<UsbId>& ids, uint16_t vid, uint16_t pid) {
  return ids.empty() || matches(ids, vid, pid);
}

}  // namespace

UsbWatcher::UsbWatcher(std::vector<UsbId> ids, std::chrono::milliseconds poll_interval)
    : ids_(std::move(ids)), poll_interval_(poll_interval) {
  const int rc = libusb_init(&context_);
  if (rc != 0) {
    context_ = nullptr;
    reason_ = std::string("libusb unavailable: ") + libusb_strerror(rc) +
              " (no USB bus visible to this process?)";
    return;
  }
  hotplug_ = libusb_has_capability(LIBUSB_CAP_HAS_HOTPLUG) != 0;
}

UsbWatcher::~UsbWatcher() {
  stop();
  if (context_ != nullptr) libusb_exit(context_);
}

std::vector<UsbDeviceEntry> UsbWatcher::enumerate() {
  std::vector<UsbDeviceEntry> out;
  if (context_ == nullptr) return out;
  libusb_device** list = nullptr;
  const ssize_t n = libusb_get_device_list(context_, &list);
  if (n < 0) {
    reason_ = std::string("libusb_get_device_list: ") + libusb_strerror(static_cast<int>(n));
    return out;
  }
  for (ssize_t i = 0; i < n; ++i) {
    libusb_device_descriptor desc{};
    if (libusb_get_device_descriptor(list[i], &desc) != 0) continue;
    if (!wanted(ids_, desc.idVendor, desc.idProduct)) continue;
    UsbDeviceEntry e;
    e.bus = libusb_get_bus_number(list[i]);
    e.address = libusb_get_device_address(list[i]);
    e.vendor_id = desc.idVendor;
    e.product_id = desc.idProduct;
    libusb_device_handle* h = nullptr;
    const int rc = libusb_open(list[i], &h);
    if (rc == 0) {
      e.openable = true;
      unsigned char buf[128];
      if (desc.iProduct != 0 &&
          libusb_get_string_descriptor_ascii(h, desc.iProduct, buf, sizeof buf) > 0)
        e.product = reinterpret_cast<const char*>(buf);
      libusb_close(h);
    } else if (rc == LIBUSB_ERROR_ACCESS) {
      e.reason = usb_access_denied_message(e.bus, e.address, e.vendor_id, e.product_id, e.product);
    } else {
      e.reason = std::string("cannot open: ") + libusb_strerror(rc);
    }
    out.push_back(std::move(e));
  }
  libusb_free_device_list(list, 1);
  return out;
}

void UsbWatcher::deliver(const UsbEvent& event) {
  if (wanted(ids_, event.vendor_id, event.product_id) && callback_) callback_(event);
}

namespace {

int LIBUSB_CALL on_hotplug(libusb_context*, libusb_device* dev, libusb_hotplug_event event,
                           void* watcher) {
  libusb_device_descriptor desc{};
  if (libusb_get_device_descriptor(dev, &desc) != 0) return 0;
  static_cast<UsbWatcher*>(watcher)->deliver(
      {event == LIBUSB_HOTPLUG_EVENT_DEVICE_ARRIVED ? UsbEventKind::kArrived : UsbEventKind::kLeft,
       libusb_get_bus_number(dev), libusb_get_device_address(dev), desc.idVendor, desc.idProduct});
  return 0;  // stay registered
}

}  // namespace

void UsbWatcher::start(Callback callback) {
  if (running_ || context_ == nullptr) return;
  callback_ = std::move(callback);
  if (hotplug_) {
    const int rc = libusb_hotplug_register_callback(
        context_,
        static_cast<libusb_hotplug_event>(LIBUSB_HOTPLUG_EVENT_DEVICE_ARRIVED |
                                          LIBUSB_HOTPLUG_EVENT_DEVICE_LEFT),
        LIBUSB_HOTPLUG_ENUMERATE, LIBUSB_HOTPLUG_MATCH_ANY, LIBUSB_HOTPLUG_MATCH_ANY,
        LIBUSB_HOTPLUG_MATCH_ANY, &on_hotplug, this, &hotplug_handle_);
    hotplug_registered_ = rc == LIBUSB_SUCCESS;
    if (!hotplug_registered_) hotplug_ = false;  // fall back to polling
  }
  running_ = true;
  thread_ = std::thread([this] { run(); });
}

void UsbWatcher::stop() {
  if (!running_.exchange(false)) return;
  if (hotplug_registered_) {
    // Deregistering wakes libusb_handle_events in the watch thread.
    libusb_hotplug_deregister_callback(context_, hotplug_handle_);
    hotplug_registered_ = false;
  }
  if (thread_.joinable()) thread_.join();
}

void UsbWatcher::poll_once() {
  std::set<std::pair<int, int>> now;
  std::vector<UsbDeviceEntry> found = enumerate();
  for (const auto& e : found) {
    now.insert({e.bus, e.address});
    if (present_.count({e.bus, e.address}) == 0 && callback_)
      callback_({UsbEventKind::kArrived, e.bus, e.address, e.vendor_id, e.product_id});
  }
  for (const auto& p : present_)
    if (now.count(p) == 0 && callback_) callback_({UsbEventKind::kLeft, p.first, p.second, 0, 0});
  present_ = std::move(now);
}

void UsbWatcher::run() {
  while (running_.load()) {
    if (hotplug_) {
      timeval tv{0, 100'000};
      libusb_handle_events_timeout_completed(context_, &tv, nullptr);
    } else {
      poll_once();
      const auto until = std::chrono::steady_clock::now() + poll_interval_;
      while (running_.load() && std::chrono::steady_clock::now() < until)
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
  }
}

std::vector<DeviceInfo> probe_usb_devices(const std::vector<UsbId>& ids) {
  std::vector<DeviceInfo> out;
  UsbWatcher w(ids);
  for (const auto& e : w.enumerate()) {
    DeviceInfo d;
    d.kind = "usb";
    d.id = std::to_string(e.bus) + ":" + std::to_string(e.address);
    std::string label;
    for (const auto& id : ids)
      if (id.vendor_id == e.vendor_id && id.product_id == e.product_id) label = id.label;
    d.description =
        (e.product.empty() ? label : e.product) + " " + to_string(e.vendor_id, e.product_id);
    d.openable = e.openable;
    d.reason = e.reason;
    out.push_back(std::move(d));
  }
  return out;
}

}  // namespace hd::drivers

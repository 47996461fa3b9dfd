// The Embree device Plumage's scenes share, and its error reporting: Embree calls
// back with an error code; the next call that checks turns it into a plumage::Error.
#include "embree_device.h"

#include <mutex>
#include <string>

#include "plumage/common/error.h"

namespace plumage {
namespace {

std::mutex g_device_mu;
std::string g_device_error;

void on_device_error(void*, RTCError code, const char* msg) {
  std::lock_guard lock(g_device_mu);
  g_device_error = "Embree error " + std::to_string(int(code)) + ": " + (msg ? msg : "");
}

}  // namespace

RTCDevice shared_device() {
  static RTCDevice device = [] {
    RTCDevice d = rtcNewDevice(nullptr);
    if (!d) throw Error("cannot create the Embree device (is the CPU supported by this Embree build?)");
    rtcSetDeviceErrorFunction(d, on_device_error, nullptr);
    return d;
  }();
  return device;
}

void throw_if_device_error(const char* during) {
  std::lock_guard lock(g_device_mu);
  if (g_device_error.empty()) return;
  std::string msg = std::move(g_device_error);
  g_device_error.clear();
  throw Error(std::string(during) + ": " + msg);
}

}  // namespace plumage

#pragma once
// Polls a condition for up to 60 s: waits for a device thread, asserts nothing about speed.
#include <chrono>
#include <thread>

template <class F>
bool eventually(F f) {
  for (int i = 0; i < 12000; ++i) {
    if (f()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return f();
}

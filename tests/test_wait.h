#pragma once
// Polls a condition for up to 60 s: waits for a device thread or a peer, asserts nothing about
// speed (the bound only ends a hang; the suite must pass with the CPUs saturated).
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

// SPDX-License-Identifier: MIT
#include "interrupt.hpp"

#include <csignal>

namespace depath::cli {

std::atomic<bool> g_interrupted{false};

namespace {
extern "C" void on_interrupt(int) { g_interrupted.store(true); }
}  // namespace

InterruptGuard::InterruptGuard() {
  g_interrupted = false;
  previous_ = std::signal(SIGINT, on_interrupt);
}
InterruptGuard::~InterruptGuard() { std::signal(SIGINT, previous_); }

}  // namespace depath::cli

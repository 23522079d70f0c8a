// SPDX-License-Identifier: MIT
// Ctrl-C during a job, for `depath solve` and the network subcommands: while an
// InterruptGuard lives, SIGINT only sets `g_interrupted`; the local solve polls it (and keeps
// the best path so far), RemoteClient::watch polls it (and asks the server to cancel).
#pragma once

#include <atomic>

namespace depath::cli {

extern std::atomic<bool> g_interrupted;

class InterruptGuard {
 public:
  InterruptGuard();   ///< clears g_interrupted and installs the handler
  ~InterruptGuard();  ///< restores the previous handler
  InterruptGuard(const InterruptGuard&) = delete;
  InterruptGuard& operator=(const InterruptGuard&) = delete;

 private:
  void (*previous_)(int);
};

}  // namespace depath::cli

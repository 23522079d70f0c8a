// SPDX-License-Identifier: MIT
// Tells ThreadSanitizer how gRPC orders a reactor's operations and reactions.
//
// gRPC sequences each call with its own synchronisation (absl::Mutex, atomics in libgrpc).
// Debian's gRPC is not built with TSan, so TSan cannot see it: a reactor built on one gRPC
// thread and deleted in OnDone on another, or a buffer filled in one OnReadDone and read in
// the next, look like data races. grpc_handoff and grpc_reaction state the callback API's
// guarantees and nothing more:
//   * what a thread did before it starts an operation (StartRead, StartWrite, Finish) happens
//     before that operation's reaction (OnReadDone, OnWriteDone) and before OnDone;
//   * the reactor is fully built before gRPC runs any reaction (OnCancel included).
// Code that touches a reactor after handing it to gRPC, or two of our threads touching it
// without a lock, are still reported. finish_from_our_thread adds the one gap a hand-off
// cannot close (Finish started outside gRPC's reactions). Outside TSan builds the
// annotations compile to nothing.
#pragma once

#include <grpcpp/support/status.h>

#if defined(__SANITIZE_THREAD__)
#define DEPATH_TSAN 1
#elif defined(__has_feature)
#if __has_feature(thread_sanitizer)
#define DEPATH_TSAN 1
#endif
#endif

#ifdef DEPATH_TSAN
#include <sanitizer/tsan_interface.h>
// The TSan runtime's dynamic annotations (no public header declares them).
extern "C" void AnnotateIgnoreReadsBegin(const char* file, int line);
extern "C" void AnnotateIgnoreReadsEnd(const char* file, int line);
extern "C" void AnnotateIgnoreWritesBegin(const char* file, int line);
extern "C" void AnnotateIgnoreWritesEnd(const char* file, int line);
#endif

namespace depath::service {

/// Call right before handing `reactor` to gRPC: immediately before StartRead, StartWrite and
/// Finish (whatever the thread does between this call and the operation is not covered), and
/// at the end of the constructor (operations started there begin when the handler returns).
inline void grpc_handoff([[maybe_unused]] const void* reactor) {
#ifdef DEPATH_TSAN
  __tsan_release(const_cast<void*>(reactor));
#endif
}

/// Call first in every reaction gRPC runs on `reactor`: OnReadDone, OnWriteDone, OnCancel,
/// OnDone.
inline void grpc_reaction([[maybe_unused]] const void* reactor) {
#ifdef DEPATH_TSAN
  __tsan_acquire(const_cast<void*>(reactor));
#endif
}

/// Finishes `reactor`'s call from a thread of ours (a task, the hub's dispatcher) or from a
/// reaction (where the scope is harmless: Finish's own accesses are gRPC's): hands the
/// reactor over, then runs Finish with TSan ignoring this thread's plain reads and writes. Finish goes on using the call after the hand-off: it
/// serialises the reply and marks the call's context, and only gRPC orders that before its
/// clean-up on another thread (the reply, context and reactor freed after OnDone). A
/// suppression naming Finish matches only a stack TSan still has, and under load it loses
/// the older one ("failed to restore the stack": clean-clone CI runs 8 and 9). Locks and
/// atomics stay visible, and everything the thread did before the hand-off is still checked.
template <class Reactor>
void finish_from_our_thread(Reactor& reactor, const grpc::Status& status) {
  grpc_handoff(&reactor);
#ifdef DEPATH_TSAN
  AnnotateIgnoreReadsBegin(__FILE__, __LINE__);
  AnnotateIgnoreWritesBegin(__FILE__, __LINE__);
#endif
  reactor.Finish(status);
#ifdef DEPATH_TSAN
  AnnotateIgnoreWritesEnd(__FILE__, __LINE__);
  AnnotateIgnoreReadsEnd(__FILE__, __LINE__);
#endif
}

}  // namespace depath::service

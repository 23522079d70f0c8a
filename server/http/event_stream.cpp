// SPDX-License-Identifier: MIT
#include "http/event_stream.hpp"

#include "event_log.hpp"
#include "http/job_json.hpp"
#include "service_error.hpp"

#include <chrono>
#include <condition_variable>
#include <mutex>

namespace depath::service::http {

namespace {

constexpr auto kKeepAlive = std::chrono::seconds(15);
constexpr auto kPoll = std::chrono::milliseconds(250);  // how soon a stopping listener is noticed

/// Wakes the stream's HTTP thread when the job's log has news (called by the event hub).
struct Wakeup final : EventSubscriber {
  void notify() override {
    {
      std::lock_guard lock(mutex);
      pending = true;
    }
    cv.notify_all();
  }
  /// Waits until notified or `timeout`; clears the flag.
  void wait(std::chrono::milliseconds timeout) {
    std::unique_lock lock(mutex);
    cv.wait_for(lock, timeout, [&] { return pending; });
    pending = false;
  }
  std::mutex mutex;
  std::condition_variable cv;
  bool pending = false;
};

struct Stream {
  std::shared_ptr<EventLog> log;
  std::shared_ptr<Wakeup> wakeup = std::make_shared<Wakeup>();
  uint64_t cursor = 0;
};

std::string frame(const v1::JobEvent& event) {
  return "id: " + std::to_string(event.sequence()) + "\nevent: " + event_name(event) +
         "\ndata: " + event_json(event).dump() + "\n\n";
}

// The sequence to resume after: Last-Event-ID, else ?after=N, else 0.
uint64_t resume_after(const httplib::Request& req) {
  std::string text;
  const char* source = nullptr;
  if (req.has_header("Last-Event-ID")) {
    text = req.get_header_value("Last-Event-ID");
    source = "Last-Event-ID";
  } else if (req.has_param("after")) {
    text = req.get_param_value("after");
    source = "after";
  } else {
    return 0;
  }
  if (text.empty()) return 0;
  uint64_t value = 0;
  for (char c : text) {
    if (c < '0' || c > '9' || value > (UINT64_MAX - 9) / 10) {
      throw ServiceError(grpc::StatusCode::INVALID_ARGUMENT,
                         std::string(source) + " must be an event sequence number (got '" + text.substr(0, 40) + "')");
    }
    value = value * 10 + static_cast<uint64_t>(c - '0');
  }
  return value;
}

}  // namespace

void add_event_stream(httplib::Server& server, HttpContext& ctx) {
  server.Get(R"(/v1/jobs/([^/]+)/events)", [&ctx](const httplib::Request& req, httplib::Response& res) {
    api_call(ctx, req, res, false, [&] {
      auto stream = std::make_shared<Stream>();
      stream->cursor = resume_after(req);
      stream->log = ctx.service.jobs.events(req.matches[1]);  // NOT_FOUND for an unknown job
      if (ctx.event_streams.fetch_add(1) >= ctx.max_event_streams) {
        ctx.event_streams.fetch_sub(1);
        throw ServiceError(grpc::StatusCode::UNAVAILABLE,
                           "too many open event streams (" + std::to_string(ctx.max_event_streams) +
                               ", from --http-threads); retry later or use gRPC WatchJob");
      }
      stream->log->subscribe(stream->wakeup);
      ctx.service.metrics.watcher_started("http");
      res.set_header("Cache-Control", "no-cache");
      res.set_header("X-Accel-Buffering", "no");
      res.set_chunked_content_provider(
          "text/event-stream",
          [&ctx, stream](size_t offset, httplib::DataSink& sink) {
            if (offset == 0 && !sink.write("retry: 2000\n\n", 13)) return false;
            auto idle_since = std::chrono::steady_clock::now();
            for (;;) {
              std::string out;
              bool terminal = false;
              while (EventPtr next = stream->log->next_after(stream->cursor)) {
                stream->cursor = next->sequence();
                out += frame(*next);
                if (is_terminal_event(*next)) {
                  terminal = true;
                  break;
                }
              }
              if (!out.empty()) {
                if (!sink.write(out.data(), out.size())) return false;
                if (terminal) sink.done();
                return true;
              }
              // Nothing new: a log closed before the cursor (resumed after the end), or a
              // listener going away, ends the stream.
              if (stream->log->closed() || ctx.stopping.load() || ctx.service.release_watchers.load()) {
                sink.done();
                return true;
              }
              if (std::chrono::steady_clock::now() - idle_since >= kKeepAlive) {
                return sink.write(": keep-alive\n\n", 14);
              }
              stream->wakeup->wait(kPoll);
            }
          },
          [&ctx, stream](bool) {
            stream->log->unsubscribe(stream->wakeup);
            ctx.service.metrics.watcher_ended("http");
            ctx.event_streams.fetch_sub(1);
          });
    });
  });
}

}  // namespace depath::service::http

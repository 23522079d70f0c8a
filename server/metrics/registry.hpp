// SPDX-License-Identifier: MIT
// A small metrics registry: counters, gauges and histograms with labels, written in the
// Prometheus text exposition format (version 0.0.4).
//
// Inputs: families declared once (name, help, type, histogram buckets), then updates from
// any thread; collectors (callbacks run at each scrape) set gauges that mirror live state.
// Outputs: exposition() — every family with its # HELP / # TYPE lines and its series, label
// values escaped, histograms as cumulative _bucket{le=...} plus _sum and _count.
// Guarantees: thread-safe; an update costs one mutex and a map lookup (never I/O); updating an
// undeclared family or with the wrong type throws std::logic_error (a programming error).
#pragma once

#include <functional>
#include <map>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

namespace depath::service {

using MetricLabels = std::vector<std::pair<std::string, std::string>>;

class MetricsRegistry {
 public:
  enum class Type { counter, gauge, histogram };

  /// Declares a family. Names follow Prometheus rules ([a-zA-Z_:][a-zA-Z0-9_:]*); counters
  /// should end in _total. `buckets` (histograms only) are upper bounds, increasing.
  void declare(const std::string& name, Type type, const std::string& help, std::vector<double> buckets = {});

  void inc(const std::string& name, const MetricLabels& labels = {}, double by = 1);  ///< counter or gauge
  /// Gauge, or a counter kept elsewhere (its source only counts up).
  void set(const std::string& name, const MetricLabels& labels, double value);
  void observe(const std::string& name, const MetricLabels& labels, double value);     ///< histogram

  /// Runs at every exposition, before the text is written (e.g. sets gauges from live state).
  void add_collector(std::function<void(MetricsRegistry&)> collector);

  /// The current value of a counter or gauge series (0 if it has no sample yet); for tests.
  double value(const std::string& name, const MetricLabels& labels = {});

  std::string exposition();

 private:
  struct Series {
    double value = 0;             // counter / gauge
    std::vector<uint64_t> counts;  // histogram: per bucket (not cumulative), +Inf last
    double sum = 0;
  };
  struct Family {
    Type type;
    std::string help;
    std::vector<double> buckets;
    std::map<std::string, Series> series;  // by the rendered label set "{a="x",b="y"}"
  };
  Family& family_locked(const std::string& name, Type type);
  Series& series_locked(Family& f, const MetricLabels& labels);

  std::mutex mutex_;
  std::map<std::string, Family> families_;
  std::vector<std::function<void(MetricsRegistry&)>> collectors_;
};

}  // namespace depath::service

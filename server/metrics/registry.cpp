// SPDX-License-Identifier: MIT
#include "metrics/registry.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

namespace depath::service {

namespace {

// Label values escape backslash, double quote and newline (exposition format 0.0.4).
std::string escape_label(const std::string& v) {
  std::string out;
  out.reserve(v.size());
  for (char c : v) {
    if (c == '\\') out += "\\\\";
    else if (c == '"') out += "\\\"";
    else if (c == '\n') out += "\\n";
    else out += c;
  }
  return out;
}

// HELP text escapes backslash and newline only.
std::string escape_help(const std::string& v) {
  std::string out;
  for (char c : v) {
    if (c == '\\') out += "\\\\";
    else if (c == '\n') out += "\\n";
    else out += c;
  }
  return out;
}

std::string render_labels(const MetricLabels& labels) {
  if (labels.empty()) return "";
  std::string out = "{";
  for (size_t i = 0; i < labels.size(); ++i) {
    if (i) out += ',';
    out += labels[i].first + "=\"" + escape_label(labels[i].second) + '"';
  }
  return out + '}';
}

// Adds one more label to a rendered label set ("" or "{...}").
std::string with_label(const std::string& rendered, const std::string& name, const std::string& value) {
  const std::string extra = name + "=\"" + value + '"';
  if (rendered.empty()) return '{' + extra + '}';
  return rendered.substr(0, rendered.size() - 1) + ',' + extra + '}';
}

std::string number(double v) {
  if (std::isnan(v)) return "NaN";
  if (std::isinf(v)) return v > 0 ? "+Inf" : "-Inf";
  if (v == std::floor(v) && std::fabs(v) < 1e15) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.0f", v);
    return buf;
  }
  char buf[40];
  for (int digits : {15, 17}) {  // the shortest of the two that reads back exactly
    std::snprintf(buf, sizeof buf, "%.*g", digits, v);
    if (std::strtod(buf, nullptr) == v) break;
  }
  return buf;
}

const char* type_name(MetricsRegistry::Type t) {
  switch (t) {
    case MetricsRegistry::Type::counter: return "counter";
    case MetricsRegistry::Type::gauge: return "gauge";
    case MetricsRegistry::Type::histogram: return "histogram";
  }
  return "untyped";
}

}  // namespace

void MetricsRegistry::declare(const std::string& name, Type type, const std::string& help,
                              std::vector<double> buckets) {
  std::lock_guard lock(mutex_);
  Family f{type, help, std::move(buckets), {}};
  families_.insert_or_assign(name, std::move(f));
}

MetricsRegistry::Family& MetricsRegistry::family_locked(const std::string& name, Type type) {
  auto it = families_.find(name);
  if (it == families_.end()) throw std::logic_error("metric family '" + name + "' was not declared");
  if (it->second.type != type && !(type == Type::gauge && it->second.type == Type::counter))
    throw std::logic_error("metric family '" + name + "' used with the wrong type");
  return it->second;
}

MetricsRegistry::Series& MetricsRegistry::series_locked(Family& f, const MetricLabels& labels) {
  Series& s = f.series[render_labels(labels)];
  if (f.type == Type::histogram && s.counts.empty()) s.counts.assign(f.buckets.size() + 1, 0);
  return s;
}

void MetricsRegistry::inc(const std::string& name, const MetricLabels& labels, double by) {
  std::lock_guard lock(mutex_);
  Family& f = family_locked(name, Type::gauge);  // counters and gauges both count up
  series_locked(f, labels).value += by;
}

void MetricsRegistry::set(const std::string& name, const MetricLabels& labels, double value) {
  std::lock_guard lock(mutex_);
  Family& f = family_locked(name, Type::gauge);  // or a counter mirrored from elsewhere
  series_locked(f, labels).value = value;
}

void MetricsRegistry::observe(const std::string& name, const MetricLabels& labels, double value) {
  std::lock_guard lock(mutex_);
  Family& f = family_locked(name, Type::histogram);
  Series& s = series_locked(f, labels);
  size_t b = 0;
  while (b < f.buckets.size() && value > f.buckets[b]) ++b;
  ++s.counts[b];
  s.sum += value;
}

void MetricsRegistry::add_collector(std::function<void(MetricsRegistry&)> collector) {
  std::lock_guard lock(mutex_);
  collectors_.push_back(std::move(collector));
}

double MetricsRegistry::value(const std::string& name, const MetricLabels& labels) {
  std::lock_guard lock(mutex_);
  auto it = families_.find(name);
  if (it == families_.end()) return 0;
  auto s = it->second.series.find(render_labels(labels));
  return s == it->second.series.end() ? 0 : s->second.value;
}

std::string MetricsRegistry::exposition() {
  std::vector<std::function<void(MetricsRegistry&)>> collectors;
  {
    std::lock_guard lock(mutex_);
    collectors = collectors_;
  }
  for (auto& c : collectors) c(*this);  // outside the lock: they call set()

  std::lock_guard lock(mutex_);
  std::string out;
  for (const auto& [name, f] : families_) {
    out += "# HELP " + name + ' ' + escape_help(f.help) + '\n';
    out += "# TYPE " + name + ' ' + type_name(f.type) + '\n';
    for (const auto& [labels, s] : f.series) {
      if (f.type != Type::histogram) {
        out += name + labels + ' ' + number(s.value) + '\n';
        continue;
      }
      uint64_t cumulative = 0;
      for (size_t b = 0; b < f.buckets.size(); ++b) {
        cumulative += s.counts[b];
        out += name + "_bucket" + with_label(labels, "le", number(f.buckets[b])) + ' ' +
               number(static_cast<double>(cumulative)) + '\n';
      }
      cumulative += s.counts.back();
      out += name + "_bucket" + with_label(labels, "le", "+Inf") + ' ' + number(static_cast<double>(cumulative)) +
             '\n';
      out += name + "_sum" + labels + ' ' + number(s.sum) + '\n';
      out += name + "_count" + labels + ' ' + number(static_cast<double>(cumulative)) + '\n';
    }
  }
  return out;
}

}  // namespace depath::service

// SPDX-License-Identifier: MIT
// Byte encoding of DeState: a magic, a version, then the fields in a fixed order, numbers as
// their raw little-endian bytes (bit-exact doubles), vectors prefixed by their length.
#include "depath/de/checkpoint.hpp"

#include <bit>
#include <cstring>

#include "depath/util/error.hpp"

namespace depath {

namespace {

static_assert(std::endian::native == std::endian::little, "checkpoints are written little-endian");
constexpr char kMagic[8] = {'D', 'P', 'D', 'E', 'C', 'K', 'P', 'T'};
constexpr uint32_t kVersion = 1;

class Writer {
 public:
  template <class T>
  void put(T v) {
    out.append(reinterpret_cast<const char*>(&v), sizeof v);
  }
  void put(const std::vector<double>& v) {
    put<uint64_t>(v.size());
    if (!v.empty()) out.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(double));
  }
  void put(const std::string& s) {
    put<uint64_t>(s.size());
    out.append(s);
  }
  std::string out;
};

class Reader {
 public:
  explicit Reader(std::string_view in) : in_(in) {}
  template <class T>
  T get() {
    need(sizeof(T));
    T v;
    std::memcpy(&v, in_.data() + pos_, sizeof v);
    pos_ += sizeof v;
    return v;
  }
  std::vector<double> doubles() {
    const auto count = get<uint64_t>();
    if (count > (in_.size() - pos_) / sizeof(double)) fail("a vector runs past the end");
    std::vector<double> v(count);
    if (count > 0) std::memcpy(v.data(), in_.data() + pos_, count * sizeof(double));  // data() may be null
    pos_ += count * sizeof(double);
    return v;
  }
  std::string text() {
    const auto count = get<uint64_t>();
    need(count);
    std::string s(in_.substr(pos_, count));
    pos_ += count;
    return s;
  }
  bool at_end() const { return pos_ == in_.size(); }
  [[noreturn]] static void fail(const std::string& what) {
    throw Error(ErrorCode::invalid_argument, "not a valid DE checkpoint: " + what);
  }

 private:
  void need(uint64_t n) {
    if (n > in_.size() - pos_) fail("truncated");
  }
  std::string_view in_;
  size_t pos_ = 0;
};

}  // namespace

std::vector<double> DeState::best_vector() const {
  if (best_index >= 0) {
    const auto begin = agents.begin() + static_cast<std::ptrdiff_t>(best_index) * dimension;
    return {begin, begin + dimension};
  }
  return saved_best;
}

std::string encode_de_state(const DeState& s) {
  Writer w;
  w.out.append(kMagic, sizeof kMagic);
  w.put<uint32_t>(kVersion);
  w.put<int32_t>(s.population);
  w.put<int32_t>(s.dimension);
  w.put<uint64_t>(s.seed);
  w.put(s.strategy);
  w.put<int32_t>(s.generation);
  w.put(s.agents);
  w.put(s.energies);
  w.put<double>(s.best_energy);
  w.put<int32_t>(s.best_index);
  w.put(s.saved_best);
  w.put<int64_t>(s.evaluations);
  w.put<int32_t>(s.restarts);
  w.put<int32_t>(s.since_improvement);
  w.put<uint8_t>(s.restart_pending ? 1 : 0);
  w.put(s.lowest_since_restart);
  w.put(s.strategy_memory);
  return std::move(w.out);
}

DeState decode_de_state(std::string_view bytes) {
  if (bytes.size() < sizeof kMagic || std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0) {
    Reader::fail("bad magic");
  }
  Reader r(bytes.substr(sizeof kMagic));
  const auto version = r.get<uint32_t>();
  if (version != kVersion) {
    Reader::fail("format version " + std::to_string(version) + ", this build reads " +
                 std::to_string(kVersion));
  }
  DeState s;
  s.population = r.get<int32_t>();
  s.dimension = r.get<int32_t>();
  s.seed = r.get<uint64_t>();
  s.strategy = r.text();
  s.generation = r.get<int32_t>();
  s.agents = r.doubles();
  s.energies = r.doubles();
  s.best_energy = r.get<double>();
  s.best_index = r.get<int32_t>();
  s.saved_best = r.doubles();
  s.evaluations = r.get<int64_t>();
  s.restarts = r.get<int32_t>();
  s.since_improvement = r.get<int32_t>();
  s.restart_pending = r.get<uint8_t>() != 0;
  s.lowest_since_restart = r.doubles();
  s.strategy_memory = r.doubles();
  if (!r.at_end()) Reader::fail("trailing bytes");
  const auto N = static_cast<size_t>(std::max(0, s.population));
  const auto n = static_cast<size_t>(std::max(0, s.dimension));
  if (s.population < 4 || s.dimension < 1 || s.agents.size() != N * n || s.energies.size() != N ||
      s.best_index < -1 || s.best_index >= s.population ||
      (s.best_index < 0 && !s.saved_best.empty() && s.saved_best.size() != n) || s.generation < 0) {
    Reader::fail("inconsistent sizes");
  }
  return s;
}

}  // namespace depath

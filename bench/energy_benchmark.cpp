// SPDX-License-Identifier: MIT
// Cost of one segment-energy evaluation (the unit of refinement work) for the angle
// energies, on every face of a 41 x 41 peaks grid.
//
//   build/bench/energy_benchmark
//
// Thousands of refined paths per second need well under a microsecond per segment; this
// figure used to be a timed test (EnergyCost.SegmentEvaluationIsCheap), which could fail on
// a loaded or sanitized build, so it is a benchmark now.
#include "depath/energy/energy.hpp"
#include "depath/generators/surfaces.hpp"

#include <benchmark/benchmark.h>

#include <memory>
#include <utility>
#include <vector>

namespace {

using namespace depath;

struct Segments {
  Mesh mesh;
  std::vector<std::pair<SurfacePoint, SurfacePoint>> ends;  // one segment across each face
  std::vector<int> faces;
};

const Segments& segments() {
  static const Segments s = [] {
    GridOptions options;
    options.n = 41;
    options.height = GridHeight::peaks;
    Segments out{make_grid(options), {}, {}};
    for (int f = 0; f < out.mesh.num_faces(); ++f) {
      const auto& t = out.mesh.face(f);
      out.ends.emplace_back(SurfacePoint::on_edge(t[0], t[1], 0.3), SurfacePoint::on_edge(t[1], t[2], 0.6));
      out.faces.push_back(f);
    }
    return out;
  }();
  return s;
}

void run(benchmark::State& state, const EnergySpec& spec) {
  const Segments& s = segments();
  const auto energy = make_energy(s.mesh, spec);
  for (auto _ : state) {
    double sum = 0.0;
    for (size_t i = 0; i < s.faces.size(); ++i) sum += energy->segment_energy(s.ends[i].first, s.ends[i].second, s.faces[i]);
    benchmark::DoNotOptimize(sum);
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(s.faces.size()));
}

void BM_VectorFieldSegment(benchmark::State& state) {
  EnergySpec spec;
  spec.kind = EnergyKind::vector_field;
  spec.field_from_height = true;
  spec.rotate_degrees = 90.0;
  run(state, spec);
}

void BM_ConstantSlopeSegment(benchmark::State& state) {
  EnergySpec spec;
  spec.kind = EnergyKind::constant_slope;
  spec.slope = 0.3;
  run(state, spec);
}

BENCHMARK(BM_VectorFieldSegment);
BENCHMARK(BM_ConstantSlopeSegment);

}  // namespace

BENCHMARK_MAIN();

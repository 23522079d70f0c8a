// libFuzzer target: job-spec validation (validate_job, which also builds the energy) on a small
// grid, with every field taken from the fuzz bytes; a spec that validates and is cheap is also
// solved. Only depath::Error may come out; crashes, sanitizer reports and hangs are findings.
#include <fuzzer/FuzzedDataProvider.h>

#include <cstdint>

#include "depath/generators/surfaces.hpp"
#include "depath/solve/job.hpp"
#include "depath/solve/solve.hpp"
#include "depath/util/error.hpp"

namespace {

const depath::Mesh& grid() {
  static const depath::Mesh mesh = [] {
    depath::GridOptions o;
    o.n = 6;
    o.height = depath::GridHeight::peaks;
    return depath::make_grid(o);
  }();
  return mesh;
}

double any_double(FuzzedDataProvider& in) {
  switch (in.ConsumeIntegralInRange<int>(0, 3)) {
    case 0:
      return in.ConsumeFloatingPoint<double>();  // any bit pattern class, NaN and inf included
    case 1:
      return in.ConsumeFloatingPointInRange<double>(-2.0, 2.0);
    case 2:
      return in.PickValueInArray({0.0, 1e-308, 1e308, 1e-100, 1e100, -0.0, 1.0});
    default:
      return in.ConsumeProbability<double>();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  FuzzedDataProvider in(data, size);
  const depath::Mesh& mesh = grid();
  const int nv = mesh.num_vertices();
  depath::JobSpec job;
  job.source = in.ConsumeIntegralInRange<int>(-2, nv + 1);
  job.target = in.ConsumeIntegralInRange<int>(-2, nv + 1);
  job.method = in.PickValueInArray({depath::Method::de, depath::Method::fmm, depath::Method::descent});
  job.refine = in.ConsumeBool();
  job.de.population = in.ConsumeIntegralInRange<int>(-1, 12);
  job.de.generations = in.ConsumeIntegralInRange<int>(-1, 4);
  job.de.stall = in.ConsumeIntegralInRange<int>(-1, 3);
  job.de.F = any_double(in);
  job.de.CR = any_double(in);
  job.de.strategy = in.PickValueInArray({"rand1bin", "shade", "", "bogus"});
  job.de.seed_with_problem = in.ConsumeBool();
  job.seed = in.ConsumeIntegral<uint64_t>();
  job.threads = 1;
  job.energy.kind = in.PickValueInArray(
      {depath::EnergyKind::geodesic, depath::EnergyKind::vector_field, depath::EnergyKind::constant_slope});
  job.energy.smoothness = any_double(in);
  job.energy.field_from_height = in.ConsumeBool();
  job.energy.up_axis = in.ConsumeIntegralInRange<int>(-1, 3);
  job.energy.rotate_degrees = any_double(in);
  job.energy.slope = any_double(in);
  const int density_size = in.PickValueInArray({0, nv, nv - 1, 1});
  for (int i = 0; i < density_size && in.remaining_bytes() > 0; ++i)
    job.energy.density.push_back(any_double(in));
  if (in.ConsumeBool()) {
    const int field_size = in.PickValueInArray({nv, 1});
    for (int i = 0; i < field_size && in.remaining_bytes() > 0; ++i)
      job.energy.field.emplace_back(any_double(in), any_double(in), any_double(in));
  }
  try {
    depath::validate_job(mesh, job);
    (void)depath::solve(mesh, job);
  } catch (const depath::Error&) {
  }
  return 0;
}

// SPDX-License-Identifier: MIT
#include "depath/wire/job.hpp"

#include "depath/util/error.hpp"
#include "vec.hpp"

#include <string>

namespace depath::wire {

v1::Method method_to_proto(Method m) {
  switch (m) {
    case Method::de: return v1::METHOD_DE;
    case Method::fmm: return v1::METHOD_FMM;
    case Method::descent: return v1::METHOD_DESCENT;
  }
  return v1::METHOD_UNSPECIFIED;
}

Method method_from_proto(int m) {
  switch (m) {
    case v1::METHOD_UNSPECIFIED:
    case v1::METHOD_DE: return Method::de;
    case v1::METHOD_FMM: return Method::fmm;
    case v1::METHOD_DESCENT: return Method::descent;
    default: throw Error(ErrorCode::invalid_argument, "unknown method value " + std::to_string(m));
  }
}

JobSpec job_from_proto(const v1::JobSpec& spec) {
  JobSpec job;
  job.source = spec.source();
  job.target = spec.target();
  const auto& e = spec.energy();
  switch (e.kind()) {
    case v1::ENERGY_KIND_UNSPECIFIED:
    case v1::ENERGY_KIND_GEODESIC: job.energy.kind = EnergyKind::geodesic; break;
    case v1::ENERGY_KIND_VECTOR_FIELD: job.energy.kind = EnergyKind::vector_field; break;
    case v1::ENERGY_KIND_CONSTANT_SLOPE: job.energy.kind = EnergyKind::constant_slope; break;
    default: throw Error(ErrorCode::invalid_argument, "unknown energy kind value " + std::to_string(e.kind()));
  }
  job.energy.density.assign(e.density().begin(), e.density().end());
  job.energy.field.reserve(e.field_size());
  for (const auto& v : e.field()) job.energy.field.push_back(get_vec(v));
  job.energy.field_from_height = e.field_from_height();
  job.energy.rotate_degrees = e.rotate_degrees();
  job.energy.slope = e.slope();
  switch (e.up()) {
    case v1::AXIS_X: job.energy.up_axis = 0; break;
    case v1::AXIS_Y: job.energy.up_axis = 1; break;
    case v1::AXIS_UNSPECIFIED:
    case v1::AXIS_Z: job.energy.up_axis = 2; break;
    default: throw Error(ErrorCode::invalid_argument, "unknown up axis value " + std::to_string(e.up()));
  }
  job.energy.smoothness = e.smoothness();
  job.method = method_from_proto(spec.method());
  job.refine = spec.refine();
  const auto& de = spec.de();
  if (de.has_population()) job.de.population = de.population();
  if (de.has_generations()) job.de.generations = de.generations();
  if (de.has_stall()) job.de.stall = de.stall();
  if (de.has_f()) job.de.F = de.f();
  if (de.has_cr()) job.de.CR = de.cr();
  if (de.has_strategy()) job.de.strategy = de.strategy();
  job.de.seed_with_problem = de.seed_with_problem();
  if (spec.has_seed()) job.seed = spec.seed();
  job.path_every = spec.path_every();
  return job;
}

v1::JobSpec job_to_proto(const JobSpec& job, const std::string& mesh_id) {
  v1::JobSpec spec;
  spec.set_mesh_id(mesh_id);
  spec.set_source(job.source);
  spec.set_target(job.target);
  auto* e = spec.mutable_energy();
  switch (job.energy.kind) {
    case EnergyKind::geodesic: e->set_kind(v1::ENERGY_KIND_GEODESIC); break;
    case EnergyKind::vector_field: e->set_kind(v1::ENERGY_KIND_VECTOR_FIELD); break;
    case EnergyKind::constant_slope: e->set_kind(v1::ENERGY_KIND_CONSTANT_SLOPE); break;
  }
  e->mutable_density()->Add(job.energy.density.begin(), job.energy.density.end());
  for (const auto& v : job.energy.field) set_vec(v, e->add_field());
  e->set_field_from_height(job.energy.field_from_height);
  e->set_rotate_degrees(job.energy.rotate_degrees);
  e->set_slope(job.energy.slope);
  e->set_up(job.energy.up_axis == 0 ? v1::AXIS_X : job.energy.up_axis == 1 ? v1::AXIS_Y : v1::AXIS_Z);
  e->set_smoothness(job.energy.smoothness);
  spec.set_method(method_to_proto(job.method));
  spec.set_refine(job.refine);
  auto* de = spec.mutable_de();
  de->set_population(job.de.population);
  de->set_generations(job.de.generations);
  de->set_stall(job.de.stall);
  de->set_f(job.de.F);
  de->set_cr(job.de.CR);
  de->set_strategy(job.de.strategy);
  de->set_seed_with_problem(job.de.seed_with_problem);
  spec.set_seed(job.seed);
  spec.set_path_every(job.path_every);
  return spec;
}

const char* state_name(v1::JobState state) {
  switch (state) {
    case v1::JOB_STATE_QUEUED: return "queued";
    case v1::JOB_STATE_RUNNING: return "running";
    case v1::JOB_STATE_SUCCEEDED: return "succeeded";
    case v1::JOB_STATE_FAILED: return "failed";
    case v1::JOB_STATE_CANCELLED: return "cancelled";
    default: return "unspecified";
  }
}

bool is_terminal(v1::JobState state) {
  return state == v1::JOB_STATE_SUCCEEDED || state == v1::JOB_STATE_FAILED || state == v1::JOB_STATE_CANCELLED;
}

}  // namespace depath::wire

// SPDX-License-Identifier: MIT
// Jobs on the wire: depath.v1.JobSpec <-> the core's JobSpec, methods, job states.
//
// Inputs: messages from a peer (any enum value) or core values. Outputs: the other form.
// Guarantees: job_from_proto rejects enum values this build does not know with
// Error(invalid_argument); range checks are left to depath::validate_job (done once, by the
// server at submit and by solve()). job_to_proto sets every DE option explicitly.
#pragma once

#include "depath/solve/job.hpp"
#include "depath/v1/job.pb.h"

#include <string>

namespace depath::wire {

namespace v1 = ::depath::v1;

/// The core's job from its message. Throws Error(invalid_argument) for enum values this
/// build does not know. Range checks are left to depath::validate_job.
JobSpec job_from_proto(const v1::JobSpec& spec);
/// The message of a core job on mesh `mesh_id` (every DE option is set explicitly).
v1::JobSpec job_to_proto(const JobSpec& job, const std::string& mesh_id);

v1::Method method_to_proto(Method m);
/// METHOD_UNSPECIFIED is `de`; throws Error(invalid_argument) for an unknown value.
Method method_from_proto(int m);

const char* state_name(v1::JobState state);  ///< "queued", "running", ...
bool is_terminal(v1::JobState state);

}  // namespace depath::wire

// SPDX-License-Identifier: MIT
// The wire layer in one include: conversions between the core's types and the depath.v1
// protobuf messages, shared by the server (depathd) and the network client (depath
// upload/submit/run/...). One header per kind of message:
#pragma once

#include "depath/wire/job.hpp"     // jobs, methods, job states
#include "depath/wire/mesh.hpp"    // mesh ids, mesh info
#include "depath/wire/result.hpp"  // paths, results, progress, writing a received result
#include "depath/wire/status.hpp"  // error codes <-> gRPC status codes

// SPDX-License-Identifier: MIT
// Internal to the wire layer: Vec3 <-> depath.v1.Vec3.
#pragma once

#include "depath/mesh/mesh.hpp"
#include "depath/v1/mesh.pb.h"

namespace depath::wire {

inline void set_vec(const Vec3& v, ::depath::v1::Vec3* out) {
  out->set_x(v.x());
  out->set_y(v.y());
  out->set_z(v.z());
}
inline Vec3 get_vec(const ::depath::v1::Vec3& v) { return {v.x(), v.y(), v.z()}; }

}  // namespace depath::wire

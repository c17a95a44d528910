// The reference's vectors are twinray's one scalar 3-vector (math/vec3.h) on its scalar type, normalised
// the textbook way: each component divided by the length.
#pragma once

#include "math/vec3.h"

namespace twinray::reference {

using math::cross;
using math::dot;
using math::length;
using math::max_abs_component;
using math::normalize;
using math::Vec3;

template <typename T>
using Color = Vec3<T>;

}  // namespace twinray::reference

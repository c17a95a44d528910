// The scene builder of src/scene/scene_builder.h under the tests' names (test::SceneBuilder, test::sphere, ...), and a
// component-wise EXPECT_NEAR for vectors.
#pragma once

#include "scene/scene_builder.h"

#include <gtest/gtest.h>

namespace twinray::test {

using scene::builder::box;
using scene::builder::csg;
using scene::builder::cylinder;
using scene::builder::mesh;
using scene::builder::placed;
using scene::builder::plane;
using scene::builder::SceneBuilder;
using scene::builder::sphere;

}  // namespace twinray::test

// Component-wise EXPECT_NEAR on anything with x, y, z (reference::Vec3): each failure prints the
// measured and the expected component.
#define TWINRAY_EXPECT_VEC_NEAR(actual, expected, tolerance)                   \
    do {                                                                       \
        const auto twinray_a_ = (actual);                                      \
        const auto twinray_e_ = (expected);                                    \
        EXPECT_NEAR(twinray_a_.x, twinray_e_.x, tolerance) << "x of " #actual; \
        EXPECT_NEAR(twinray_a_.y, twinray_e_.y, tolerance) << "y of " #actual; \
        EXPECT_NEAR(twinray_a_.z, twinray_e_.z, tolerance) << "z of " #actual; \
    } while (false)

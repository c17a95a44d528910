// Where the failing pixels of a comparison lie: groups of nearby failing pixels, each with its bounding box,
// size and worst pixel, so a report can draw a box around each and name the pixel to probe.
#pragma once

#include "compare/image_compare.h"

#include <vector>

namespace twinray::compare {

struct FailingCluster {
    int left = 0, top = 0, right = 0, bottom = 0;  // bounding box, inclusive
    long pixels = 0;                               // failing pixels inside
    PixelError worst{0, 0, 0};                     // largest error (ties: top-left first)
};

// Pixels failing where their largest channel difference exceeds `fail` (as fail_mask shows them). Two failing
// pixels belong to one cluster when at most `gap` pixels lie between them in x and in y, and clusters whose
// boxes come that close are merged, so no two boxes overlap. The `max_count` largest, by pixel count (ties: top-left
// box first), so the result does not depend on anything but the images.
std::vector<FailingCluster> failing_clusters(const Image& reference, const Image& other, double fail, int gap,
                                             int max_count);

}  // namespace twinray::compare

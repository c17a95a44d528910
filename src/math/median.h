// The median of timed runs, for `twinray bench` and the benchmarks: the middle value, or the mean of the two
// middle ones for an even count.
#pragma once

#include <algorithm>
#include <vector>

namespace twinray::math {

inline double median(std::vector<double> values) {
    std::sort(values.begin(), values.end());
    std::size_t middle = values.size() / 2;
    return values.size() % 2 == 1 ? values[middle] : 0.5 * (values[middle - 1] + values[middle]);
}

}  // namespace twinray::math

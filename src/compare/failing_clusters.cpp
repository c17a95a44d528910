#include "compare/failing_clusters.h"

#include <algorithm>
#include <cstddef>

namespace twinray::compare {
namespace {

bool boxes_within(const FailingCluster& a, const FailingCluster& b, int gap) {
    return a.left - b.right <= gap + 1 && b.left - a.right <= gap + 1 && a.top - b.bottom <= gap + 1 &&
           b.top - a.bottom <= gap + 1;
}

bool worse(const PixelError& p, const PixelError& q) {
    return p.error != q.error ? p.error > q.error : (p.y != q.y ? p.y < q.y : p.x < q.x);
}

void absorb(FailingCluster& into, const FailingCluster& other) {
    into.left = std::min(into.left, other.left);
    into.top = std::min(into.top, other.top);
    into.right = std::max(into.right, other.right);
    into.bottom = std::max(into.bottom, other.bottom);
    into.pixels += other.pixels;
    if (worse(other.worst, into.worst)) {
        into.worst = other.worst;
    }
}

// One cluster per group of failing pixels reachable from each other in steps of at most `gap` + 1 pixels
// in x and y; groups are found from their top-left pixel in row-major order.
std::vector<FailingCluster> pixel_groups(const std::vector<double>& errors, int width, int height, double fail,
                                         int gap) {
    auto failing = [&](int x, int y) { return errors[static_cast<std::size_t>(y) * width + x] > fail; };
    std::vector<bool> visited(errors.size(), false);
    std::vector<FailingCluster> groups;
    std::vector<PixelError> stack;
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            const std::size_t index = static_cast<std::size_t>(y) * width + x;
            if (visited[index] || !failing(x, y)) {
                continue;
            }
            visited[index] = true;
            FailingCluster group{x, y, x, y, 0, {x, y, errors[index]}};
            stack.push_back(group.worst);
            while (!stack.empty()) {
                const PixelError pixel = stack.back();
                stack.pop_back();
                absorb(group, {pixel.x, pixel.y, pixel.x, pixel.y, 1, pixel});
                for (int ny = std::max(0, pixel.y - gap - 1); ny <= std::min(height - 1, pixel.y + gap + 1); ++ny) {
                    for (int nx = std::max(0, pixel.x - gap - 1); nx <= std::min(width - 1, pixel.x + gap + 1); ++nx) {
                        const std::size_t neighbour = static_cast<std::size_t>(ny) * width + nx;
                        if (!visited[neighbour] && failing(nx, ny)) {
                            visited[neighbour] = true;
                            stack.push_back({nx, ny, errors[neighbour]});
                        }
                    }
                }
            }
            groups.push_back(group);
        }
    }
    return groups;
}

}  // namespace

std::vector<FailingCluster> failing_clusters(const Image& reference, const Image& other, double fail, int gap,
                                             int max_count) {
    require_same_size(reference, other);
    const int width = reference.width(), height = reference.height();
    std::vector<double> errors;
    errors.reserve(reference.pixels().size());
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            errors.push_back(largest_channel_difference(reference.at(x, y), other.at(x, y)));
        }
    }
    std::vector<FailingCluster> clusters = pixel_groups(errors, width, height, fail, gap);
    // Groups apart pixel by pixel may still have boxes that overlap (a ring around a dot): merge until none
    // comes within `gap` of another, so each box drawn is one cluster.
    for (bool merged = true; merged;) {
        merged = false;
        for (std::size_t i = 0; i < clusters.size(); ++i) {
            for (std::size_t j = i + 1; j < clusters.size();) {
                if (boxes_within(clusters[i], clusters[j], gap)) {
                    absorb(clusters[i], clusters[j]);
                    clusters.erase(clusters.begin() + static_cast<std::ptrdiff_t>(j));
                    merged = true;
                } else {
                    ++j;
                }
            }
        }
    }
    std::sort(clusters.begin(), clusters.end(), [](const FailingCluster& a, const FailingCluster& b) {
        if (a.pixels != b.pixels) {
            return a.pixels > b.pixels;
        }
        return a.top != b.top ? a.top < b.top : a.left < b.left;
    });
    clusters.resize(std::min(clusters.size(), static_cast<std::size_t>(std::max(max_count, 0))));
    return clusters;
}

}  // namespace twinray::compare

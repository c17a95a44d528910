// POV-Ray 3.7 as an outside judge: every scene in scenes/ is exported (src/pov/), rendered headless by
// POV-Ray and compared with reference<double>, both as 8-bit images. Per scene: the share of pixels
// within 2/255; the largest error away from edges, both off the band where the primary ray's primitive
// changes and off the band where anything in the ray tree changes (secondary silhouettes, shadow edges,
// total internal reflection); and the share of pixels whose primary ray meets the same primitive in
// both (POV-Ray renders an object-id pass). The numbers are printed on every run; docs/povray.md
// explains each threshold and each residual difference. Also: the exporter's rules and `twinray pov`.
#include "compare/image_compare.h"
#include "image/image_file.h"
#include "pov/exporter.h"
#include "pov/povray_runner.h"
#include "reference/tracer.h"
#include "scene/depth_control.h"
#include "scene/loader.h"
#include "tests/gltf_files.h"
#include "tests/run_twinray.h"
#include "tests/scene_files.h"
#include "tests/test_output.h"

#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using twinray::Image;

// What each scene must reach. The measured values and why each bound is where it is are in
// docs/povray.md; each bound leaves a margin over the measurement and says why the scene cannot do better.
struct Thresholds {
    double min_share_within_2_levels;   // share of pixels whose every channel is within 2/255
    int max_levels_off_object_edges;    // largest channel error (in 1/255) outside the object-edge band
    int max_levels_off_ray_tree_edges;  // ... outside the band where anything in the ray tree changes
    double min_object_agreement;        // share of pixels whose primary ray meets the same primitive
    const char* why;
};

// Why POV-Ray and we differ at all, in every scene: POV-Ray keeps colours in single precision (one level
// where a value sits near a rounding boundary), and its tolerances (TOOLING.md, docs/povray.md) differ
// from ours: every ray ignores hits nearer than 1e-4 and secondary rays start exactly on the surface;
// shadow rays ignore surfaces within 1e-3 of where they start and restart at each transparent surface
// with the same tolerance. The default therefore allows one level everywhere plus a margin (2), and
// at most 0.01% of pixels (8 of 76 800) beyond 2 levels, on steps of the ray tree where one ray per pixel
// is sensitive to such tolerances. Primary rays must meet the same primitive except where a pixel
// centre lies within rounding of a silhouette: measured 0 pixels on every scene, 0.05% allowed.
const Thresholds& thresholds_for(const std::string& scene) {
    static const Thresholds standard{0.9999, 2, 2, 0.9995, "the default: POV-Ray reproduces the scene up to rounding"};
    static const std::vector<std::pair<std::string, Thresholds>> table = {
        // Measured 99.9883% (9 pixels over 2 levels, at most 12), all on ray-tree steps (max 1 level off
        // them): the floor meets the glass box and the water cylinder, which reach 0.05 below it, and
        // shadow rays cross their corners. Floor points within 1e-3 of the glass (or whose reflected ray
        // meets it within 1e-4), and shadow rays that clip a corner with a chord under 1e-3, see one
        // transmission factor fewer in POV-Ray: one light's diffuse term on the floor scaled by 1/0.8 or
        // 1/0.7, up to 12 levels measured. These pixels lie on secondary and shadow edges, outside the
        // primary object band, hence the bound of 16 there; 0.05% (38 pixels) over 2 levels allowed.
        {"complete2",
         {0.9995, 16, 2, 0.9995,
          "POV-Ray's 1e-3 shadow and 1e-4 hit tolerances where the floor meets the glass box and water "
          "cylinder and where shadow rays clip their corners"}},
        // Measured 99.9818% (14 pixels over 2 levels, at most 38, max 2 levels off the ray tree's edges): the
        // chrome torus reflects its own inner side at grazing angles, where its interpolated normals face
        // away from the geometric ones. We turn such a normal to the geometric side (docs/scene-format.md,
        // "Meshes"); POV-Ray does not, so its reflected ray leaves in another direction there.
        // Measured 99.9977% (6 pixels over 2 levels, at most 13, max 1 level off the ray tree's edges): rays
        // refracted through the glass gem (an instance of a 20-triangle shape) that pass near its facets' edges,
        // where a secondary ray's start within POV-Ray's 1e-4 and 1e-3 tolerances of the next facet changes
        // which facet it leaves by. On secondary edges only, hence 16 there, as complete2.
        {"instances",
         {0.9995, 16, 2, 0.9995,
          "rays refracted through the glass instance near its facets' edges, within POV-Ray's hit and shadow "
          "tolerances"}},
        {"meshes",
         {0.9995, 48, 2, 0.9995,
          "a smooth mesh's interpolated normals facing away from the geometric normal at grazing reflections: "
          "turned to its side by us, not by POV-Ray"}},
    };
    for (const auto& [name, thresholds] : table) {
        if (name == scene) {
            return thresholds;
        }
    }
    return standard;
}

using twinray::test::scene_files;

using twinray::pov::find_povray;

// The runner's image, or an empty optional after ADD_FAILURE with POV-Ray's log.
std::optional<Image> render_with_povray(const fs::path& povray, const fs::path& folder, const std::string& name,
                                        const std::string& pov_text, int width, int height) {
    try {
        return twinray::pov::render_with_povray(povray, folder, name, pov_text, width, height);
    } catch (const twinray::pov::PovrayError& error) {
        ADD_FAILURE() << error.what();
        return std::nullopt;
    }
}

int level(float stored) {
    return static_cast<int>(std::lround(std::clamp(stored, 0.0f, 1.0f) * 255.0f));
}

std::array<int, 3> levels_of(const twinray::Rgb& p) {
    return {level(p.r), level(p.g), level(p.b)};
}

// The largest difference of a channel between two pixels, in 8-bit levels.
int levels_apart(const twinray::Rgb& p, const twinray::Rgb& q) {
    const std::array<int, 3> a = levels_of(p), b = levels_of(q);
    return std::max({std::abs(a[0] - b[0]), std::abs(a[1] - b[1]), std::abs(a[2] - b[2])});
}

using RefTracer = twinray::reference::Tracer<double>;
using RefVec = twinray::reference::Vec3<double>;
using RefRay = twinray::reference::Ray<double>;

std::size_t index_of(int x, int y, int width) {
    return static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x);
}

// Per pixel: the id of the primitive the reference's primary ray meets (leaf + 1), 0 on a miss.
std::vector<int> reference_object_ids(const RefTracer& tracer, int width, int height) {
    std::vector<int> ids(static_cast<std::size_t>(width) * static_cast<std::size_t>(height));
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            auto hit = tracer.intersect(tracer.primary_ray(x, y, width, height));
            ids[index_of(x, y, width)] = hit ? hit->leaf + 1 : 0;
        }
    }
    return ids;
}

// Everything discrete along one pixel's ray tree in the reference: the primitive each ray meets,
// entering or leaving, each light facing away or not and its shadow transmittance, and total internal
// reflection. Where it changes from one pixel to the next the image has a step (a silhouette seen
// directly, in a reflection or through glass, a shadow's edge, the edge of total internal reflection),
// which one ray per pixel samples somewhere in the pixel: a tiny difference in where either tracer
// puts it is a full-size difference there. Directions follow docs/scene-format.md (mirror, Snell).
class RayTreeSignature {
public:
    RayTreeSignature(const twinray::scene::Scene& scene, const RefTracer& tracer) : scene_(scene), tracer_(tracer) {}

    std::uint64_t of(const RefRay& ray) const {
        std::uint64_t hash = 14695981039346656037ull;
        visit(ray, 1, hash);
        return hash;
    }

private:
    static void add(std::uint64_t& hash, std::uint64_t value) {
        hash ^= value;
        hash *= 1099511628211ull;
    }

    void visit(const RefRay& ray, int depth, std::uint64_t& hash) const {
        auto hit = tracer_.intersect(ray);
        add(hash, hit ? static_cast<std::uint64_t>(hit->leaf) * 2 + (hit->entering ? 1 : 0) : ~0ull);
        if (!hit) {
            return;
        }
        for (const twinray::scene::Light& light : scene_.lights) {
            RefVec to_light = normalize(RefVec(light.position) - hit->point);
            if (!(dot(hit->normal, to_light) > 0)) {
                add(hash, 3);
                continue;
            }
            double shadow =
                tracer_.shadow_transmittance(RefTracer::spawn_origin(*hit, to_light), RefVec(light.position));
            std::uint64_t bits = 0;
            std::memcpy(&bits, &shadow, sizeof bits);
            add(hash, bits);
        }
        if (depth >= scene_.max_depth) {
            return;
        }
        const auto& m = tracer_.material_of(hit->leaf);
        RefVec d = ray.direction;
        RefVec n = hit->normal;
        double reflection = m.reflection;
        if (m.transmission > 0) {
            double eta = hit->entering ? 1 / m.ior : m.ior;
            double cos_i = -dot(d, n);
            double sin2_t = eta * eta * (1 - cos_i * cos_i);
            if (sin2_t > 1) {
                add(hash, 5);  // total internal reflection
                reflection += m.transmission;
            } else {
                RefVec refracted = normalize(eta * d + (eta * cos_i - std::sqrt(1 - sin2_t)) * n);
                visit({RefTracer::spawn_origin(*hit, refracted), refracted}, depth + 1, hash);
            }
        }
        if (reflection > 0) {
            RefVec mirror = d - 2 * dot(d, n) * n;
            visit({RefTracer::spawn_origin(*hit, mirror), mirror}, depth + 1, hash);
        }
    }

    const twinray::scene::Scene& scene_;
    const RefTracer& tracer_;
};

std::vector<std::uint64_t> ray_tree_signatures(const twinray::scene::Scene& scene, const RefTracer& tracer, int width,
                                               int height) {
    RayTreeSignature signature(scene, tracer);
    std::vector<std::uint64_t> signatures(static_cast<std::size_t>(width) * static_cast<std::size_t>(height));
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            signatures[index_of(x, y, width)] = signature.of(tracer.primary_ray(x, y, width, height));
        }
    }
    return signatures;
}

// A pixel is in the band when a pixel of its 3×3 neighbourhood has another label.
template <class Label>
std::vector<bool> band_of(const std::vector<Label>& labels, int width, int height) {
    std::vector<bool> band(labels.size(), false);
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            for (int v = std::max(0, y - 1); v <= std::min(height - 1, y + 1); ++v) {
                for (int u = std::max(0, x - 1); u <= std::min(width - 1, x + 1); ++u) {
                    if (labels[index_of(u, v, width)] != labels[index_of(x, y, width)]) {
                        band[index_of(x, y, width)] = true;
                    }
                }
            }
        }
    }
    return band;
}

struct Measurement {
    double share_within_2_levels = 0;
    double share_identical = 0;
    int max_levels = 0;
    int max_levels_off_object_edges = 0;    // outside the band of primary-ray object changes
    int max_levels_off_ray_tree_edges = 0;  // outside the band of any change in the ray tree
    std::array<int, 2> worst_off_object_edges{0, 0};
    std::array<int, 2> worst_off_ray_tree_edges{0, 0};
    double object_band_share = 0;
    double ray_tree_band_share = 0;
    double object_agreement = 0;    // same primitive (or both background) on the primary ray
    double coverage_agreement = 0;  // both background or both some primitive
};

Measurement measure(const Image& pov, const Image& reference, const Image& pov_ids, const std::vector<int>& ids,
                    const std::vector<bool>& object_band, const std::vector<bool>& ray_tree_band) {
    const int width = reference.width();
    const int height = reference.height();
    Measurement m;
    long identical = 0, within_2 = 0, same_object = 0, same_coverage = 0, in_object_band = 0, in_ray_tree_band = 0;
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            std::size_t i = index_of(x, y, width);
            int error = levels_apart(pov.at(x, y), reference.at(x, y));
            within_2 += error <= 2 ? 1 : 0;
            identical += error == 0 ? 1 : 0;
            m.max_levels = std::max(m.max_levels, error);
            in_object_band += object_band[i] ? 1 : 0;
            in_ray_tree_band += ray_tree_band[i] ? 1 : 0;
            if (!object_band[i] && error > m.max_levels_off_object_edges) {
                m.max_levels_off_object_edges = error;
                m.worst_off_object_edges = {x, y};
            }
            if (!ray_tree_band[i] && error > m.max_levels_off_ray_tree_edges) {
                m.max_levels_off_ray_tree_edges = error;
                m.worst_off_ray_tree_edges = {x, y};
            }
            std::array<int, 3> id = levels_of(pov_ids.at(x, y));
            int pov_id = twinray::pov::decode_object_id(id[0], id[1]);
            same_object += pov_id == ids[i] ? 1 : 0;
            same_coverage += (pov_id == 0) == (ids[i] == 0) ? 1 : 0;
        }
    }
    const double pixels = static_cast<double>(width) * height;
    m.share_within_2_levels = static_cast<double>(within_2) / pixels;
    m.share_identical = static_cast<double>(identical) / pixels;
    m.object_band_share = static_cast<double>(in_object_band) / pixels;
    m.ray_tree_band_share = static_cast<double>(in_ray_tree_band) / pixels;
    m.object_agreement = static_cast<double>(same_object) / pixels;
    m.coverage_agreement = static_cast<double>(same_coverage) / pixels;
    return m;
}

class PovJudge : public ::testing::TestWithParam<fs::path> {};

TEST_P(PovJudge, PovRayRendersTheExportedSceneAsTheReferenceDoes) {
    std::optional<fs::path> povray = find_povray();
    ASSERT_TRUE(povray.has_value())
        << "povray is not on PATH: install the Debian package `povray` "
           "(apt-get install povray, or run ci/setup). The POV-Ray judge cannot be skipped.";
    const std::string name = GetParam().stem().string();
    const Thresholds& limits = thresholds_for(name);
    twinray::scene::Scene scene = twinray::scene::load_scene(GetParam());
    const int width = scene.width;
    const int height = scene.height;
    fs::path folder = fs::path(TWINRAY_TEST_OUTPUT_DIR) / "pov" / name;
    fs::remove_all(folder);
    fs::create_directories(folder);

    std::optional<Image> pov =
        render_with_povray(*povray, folder, "pov", twinray::pov::export_pov(scene, width, height), width, height);
    ASSERT_TRUE(pov.has_value());
    std::optional<Image> pov_ids = render_with_povray(
        *povray, folder, "pov_ids", twinray::pov::export_pov_object_ids(scene, width, height), width, height);
    ASSERT_TRUE(pov_ids.has_value());
    ASSERT_EQ(pov->width(), width);
    ASSERT_EQ(pov->height(), height);
    ASSERT_EQ(pov_ids->width(), width);
    ASSERT_EQ(pov_ids->height(), height);

    twinray::RenderOptions options;
    options.threads = 1;  // ctest runs the scenes side by side
    Image reference = twinray::compare::quantized_8bit(twinray::reference::render<double>(scene, options).image);
    twinray::write_image(reference, folder / "reference.png");
    RefTracer tracer(scene);
    std::vector<int> ids = reference_object_ids(tracer, width, height);
    Measurement m = measure(*pov, reference, *pov_ids, ids, band_of(ids, width, height),
                            band_of(ray_tree_signatures(scene, tracer, width, height), width, height));

    std::printf(
        "[ measured ] %s %dx%d: %.4f%% of pixels within 2/255 (%.3f%% identical), max error %d/255; off object edges "
        "(%.2f%% of pixels excluded) max %d/255 at %d,%d; off ray-tree edges (%.2f%% excluded) max %d/255 at "
        "%d,%d; same primitive %.4f%%, same coverage %.4f%%\n",
        name.c_str(), width, height, 100.0 * m.share_within_2_levels, 100.0 * m.share_identical, m.max_levels,
        100.0 * m.object_band_share, m.max_levels_off_object_edges, m.worst_off_object_edges[0],
        m.worst_off_object_edges[1], 100.0 * m.ray_tree_band_share, m.max_levels_off_ray_tree_edges,
        m.worst_off_ray_tree_edges[0], m.worst_off_ray_tree_edges[1], 100.0 * m.object_agreement,
        100.0 * m.coverage_agreement);
    RecordProperty("share_within_2_levels", std::to_string(m.share_within_2_levels));
    RecordProperty("max_levels_off_object_edges", std::to_string(m.max_levels_off_object_edges));
    RecordProperty("max_levels_off_ray_tree_edges", std::to_string(m.max_levels_off_ray_tree_edges));
    RecordProperty("object_agreement", std::to_string(m.object_agreement));

    std::ostringstream failures;
    if (m.share_within_2_levels < limits.min_share_within_2_levels) {
        failures << "  within 2/255: " << 100.0 * m.share_within_2_levels << "% of pixels, at least "
                 << 100.0 * limits.min_share_within_2_levels << "% required\n";
    }
    if (m.max_levels_off_object_edges > limits.max_levels_off_object_edges) {
        failures << "  off object edges: " << m.max_levels_off_object_edges << "/255 at " << m.worst_off_object_edges[0]
                 << "," << m.worst_off_object_edges[1] << ", at most " << limits.max_levels_off_object_edges
                 << " allowed\n";
    }
    if (m.max_levels_off_ray_tree_edges > limits.max_levels_off_ray_tree_edges) {
        failures << "  off ray-tree edges: " << m.max_levels_off_ray_tree_edges << "/255 at "
                 << m.worst_off_ray_tree_edges[0] << "," << m.worst_off_ray_tree_edges[1] << ", at most "
                 << limits.max_levels_off_ray_tree_edges << " allowed\n";
    }
    if (m.object_agreement < limits.min_object_agreement) {
        failures << "  same primitive: " << 100.0 * m.object_agreement << "% of pixels, at least "
                 << 100.0 * limits.min_object_agreement << "% required\n";
    }
    if (!failures.str().empty()) {
        fs::path error_map = folder / "error_map.png";
        const int scale = std::max(2, limits.max_levels_off_object_edges);
        twinray::write_image(
            twinray::compare::error_heat_map(reference, *pov, twinray::compare::HeatMapScale::linear(scale / 255.0)),
            error_map);
        ADD_FAILURE() << name << ": POV-Ray's image differs from the reference's beyond this scene's thresholds ("
                      << limits.why << "):\n"
                      << failures.str() << "  error map (inferno, brightest at " << scale
                      << "/255 and above): " << error_map.string()
                      << "\n  POV-Ray's image, the reference's, the scene: " << (folder / "pov.png").string() << ", "
                      << (folder / "reference.png").string() << ", " << (folder / "pov.pov").string();
    }
}

INSTANTIATE_TEST_SUITE_P(Scenes, PovJudge, ::testing::ValuesIn(scene_files()),
                         [](const ::testing::TestParamInfo<fs::path>& param_info) {
                             return param_info.param.stem().string();
                         });

// The exporter's rules, one at a time, on scenes written here.

twinray::scene::Scene scene_from(const std::string& objects, const std::string& materials = "{}") {
    return twinray::scene::parse_scene(R"({"camera": {"eye": [0, 1, 5], "look_at": [0, 1, 0]}, "materials": )" +
                                           materials + R"(, "objects": )" + objects + "}",
                                       "<test>");
}

bool contains(const std::string& text, const std::string& part) {
    return text.find(part) != std::string::npos;
}

std::size_t occurrences(const std::string& text, const std::string& part) {
    std::size_t found = 0;
    for (std::size_t at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) {
        ++found;
    }
    return found;
}

// `twinray bench` takes POV-Ray's render time from its own statistics (the trace's CPU seconds), not from a
// difference of whole-process times: read back from the log, and sixteen times the pixels take longer to
// trace, while the parse of the same scene does not grow with them.
TEST(PovRunner, StatisticsGiveTheTraceCpuSecondsWhichGrowWithThePixels) {
    std::optional<fs::path> povray = find_povray();
    ASSERT_TRUE(povray.has_value()) << "povray is not on PATH: install the Debian package `povray` (ci/setup)";
    twinray::scene::Scene scene = twinray::scene::load_scene(fs::path(TWINRAY_SOURCE_DIR) / "scenes" / "spheres.json");
    fs::path folder = fs::path(TWINRAY_TEST_OUTPUT_DIR) / "pov" / "statistics";
    fs::remove_all(folder);
    fs::create_directories(folder);
    twinray::pov::PovrayStatistics small, large;
    twinray::pov::render_with_povray(*povray, folder, "small", twinray::pov::export_pov(scene, 40, 30), 40, 30, 1,
                                     &small);
    twinray::pov::render_with_povray(*povray, folder, "large", twinray::pov::export_pov(scene, 640, 480), 640, 480, 1,
                                     &large);
    EXPECT_GT(large.trace_cpu_seconds, 0.0);
    EXPECT_GT(large.trace_cpu_seconds, 4 * small.trace_cpu_seconds)
        << "trace CPU seconds: " << small.trace_cpu_seconds << " at 40x30, " << large.trace_cpu_seconds
        << " at 640x480";
    EXPECT_LT(large.parse_cpu_seconds + large.bounding_cpu_seconds, 1.0)
        << "parse " << large.parse_cpu_seconds << " s, bounding " << large.bounding_cpu_seconds << " s";
}

TEST(PovExporter, NegatesZAndSwapsTheBoxCornersItsOrderChanges) {
    std::string pov = twinray::pov::export_pov(scene_from(R"([{"type": "box", "min": [-1, 0, -3], "max": [1, 2, -2]},
                       {"type": "sphere", "center": [1, 2, 3], "radius": 0.5},
                       {"type": "plane", "normal": [0, 0, 1], "offset": 2}])"),
                                               32, 24);
    EXPECT_TRUE(contains(pov, "box {\n  <-1, 0, 2>, <1, 2, 3>")) << pov;
    EXPECT_TRUE(contains(pov, "sphere {\n  <1, 2, -3>, 0.5")) << pov;
    EXPECT_TRUE(contains(pov, "plane {\n  <0, 0, -1>, 2")) << pov;
    EXPECT_TRUE(contains(pov, "location <0, 1, -5>")) << pov;
}

// A glTF file's nodes (tests/gltf_files.h: one octahedron placed by three nodes under a parent) are exported as one
// declared mesh2 and an object of it per node under the node's matrix, and POV-Ray renders them as the reference does.
TEST(PovExporter, AGltfFilesMeshIsDeclaredOnceAndEachNodePlacesItAsTheReferenceRendersIt) {
    std::optional<fs::path> povray = find_povray();
    ASSERT_TRUE(povray.has_value()) << "povray is not on PATH: install the Debian package `povray` (ci/setup)";
    const fs::path folder = fs::path(TWINRAY_TEST_OUTPUT_DIR) / "pov" / "gltf";
    fs::remove_all(folder);
    fs::create_directories(folder);
    std::ofstream(folder / "three_gems.gltf") << twinray::test::octahedron_gltf(twinray::test::three_gems_nodes, "[0]");
    const twinray::scene::Scene scene = twinray::scene::parse_scene(R"({
      "image": { "width": 80, "height": 60 },
      "camera": { "eye": [0.3, 1.5, 2.5], "look_at": [0, 0.4, -0.5] },
      "materials": { "red": { "color": [0.9, 0.2, 0.1], "diffuse": 0.7, "phong": 0.4 } },
      "lights": [ { "position": [-3, 6, 4] } ],
      "objects": [ { "type": "plane", "normal": [0, 1, 0], "offset": -0.5 },
                   { "type": "mesh", "file": "three_gems.gltf", "material": "red" } ] })",
                                                                    (folder / "gems.json").string());
    const std::string pov_text = twinray::pov::export_pov(scene, scene.width, scene.height);
    EXPECT_EQ(occurrences(pov_text, "#declare twinray_shape_"), 1u);
    EXPECT_EQ(occurrences(pov_text, "  twinray_shape_0\n"), 3u);
    EXPECT_EQ(occurrences(pov_text, "// objects[1] node \"Turned\" (three_gems.gltf mesh 0)"), 1u);
    std::optional<Image> pov = render_with_povray(*povray, folder, "pov", pov_text, scene.width, scene.height);
    ASSERT_TRUE(pov.has_value());
    twinray::RenderOptions options;
    options.threads = 1;
    const Image reference = twinray::compare::quantized_8bit(twinray::reference::render<double>(scene, options).image);
    int within_2 = 0;
    int red = 0;  // pixels of the gems, so that the comparison is about them
    for (int y = 0; y < scene.height; ++y) {
        for (int x = 0; x < scene.width; ++x) {
            within_2 += levels_apart(pov->at(x, y), reference.at(x, y)) <= 2;
            const std::array<int, 3> b = levels_of(reference.at(x, y));
            red += b[0] > 2 * b[2] + 10;
        }
    }
    std::printf("[ measured ] glTF gems: %d of %d pixels within 2/255 of the reference, %d of the gems\n", within_2,
                scene.width * scene.height, red);
    EXPECT_GT(red, scene.width * scene.height / 20);
    EXPECT_GE(within_2, scene.width * scene.height - scene.width * scene.height / 1000);
}

// A CSG shape (a bead: a sphere taking its instance's material, pierced by a gold box) is declared once for each
// material its instances give it, with the glass one's shadow caster declared beside it, and once in the object-id pass,
// where each instance colours it by its id; POV-Ray renders both passes as the reference does.
TEST(PovExporter, ACsgShapeIsDeclaredOnceForEachMaterialItsInstancesGiveItAndEachInstancePlacesIt) {
    std::optional<fs::path> povray = find_povray();
    ASSERT_TRUE(povray.has_value()) << "povray is not on PATH: install the Debian package `povray` (ci/setup)";
    const fs::path folder = twinray::test::fresh_directory(twinray::test::own_output_path("pov"));
    const twinray::scene::Scene scene = twinray::scene::parse_scene(R"({
      "image": { "width": 96, "height": 64 },
      "camera": { "eye": [0, 2.2, 4.5], "look_at": [0, 0.3, 0] },
      "materials": { "red": { "color": [0.9, 0.2, 0.1], "diffuse": 0.7, "phong": 0.4 },
                     "gold": { "color": [0.9, 0.7, 0.2], "diffuse": 0.6, "reflection": 0.3 },
                     "glass": { "color": [1, 1, 1], "diffuse": 0.1, "reflection": 0.1, "transmission": 0.8,
                                "ior": 1.5 } },
      "lights": [ { "position": [-3, 6, 4] } ],
      "shapes": { "bead": { "type": "union", "children": [
                    { "type": "sphere", "center": [0, 0, 0], "radius": 0.5 },
                    { "type": "box", "min": [-0.7, -0.15, -0.15], "max": [0.7, 0.15, 0.15], "material": "gold" } ] } },
      "objects": [ { "type": "plane", "normal": [0, 1, 0], "offset": -0.5 },
                   { "type": "instance", "shape": "bead", "material": "red",
                     "transform": [ { "translate": [-1.5, 0, 0] } ] },
                   { "type": "instance", "shape": "bead", "material": "glass",
                     "transform": [ { "rotate": [0, 30, 0] }, { "translate": [0, 0.2, 0.5] } ] },
                   { "type": "instance", "shape": "bead", "material": "red",
                     "transform": [ { "scale": [1, 1.5, 1] }, { "translate": [1.5, 0.25, 0] } ] },
                   { "type": "instance", "shape": "bead", "material": "red",
                     "transform": [ { "rotate": [0, 0, 90] }, { "translate": [0, 0.3, -1.5] } ] } ] })",
                                                                    "beads.json");
    ASSERT_EQ(scene.solid_instances.size(), 4u);
    const std::string pov_text = twinray::pov::export_pov(scene, scene.width, scene.height);
    const std::string ids_text = twinray::pov::export_pov_object_ids(scene, scene.width, scene.height);
    const auto material = [&scene](const std::string& name) {
        const auto found = std::find(scene.material_names.begin(), scene.material_names.end(), name);
        return std::to_string(found - scene.material_names.begin());
    };
    const std::string red = "twinray_solid_0_" + material("red");
    const std::string glass = "twinray_solid_0_" + material("glass");
    EXPECT_EQ(occurrences(pov_text, "#declare twinray_solid_"), 3u) << pov_text;
    EXPECT_EQ(occurrences(pov_text, "#declare " + red + " =\nmerge {"), 1u) << pov_text;
    EXPECT_EQ(occurrences(pov_text, "#declare " + glass + " =\nmerge {"), 1u) << pov_text;
    EXPECT_EQ(occurrences(pov_text, "#declare " + glass + "_shadow =\nmerge {"), 1u) << pov_text;
    EXPECT_EQ(occurrences(pov_text, "  " + red + "\n"), 3u) << pov_text;
    EXPECT_EQ(occurrences(pov_text, "  " + glass + "\n"), 1u) << pov_text;
    EXPECT_EQ(occurrences(pov_text, "object { " + glass + "_shadow matrix <"), 1u) << pov_text;
    EXPECT_EQ(occurrences(pov_text, "// shapes.bead.children[1]"), 3u)
        << pov_text;  // in each of the three declarations
    EXPECT_EQ(occurrences(pov_text, "// objects[3] (shapes.bead)"), 1u) << pov_text;
    EXPECT_EQ(occurrences(ids_text, "#declare twinray_solid_"), 1u) << ids_text;
    EXPECT_EQ(occurrences(ids_text, "  twinray_solid_0\n"), 4u) << ids_text;
    EXPECT_EQ(occurrences(ids_text, "pigment"), 5u) << ids_text;  // the plane's and one per instance, none in the shape

    std::optional<Image> pov = render_with_povray(*povray, folder, "pov", pov_text, scene.width, scene.height);
    ASSERT_TRUE(pov.has_value());
    std::optional<Image> pov_ids = render_with_povray(*povray, folder, "pov_ids", ids_text, scene.width, scene.height);
    ASSERT_TRUE(pov_ids.has_value());
    twinray::RenderOptions options;
    options.threads = 1;
    const Image reference = twinray::compare::quantized_8bit(twinray::reference::render<double>(scene, options).image);
    const std::vector<int> ids = reference_object_ids(RefTracer(scene), scene.width, scene.height);
    int within_2 = 0;
    int same_object = 0;
    int on_beads = 0;
    for (int y = 0; y < scene.height; ++y) {
        for (int x = 0; x < scene.width; ++x) {
            within_2 += levels_apart(pov->at(x, y), reference.at(x, y)) <= 2;
            const twinray::Rgb& id_pixel = pov_ids->at(x, y);
            const int pov_id = twinray::pov::decode_object_id(level(id_pixel.r), level(id_pixel.g));
            const int reference_id = ids[index_of(x, y, scene.width)];
            same_object += pov_id == reference_id;
            on_beads += reference_id > 1;
        }
    }
    const int pixels = scene.width * scene.height;
    std::printf(
        "[ measured ] CSG instances: %d of %d pixels within 2/255 of the reference, %d on the same object, %d "
        "on the beads\n",
        within_2, pixels, same_object, on_beads);
    EXPECT_GT(on_beads, pixels / 20);
    EXPECT_GE(within_2, pixels - pixels / 200);
    EXPECT_GE(same_object, pixels - pixels / 1000);
}

TEST(PovExporter, CameraHasExplicitRightUpSkyAndHorizontalAngle) {
    twinray::scene::Scene scene = scene_from("[]");
    scene.camera.fov_deg = 62;
    std::string pov = twinray::pov::export_pov(scene, 400, 240);
    for (const char* part : {"right <1.6666666666666667, 0, 0>", "up <0, 1, 0>", "sky <0, 1, 0>", "angle 62",
                             "assumed_gamma 1.0", "adc_bailout 0", "max_trace_level 5"}) {
        EXPECT_TRUE(contains(pov, part)) << part << " missing from:\n" << pov;
    }
    EXPECT_FALSE(contains(pov, "shadowless")) << pov;
}

// POV-Ray judges the rays we trace: adc_bailout is the scene's min_weight, else the weight below which no single
// secondary ray can move a pixel by the cutoff's tolerance (scene/depth_control.h).
TEST(PovExporter, AdcBailoutIsTheMinWeightOrTheWeightBelowWhichNoRayCanMatter) {
    const std::string mirror = R"({"mirror": {"reflection": 0.5, "ambient": 1, "diffuse": 0}})";
    const std::string objects = R"([{"type": "sphere", "center": [0, 1, 0], "radius": 1, "material": "mirror"}])";
    twinray::scene::Scene scene = scene_from(objects, mirror);
    // One material: local 1 (ambient 1, no lights), s = 0.5, max_depth 5: a ray at depth 2 returns at most
    // 1 + 0.5 + 0.25 + 0.125 = 1.875 (times the rounding margin 1 + 2⁻¹⁰).
    double expected = twinray::scene::DepthControl::pixel_tolerance / (1.875 * (1.0 + 1.0 / 1024));
    std::string pov = twinray::pov::export_pov(scene, 32, 24);
    char line[64];
    std::snprintf(line, sizeof line, "adc_bailout %.17g\n", expected);
    EXPECT_TRUE(contains(pov, line)) << line << " missing from:\n" << pov;
    scene.min_weight = 0.01;
    EXPECT_TRUE(contains(twinray::pov::export_pov(scene, 32, 24), "adc_bailout 0.01\n"));
}

TEST(PovExporter, NumbersReadBackAsTheSameDouble) {
    std::string pov =
        twinray::pov::export_pov(scene_from(R"([{"type": "sphere", "center": [0, 0, 0], "radius": 0.1}])"), 8, 8);
    std::size_t at = pov.find("sphere {\n  <0, 0, 0>, ");
    ASSERT_NE(at, std::string::npos) << pov;
    EXPECT_EQ(std::strtod(pov.c_str() + at + std::string("sphere {\n  <0, 0, 0>, ").size(), nullptr), 0.1);
}

TEST(PovExporter, UnionIsWrittenAsMergeSoATransparentUnionHasNoInnerSurfaces) {
    std::string pov = twinray::pov::export_pov(
        scene_from(R"([{"type": "union", "children": [{"type": "sphere", "center": [0, 0, 0], "radius": 1},
                                                     {"type": "sphere", "center": [1, 0, 0], "radius": 1}]}])"),
        8, 8);
    EXPECT_TRUE(contains(pov, "merge {")) << pov;
    EXPECT_FALSE(contains(pov, "union {")) << pov;
}

TEST(PovExporter, GlassGetsTransmitAndRefractionThatGiveOurTotalInternalReflectionAndACopyForShadows) {
    // t = 0.8, r = 0.1: POV-Ray's transmit f = t/(r + t), refraction k = r + t, ambient and diffuse over (1 − f).
    std::string pov = twinray::pov::export_pov(
        scene_from(
            R"([{"type": "box", "min": [-1, 0, -1], "max": [1, 1, 1], "material": "glass"}])",
            R"({"glass": {"ambient": 0.1, "diffuse": 0.05, "reflection": 0.1, "transmission": 0.8, "ior": 1.5}})"),
        8, 8);
    const double f = 0.8 / (0.1 + 0.8);
    char expected[160];
    std::snprintf(expected, sizeof expected, "rgbt <1, 1, 1, %.17g>", f);
    EXPECT_TRUE(contains(pov, expected)) << expected << " missing from:\n" << pov;
    std::snprintf(expected, sizeof expected, "diffuse %.17g", 0.05 / (1 - f));
    EXPECT_TRUE(contains(pov, expected)) << expected << " missing from:\n" << pov;
    std::snprintf(expected, sizeof expected, "refraction %.17g", 0.1 + 0.8);
    EXPECT_TRUE(contains(pov, expected)) << expected << " missing from:\n" << pov;
    EXPECT_TRUE(contains(pov, "interior { ior 1.5 }")) << pov;
    EXPECT_TRUE(contains(pov, "no_shadow")) << pov;
    EXPECT_TRUE(contains(pov, "rgbt <0, 0, 0, 0.80000000000000004>")) << pov;
    EXPECT_TRUE(contains(pov, "no_image")) << pov;
    EXPECT_TRUE(contains(pov, "no_reflection")) << pov;
    EXPECT_FALSE(contains(pov, "Not exact")) << pov;
}

TEST(PovExporter, GlassWhoseReflectionAndTransmissionSumToOneNeedsNoShadowCopy) {
    std::string pov = twinray::pov::export_pov(
        scene_from(R"([{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "glass"}])",
                   R"({"glass": {"diffuse": 0.1, "reflection": 0.15, "transmission": 0.85, "ior": 2.4}})"),
        8, 8);
    EXPECT_TRUE(contains(pov, "rgbt <1, 1, 1, 0.84999999999999998>")) << pov;
    EXPECT_FALSE(contains(pov, "refraction")) << pov;
    EXPECT_FALSE(contains(pov, "no_shadow")) << pov;
}

TEST(PovExporter, TransparentWithoutReflectionIsMarkedNotExact) {
    std::string pov = twinray::pov::export_pov(
        scene_from(R"([{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "tinted"}])",
                   R"({"tinted": {"diffuse": 0.2, "transmission": 0.5, "ior": 1.3}})"),
        8, 8);
    EXPECT_TRUE(contains(pov, "// Not exact: material tinted: reflection 0 with 0 < transmission < 1")) << pov;
    EXPECT_TRUE(contains(pov, "rgbt <1, 1, 1, 0.5>")) << pov;
    EXPECT_TRUE(contains(pov, "diffuse 0.40000000000000002")) << pov;
}

TEST(PovExporter, ACsgObjectWhosePrimitivesShareAnIorSharesOneInteriorAndEveryPrimitiveCarriesItsRefraction) {
    std::string pov = twinray::pov::export_pov(
        scene_from(R"([{"type": "difference", "children": [
                         {"type": "intersection", "material": "glass", "children": [
                           {"type": "sphere", "center": [0, 1, 0], "radius": 1},
                           {"type": "plane", "normal": [0, 1, 0], "offset": 1.5}]},
                         {"type": "box", "min": [-0.4, 0.6, -2], "max": [0.4, 1.4, 2], "material": "blue"}]}])",
                   R"({"glass": {"reflection": 0.1, "transmission": 0.85, "ior": 1.5}, "blue": {}})"),
        8, 8);
    std::size_t visible_end = pov.find("// The same object");
    ASSERT_NE(visible_end, std::string::npos) << pov;
    std::string visible = pov.substr(0, visible_end);
    std::size_t interiors = 0;
    for (std::size_t at = visible.find("interior {"); at != std::string::npos;
         at = visible.find("interior {", at + 1)) {
        ++interiors;
    }
    EXPECT_EQ(interiors, 1u) << pov;
    std::size_t refractions = 0;
    for (std::size_t at = visible.find("refraction 0.94999999999999996"); at != std::string::npos;
         at = visible.find("refraction 0.94999999999999996", at + 1)) {
        ++refractions;
    }
    EXPECT_EQ(refractions, 3u) << "the opaque box must carry k too, or POV-Ray resets the shared interior's:\n" << pov;
}

TEST(PovExporter, ObjectIdPassColoursEachPrimitiveByItsIdWithoutLights) {
    std::string pov =
        twinray::pov::export_pov_object_ids(scene_from(R"([{"type": "sphere", "center": [0, 0, 0], "radius": 1},
                       {"type": "sphere", "center": [2, 0, 0], "radius": 1}])"),
                                            8, 8);
    EXPECT_TRUE(contains(pov, "pigment { color rgb <0.0039215686274509803, 0, 0> }")) << pov;
    EXPECT_TRUE(contains(pov, "pigment { color rgb <0.0078431372549019607, 0, 0> }")) << pov;
    EXPECT_TRUE(contains(pov, "max_trace_level 1")) << pov;
    EXPECT_FALSE(contains(pov, "light_source")) << pov;
    EXPECT_EQ(twinray::pov::decode_object_id(2, 1), 258);
}

// `twinray pov` as a user meets it.

using twinray::test::CommandResult;
using twinray::test::run_twinray;

class PovCommand : public ::testing::Test {
protected:
    void SetUp() override { folder_ = twinray::test::fresh_directory(twinray::test::own_output_path("pov_command")); }
    fs::path folder_;
};

TEST_F(PovCommand, WritesTheSceneAtTheRequestedSize) {
    fs::path output = folder_ / "csg.pov";
    CommandResult result = run_twinray("pov " + std::string(TWINRAY_SOURCE_DIR) + "/scenes/csg.json -o " +
                                       output.string() + " --width 200");
    ASSERT_EQ(result.exit_status, 0) << result.output;
    EXPECT_TRUE(contains(result.output, "resolution:  200 x 120")) << result.output;
    std::ifstream stream(output);
    std::string text((std::istreambuf_iterator<char>(stream)), std::istreambuf_iterator<char>());
    EXPECT_TRUE(contains(text, "#version 3.7;")) << text;
    EXPECT_TRUE(contains(text, "+W200 +H120")) << text;
}

TEST_F(PovCommand, InvalidSceneExitsTwoAndWritesNothing) {
    fs::path output = folder_ / "bad.pov";
    CommandResult result = run_twinray("pov " + std::string(TWINRAY_SOURCE_DIR) +
                                       "/tests/data/malformed/sphere_radius_zero.json -o " + output.string());
    EXPECT_EQ(result.exit_status, 2) << result.output;
    EXPECT_TRUE(contains(result.output, "objects[0].radius")) << result.output;
    EXPECT_FALSE(fs::exists(output));
}

TEST_F(PovCommand, MissingOutputFolderExitsThree) {
    CommandResult result = run_twinray("pov " + std::string(TWINRAY_SOURCE_DIR) + "/scenes/planes.json -o " +
                                       (folder_ / "missing" / "planes.pov").string());
    EXPECT_EQ(result.exit_status, 3) << result.output;
    EXPECT_TRUE(contains(result.output, "does not exist")) << result.output;
}

TEST_F(PovCommand, DiffWithPovAddsPovRaysImageAndErrorMapAsAThirdColumn) {
    CommandResult result = run_twinray("diff " + std::string(TWINRAY_SOURCE_DIR) +
                                       "/scenes/csg.json --pov --width 80 -o " + (folder_ / "report").string());
    ASSERT_EQ(result.exit_status, 0) << result.output;
    EXPECT_TRUE(fs::exists(folder_ / "report" / "csg" / "povray.png"));
    EXPECT_TRUE(fs::exists(folder_ / "report" / "csg" / "povray_error.png"));
    std::ifstream page(folder_ / "report" / "index.html");
    std::string html((std::istreambuf_iterator<char>(page)), std::istreambuf_iterator<char>());
    EXPECT_TRUE(contains(html, "csg/povray.png")) << "third column missing";
    EXPECT_TRUE(contains(html, "within 2/255 of the reference")) << html;
}

// POV-Ray runs from inside its work folder: an output folder given relative to where twinray was started
// must still hold its scene, log and image (it once failed with "Directory nonexistent", status 70).
TEST_F(PovCommand, DiffWithPovWritesIntoAnOutputFolderGivenRelativeToTheWorkingDirectory) {
    CommandResult result =
        run_twinray("diff " + std::string(TWINRAY_SOURCE_DIR) + "/scenes/spheres.json --pov --width 32 -o report",
                    "cd '" + folder_.string() + "' &&");
    ASSERT_EQ(result.exit_status, 0) << result.output;
    EXPECT_TRUE(fs::exists(folder_ / "report" / "spheres" / "povray.png")) << result.output;
}

}  // namespace

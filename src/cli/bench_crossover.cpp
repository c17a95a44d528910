// `twinray bench --scaling`'s crossover of `--accel auto` (docs/performance.md, "The BVH", measured per kind):
// for each kind of bounded primitive, matte and glass, grids of 1 to 128 of it on a floor, rendered by the SSE
// tracer by brute force and through its BVH in alternated runs; where the BVH starts to pay, beside what `auto`
// weighs each grid (sse::BvhStats::brute_force_weight) and which of the two it builds.
#include "cli/bench_run.h"
#include "cli/generate/scene_text_writer.h"
#include "scene/loader.h"
#include "sse/tracer.h"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

namespace twinray::cli::bench {
namespace {

// The grid's objects, half an octave apart from 8 on, around every kind's crossover (`auto` weighs a sphere 1, a
// box 2.7, a CSG difference of a box and a sphere 5.9 and a tetrahedron's four triangles 24.8).
constexpr int object_counts[] = {1, 2, 4, 8, 12, 16, 24, 32, 48, 64, 96, 128};
// A ratio within this of 1 is noise on this VM, not a choice: `auto` is judged only where the two differ by more.
constexpr double tie_ratio = 1.05;

struct Kind {
    const char* name;
    int primitives_per_object;
    // The object in the cell centred at (x, 0, z), its `"material"` key written after it.
    void (*write)(std::string& json, double x, double z);
};

void point(std::string& json, double x, double y, double z) {
    json += '[';
    append_shortest(json, x);
    json += ',';
    append_shortest(json, y);
    json += ',';
    append_shortest(json, z);
    json += ']';
}

void box_text(std::string& json, double x, double z) {
    json += R"({"type":"box","min":)";
    point(json, x - 0.3, -0.05, z - 0.3);
    json += R"(,"max":)";
    point(json, x + 0.3, 0.6, z + 0.3);
}

void sphere_text(std::string& json, double x, double y, double z, double radius) {
    json += R"({"type":"sphere","center":)";
    point(json, x, y, z);
    json += R"(,"radius":)";
    append_shortest(json, radius);
}

// Tetrahedra go into one mesh (below): a vertex list of four a cell and their triangles, fronts outwards.
const Kind kinds[] = {
    {"sphere", 1, [](std::string& json, double x, double z) { sphere_text(json, x, 0.4, z, 0.4); }},
    {"cylinder", 1,
     [](std::string& json, double x, double z) {
         json += R"({"type":"cylinder","base":)";
         point(json, x, -0.05, z);
         json += R"(,"cap":)";
         point(json, x, 0.7, z);
         json += R"(,"radius":0.3)";
     }},
    {"box", 1, box_text},
    {"ellipsoid", 1,
     [](std::string& json, double x, double z) {
         sphere_text(json, 0, 0, 0, 1);
         json += R"(,"transform":[{"scale":[0.42,0.25,0.3]},{"rotate":[0,35,0]},{"translate":)";
         point(json, x, 0.25, z);
         json += "}]";
     }},
    {"csg difference", 2,
     [](std::string& json, double x, double z) {
         json += R"({"type":"difference","children":[)";
         box_text(json, x, z);
         json += "},";
         sphere_text(json, x, 0.6, z, 0.35);
         json += "}]";
     }},
    {"triangle", 4, nullptr},
};

// `objects` of the kind on a square grid of unit cells, every one of `material`, on a floor, seen from above and in
// front, lit from above; reflection and refraction to the default depth.
scene::Scene grid_scene(const Kind& kind, const char* material, int objects) {
    const int side = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(objects))));
    const double half = 0.5 * side;
    std::string json = R"({"format":"twinray-scene/1","image":{"width":320,"height":240},"camera":{"eye":)";
    point(json, 0, 0.9 * half + 1, -1.4 * half - 1.5);
    json += R"(,"look_at":[0,0.2,0],"fov_deg":50},"background":[0.1,0.1,0.15],)"
            R"("materials":{"floor":{"color":[0.7,0.7,0.7]},"matte":{"color":[0.8,0.5,0.3],"phong":0.4},)"
            R"("glass":{"color":[1,1,1],"diffuse":0.05,"phong":0.6,"reflection":0.1,"transmission":0.9,"ior":1.5}},)"
            R"("lights":[{"position":)";
    point(json, half, 2 * half + 3, -half - 2);
    json += R"(}],"objects":[{"type":"plane","normal":[0,1,0],"offset":0,"material":"floor"})";
    auto cell_x = [&](int i) { return -half + (i % side) + 0.5; };
    auto cell_z = [&](int i) { return -half + (i / side) + 0.5; };
    if (kind.write == nullptr) {
        json += R"(,{"type":"mesh","vertices":[)";
        for (int i = 0; i < objects; ++i) {
            const double x = cell_x(i), z = cell_z(i);
            json += i == 0 ? "" : ",";
            point(json, x - 0.35, 0, z - 0.3);
            json += ',';
            point(json, x + 0.35, 0, z - 0.3);
            json += ',';
            point(json, x, 0, z + 0.35);
            json += ',';
            point(json, x, 0.6, z);
        }
        json += R"(],"triangles":[)";
        constexpr int faces[4][3] = {{0, 1, 2}, {0, 3, 1}, {1, 3, 2}, {2, 3, 0}};
        for (int i = 0; i < objects; ++i) {
            for (const auto& face : faces) {
                json += (json.back() == '[' ? "[" : ",[") + std::to_string(4 * i + face[0]) + "," +
                        std::to_string(4 * i + face[1]) + "," + std::to_string(4 * i + face[2]) + "]";
            }
        }
        json += R"(],"material":")";
        json += material;
        json += R"("})";
    } else {
        for (int i = 0; i < objects; ++i) {
            json += ',';
            kind.write(json, cell_x(i), cell_z(i));
            json += R"(,"material":")";
            json += material;
            json += R"("})";
        }
    }
    json += "]}";
    return scene::parse_scene(json, std::string("crossover ") + kind.name);
}

// Nanoseconds of the pixel loop's CPU time per ray, by brute force and through the BVH, in alternated runs; and whether
// the two images are the same bit for bit.
struct Timed {
    double brute_ns = 0, bvh_ns = 0;
    bool same_images = false;
};

Timed time_both(const scene::Scene& scene, int width, int runs) {
    const Configuration sse{"sse", "sse", {}, 1};
    std::vector<double> brute, bvh;
    std::vector<Image> brute_image, bvh_image;
    std::uint64_t rays = 0;
    for (int run = 0; run < runs; ++run) {
        brute.push_back(time_renders({sse}, scene, width, 1, &brute_image, Accel::none)[0].tracing_cpu_seconds[0]);
        Timings through_bvh = time_renders({sse}, scene, width, 1, &bvh_image, Accel::bvh)[0];
        bvh.push_back(through_bvh.tracing_cpu_seconds[0]);
        rays = through_bvh.rays;
    }
    return {median(brute) * 1e9 / static_cast<double>(rays), median(bvh) * 1e9 / static_cast<double>(rays),
            same_bits(brute_image[0], bvh_image[0])};
}

}  // namespace

void bench_crossover(int width, int runs, Report& report) {
    for (const Kind& kind : kinds) {
        for (const char* material : {"matte", "glass"}) {
            std::fprintf(stderr, "scaling: the crossover of --accel auto, %s, %s:", kind.name, material);
            struct Size {
                int objects;
                double weight, ratio;
                bool automatic_bvh;
            };
            std::vector<Size> sizes;
            for (int objects : object_counts) {
                std::fprintf(stderr, " %d", objects);
                const scene::Scene scene = grid_scene(kind, material, objects);
                const sse::BvhStats automatic = sse::Tracer(scene, {}, Accel::automatic).bvh_stats();
                const Timed timed = time_both(scene, width, runs);
                sizes.push_back(
                    {objects, automatic.brute_force_weight, timed.bvh_ns / timed.brute_ns, automatic.items > 0});
                report.scaling_crossover.add_row(
                    {kind.name, material, std::to_string(objects), std::to_string(objects * kind.primitives_per_object),
                     cell("%.1f", automatic.brute_force_weight), automatic.items > 0 ? "bvh" : "brute force",
                     cell("%.1f", timed.brute_ns), cell("%.1f", timed.bvh_ns), cell("%.2f", sizes.back().ratio),
                     timed.same_images ? "yes" : "NO"});
            }
            std::fputs("\n", stderr);
            // The BVH pays from the first size after which it is faster at every size.
            std::size_t pays_from = sizes.size();
            while (pays_from > 0 && sizes[pays_from - 1].ratio < 1) {
                --pays_from;
            }
            std::size_t automatic_from = 0;
            while (automatic_from < sizes.size() && !sizes[automatic_from].automatic_bvh) {
                ++automatic_from;
            }
            auto objects_and_weight = [&](std::size_t i) -> std::vector<std::string> {
                if (i == sizes.size()) {
                    return {"above " + std::to_string(sizes.back().objects), ""};
                }
                return {std::to_string(sizes[i].objects), cell("%.1f", sizes[i].weight)};
            };
            std::string slower;
            for (const Size& size : sizes) {
                const double cost = size.automatic_bvh ? size.ratio : 1 / size.ratio;  // auto's time over the other's
                if (cost > tie_ratio) {
                    slower +=
                        (slower.empty() ? "" : ", ") + std::to_string(size.objects) + " (" + cell("%.2f", cost) + "x)";
                }
            }
            std::vector<std::string> row = {kind.name, material};
            for (const std::string& text : objects_and_weight(pays_from)) {
                row.push_back(text);
            }
            for (const std::string& text : objects_and_weight(automatic_from)) {
                row.push_back(text);
            }
            row.push_back(slower.empty() ? "none" : slower);
            report.scaling_crossover_summary.add_row(row);
        }
    }
}

}  // namespace twinray::cli::bench

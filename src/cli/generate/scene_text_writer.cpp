#include "cli/generate/scene_text_writer.h"

#include <charconv>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <stdexcept>
#include <utility>

namespace twinray::cli {
namespace {

constexpr std::size_t piece_bytes = std::size_t{1} << 20;

// A file name as a JSON string.
std::string json_string(std::string_view text) {
    std::string quoted = "\"";
    for (char c : text) {
        if (c == '"' || c == '\\') {
            quoted += '\\';
            quoted += c;
        } else if (static_cast<unsigned char>(c) < 0x20) {
            char escape[8];
            std::snprintf(escape, sizeof escape, "\\u%04x", static_cast<unsigned>(static_cast<unsigned char>(c)));
            quoted += escape;
        } else {
            quoted += c;
        }
    }
    return quoted + '"';
}

// A generator's own mistakes, caught before a file the loader would refuse is written.
void check_corners(int a, int b, int c, std::int64_t vertices) {
    for (int index : {a, b, c}) {
        if (index < 0 || index >= vertices) {
            throw std::logic_error("generated triangle names vertex " + std::to_string(index) + " of " +
                                   std::to_string(vertices));
        }
    }
}

void check_normal_count(std::int64_t normals, std::int64_t vertices) {
    if (normals != vertices) {
        throw std::logic_error("generated mesh has " + std::to_string(normals) + " normals for " +
                               std::to_string(vertices) + " vertices");
    }
}

}  // namespace

// std::to_chars's shortest form is exact by the standard, unlike printf's "%g" and iostreams'
// precision, whose last digit each standard library has rounded its own way.
void append_shortest(std::string& text, double value) {
    char digits[64];
    auto [end, error] = std::to_chars(digits, digits + sizeof digits, value, std::chars_format::fixed);
    if (error != std::errc{}) {
        throw std::logic_error("generated coordinate out of range: " + std::to_string(value));
    }
    text.append(digits, end);
}

SceneTextWriter::SceneTextWriter(SceneSink sink, int decimals) : sink_(std::move(sink)), grid_scale_(1) {
    if (decimals < 0 || decimals > 9) {
        throw std::invalid_argument("decimals must be 0..9, got " + std::to_string(decimals));
    }
    // Powers of ten up to 10^22 are exact doubles.
    for (int i = 0; i < decimals; ++i) {
        grid_scale_ *= 10;
    }
    text_.reserve(piece_bytes + 4096);
}

// k / 10^decimals is one correctly rounded division, so the result is the double nearest the decimal
// k·10^-decimals, and the shortest text that reads back as it has at most that decimal's digits.
double SceneTextWriter::on_grid(double value) const {
    double rounded = std::round(value * grid_scale_) / grid_scale_;
    return rounded == 0 ? 0 : rounded;  // no "-0"
}

Vec3 SceneTextWriter::on_grid(Vec3 value) const {
    return {on_grid(value.x), on_grid(value.y), on_grid(value.z)};
}

void SceneTextWriter::number(double value) {
    append_shortest(text_, on_grid(value));
}

void SceneTextWriter::integer(int value) {
    text_ += std::to_string(value);
}

void SceneTextWriter::vector(Vec3 value) {
    text_ += '[';
    number(value.x);
    text_ += ", ";
    number(value.y);
    text_ += ", ";
    number(value.z);
    text_ += ']';
}

void SceneTextWriter::key(std::string_view name) {
    text_ += '"';
    text_ += name;
    text_ += "\": ";
}

void SceneTextWriter::begin(const scene::Scene& header) {
    material_names_ = header.material_names;
    text_ += "{\n  \"format\": \"twinray-scene/1\",\n  \"image\": {\"width\": ";
    integer(header.width);
    text_ += ", \"height\": ";
    integer(header.height);
    text_ += "},\n  \"camera\": {\"eye\": ";
    vector(header.camera.eye);
    text_ += ", \"look_at\": ";
    vector(header.camera.look_at);
    text_ += ", \"up\": ";
    vector(header.camera.up);
    text_ += ", \"fov_deg\": ";
    number(header.camera.fov_deg);
    text_ += "},\n  \"background\": ";
    vector(header.background);
    text_ += ",\n  \"ambient_light\": ";
    vector(header.ambient_light);
    text_ += ",\n  \"max_depth\": ";
    integer(header.max_depth);
    text_ += ",\n  \"materials\": {";
    for (std::size_t i = 1; i < header.materials.size(); ++i) {
        const scene::Material& material = header.materials[i];
        text_ += i > 1 ? ",\n    \"" : "\n    \"";
        text_ += header.material_names[i];
        text_ += "\": {\"color\": ";
        vector(material.color);
        const std::pair<const char*, double> values[] = {{"ambient", material.ambient},
                                                         {"diffuse", material.diffuse},
                                                         {"phong", material.phong},
                                                         {"phong_size", material.phong_size},
                                                         {"reflection", material.reflection},
                                                         {"transmission", material.transmission},
                                                         {"ior", material.ior}};
        for (const auto& [name, value] : values) {
            text_ += ", ";
            key(name);
            number(value);
        }
        text_ += '}';
    }
    text_ += "\n  },\n  \"lights\": [";
    for (std::size_t i = 0; i < header.lights.size(); ++i) {
        text_ += i > 0 ? ",\n    {\"position\": " : "\n    {\"position\": ";
        vector(header.lights[i].position);
        text_ += ", \"color\": ";
        vector(header.lights[i].color);
        text_ += '}';
    }
    text_ += "\n  ]";
    section_ = Section::header;
}

void SceneTextWriter::open_objects() {
    text_ += section_ == Section::shapes ? "\n  },\n  \"objects\": [" : ",\n  \"objects\": [";
    section_ = Section::objects;
    list_has_elements_ = {false};
}

void SceneTextWriter::end() {
    if (list_has_elements_.size() != 1) {
        throw std::logic_error("SceneTextWriter::end with a CSG node still open");
    }
    if (section_ != Section::objects) {
        open_objects();
    }
    text_ += list_has_elements_.back() ? "\n  ]\n}\n" : "]\n}\n";
    sink_.text(text_);
    text_.clear();
}

void SceneTextWriter::begin_object(std::string_view type) {
    if (section_ != Section::objects) {
        open_objects();
    }
    const bool top_level = list_has_elements_.size() == 1;
    if (list_has_elements_.back()) {
        text_ += top_level ? ",\n    " : ", ";
    } else if (top_level) {
        text_ += "\n    ";
    }
    list_has_elements_.back() = true;
    open_object(type);
}

void SceneTextWriter::open_object(std::string_view type) {
    text_ += "{\"type\": \"";
    text_ += type;
    text_ += '"';
}

void SceneTextWriter::material_key(int material) {
    if (material != 0) {
        text_ += ", \"material\": \"";
        text_ += material_names_.at(static_cast<std::size_t>(material));
        text_ += '"';
    }
}

void SceneTextWriter::end_object(int material) {
    material_key(material);
    text_ += '}';
    // Whole top-level objects only reach the sink, so a piece never ends inside a CSG node's text.
    if (list_has_elements_.size() == 1) {
        flush_if_full();
    }
}

void SceneTextWriter::flush_if_full() {
    if (text_.size() >= piece_bytes) {
        sink_.text(text_);
        text_.clear();
    }
}

void SceneTextWriter::plane(Vec3 normal, double offset, int material) {
    begin_object("plane");
    text_ += ", \"normal\": ";
    vector(normal);
    text_ += ", \"offset\": ";
    number(offset);
    ++primitives_;
    end_object(material);
}

void SceneTextWriter::sphere(Vec3 center, double radius, int material) {
    begin_object("sphere");
    text_ += ", \"center\": ";
    vector(center);
    text_ += ", \"radius\": ";
    number(radius);
    ++primitives_;
    end_object(material);
}

void SceneTextWriter::cylinder(Vec3 base, Vec3 cap, double radius, int material) {
    begin_object("cylinder");
    text_ += ", \"base\": ";
    vector(base);
    text_ += ", \"cap\": ";
    vector(cap);
    text_ += ", \"radius\": ";
    number(radius);
    ++primitives_;
    end_object(material);
}

void SceneTextWriter::box(Vec3 min, Vec3 max, int material) {
    begin_object("box");
    text_ += ", \"min\": ";
    vector(min);
    text_ += ", \"max\": ";
    vector(max);
    ++primitives_;
    end_object(material);
}

void SceneTextWriter::begin_mesh_list(std::string_view name) {
    text_ += ", ";
    key(name);
    text_ += '[';
}

// A mesh's lists may be tens of mebibytes: a piece may end between two of their elements.
void SceneTextWriter::next_mesh_list_element(std::int64_t& count) {
    flush_if_full();
    text_ += count == 0 ? "\n      " : ",\n      ";
    ++count;
}

void SceneTextWriter::end_mesh_list(std::int64_t count) {
    text_ += count == 0 ? "]" : "\n    ]";
}

void SceneTextWriter::mesh(const MeshLists& lists, int material) {
    if (section_ == Section::objects && list_has_elements_.size() != 1) {
        throw std::logic_error("SceneTextWriter::mesh inside a CSG node");
    }
    begin_object("mesh");
    ++primitives_;
    mesh_object(lists, material);
}

void SceneTextWriter::shape_mesh(std::string_view name, const MeshLists& lists, int material) {
    if (section_ == Section::objects) {
        throw std::logic_error("SceneTextWriter::shape_mesh after the first object");
    }
    text_ += section_ == Section::header ? ",\n  \"shapes\": {\n    " : ",\n    ";
    section_ = Section::shapes;
    text_ += json_string(name) + ": ";
    open_object("mesh");
    mesh_object(lists, material);
}

void SceneTextWriter::instance(std::string_view shape, const Placement& placement, int material) {
    begin_object("instance");
    text_ += ", \"shape\": " + json_string(shape) + ", \"transform\": [{\"rotate\": ";
    vector({0, placement.turn_deg, 0});
    text_ += "}, {\"scale\": ";
    number(placement.scale);
    text_ += "}, {\"translate\": ";
    vector(placement.position);
    text_ += "}]";
    ++primitives_;
    end_object(material);
}

// After the object's "type": its lists, inline or in a file of their own, and its material.
void SceneTextWriter::mesh_object(const MeshLists& lists, int material) {
    if (sink_.mesh_file) {
        mesh_file(lists);
        end_object(material);
        return;
    }
    std::int64_t vertices = 0;
    begin_mesh_list("vertices");
    lists.vertices([&](Vec3 vertex) {
        next_mesh_list_element(vertices);
        vector(vertex);
    });
    end_mesh_list(vertices);
    std::int64_t triangles = 0;
    begin_mesh_list("triangles");
    lists.triangles([&](int a, int b, int c) {
        check_corners(a, b, c, vertices);
        next_mesh_list_element(triangles);
        text_ += '[';
        integer(a);
        text_ += ", ";
        integer(b);
        text_ += ", ";
        integer(c);
        text_ += ']';
    });
    end_mesh_list(triangles);
    if (lists.normals) {
        std::int64_t normals = 0;
        begin_mesh_list("normals");
        lists.normals([&](Vec3 normal) {
            next_mesh_list_element(normals);
            vector(normal);
        });
        end_mesh_list(normals);
        check_normal_count(normals, vertices);
        text_ += ", \"smooth\": true";
    }
    triangles_ += triangles;
    end_object(material);
}

MeshCounts SceneTextWriter::counted(const MeshLists& lists) const {
    MeshCounts counts;
    lists.vertices([&](Vec3) { ++counts.vertices; });
    lists.triangles([&](int a, int b, int c) {
        check_corners(a, b, c, counts.vertices);
        ++counts.triangles;
    });
    if (lists.normals) {
        std::int64_t normals = 0;
        lists.normals([&](Vec3) { ++normals; });
        check_normal_count(normals, counts.vertices);
    }
    return counts;
}

// The lists go to the file on the grid, so the file holds the very doubles the inline lists would.
void SceneTextWriter::mesh_file(const MeshLists& lists) {
    MeshCounts counts = counted(lists);
    MeshLists on_grid_lists{
        [&](const PointEmitter& emit) { lists.vertices([&](Vec3 vertex) { emit(on_grid(vertex)); }); }, lists.triangles,
        nullptr};
    if (lists.normals) {
        on_grid_lists.normals = [&](const PointEmitter& emit) {
            lists.normals([&](Vec3 normal) { emit(on_grid(normal)); });
        };
    }
    std::string name = sink_.mesh_file(on_grid_lists, counts);
    text_ += ", \"file\": " + json_string(name);
    if (lists.normals) {
        text_ += ", \"smooth\": true";
    }
    triangles_ += counts.triangles;
}

void SceneTextWriter::begin_csg(std::string_view operation, int material) {
    begin_object(operation);
    material_key(material);
    text_ += ", \"children\": [";
    list_has_elements_.push_back(false);
}

void SceneTextWriter::end_csg() {
    list_has_elements_.pop_back();
    text_ += ']';
    end_object(0);
}

}  // namespace twinray::cli

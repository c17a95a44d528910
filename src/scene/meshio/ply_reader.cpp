// PLY, ASCII and binary (either byte order), read here rather than through assimp: Debian 12's assimp 5.2.5
// reads a truncated binary PLY without a word, making coordinates and indices of whatever bytes lie past its
// end, fills a truncated ASCII one with its last values again, and rounds double coordinates to float
// (measured: docs/performance.md, "Mesh files: the library"). Here every value is the file's (binary float or
// double exactly; ASCII text correctly rounded to double by std::from_chars, whatever type the header
// declares), and a file that ends early is refused where it ends.
#include "scene/meshio/polygon.h"
#include "scene/meshio/readers.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <optional>
#include <set>

namespace twinray::scene::meshio {
namespace {

enum class Type { int8, uint8, int16, uint16, int32, uint32, float32, float64 };

std::optional<Type> type_named(std::string_view name) {
    static const std::array<std::pair<std::string_view, Type>, 16> names{{
        {"char", Type::int8},
        {"int8", Type::int8},
        {"uchar", Type::uint8},
        {"uint8", Type::uint8},
        {"short", Type::int16},
        {"int16", Type::int16},
        {"ushort", Type::uint16},
        {"uint16", Type::uint16},
        {"int", Type::int32},
        {"int32", Type::int32},
        {"uint", Type::uint32},
        {"uint32", Type::uint32},
        {"float", Type::float32},
        {"float32", Type::float32},
        {"double", Type::float64},
        {"float64", Type::float64},
    }};
    for (const auto& [known, type] : names) {
        if (name == known) {
            return type;
        }
    }
    return std::nullopt;
}

std::size_t size_of(Type type) {
    switch (type) {
        case Type::int8:
        case Type::uint8: return 1;
        case Type::int16:
        case Type::uint16: return 2;
        case Type::int32:
        case Type::uint32:
        case Type::float32: return 4;
        case Type::float64: return 8;
    }
    return 0;
}

bool is_integer(Type type) {
    return type != Type::float32 && type != Type::float64;
}

struct Property {
    std::string name;
    Type type;                       // of the value, or of a list's items
    std::optional<Type> count_type;  // set for a list
};

struct Element {
    std::string name;
    std::uint64_t count = 0;
    std::vector<Property> properties;
};

enum class Encoding { ascii, little_endian, big_endian };

struct Header {
    Encoding encoding = Encoding::ascii;
    std::vector<Element> elements;
    std::size_t body_offset = 0;
    std::size_t body_first_line = 0;
};

// What the vertex and face elements are made of: positions of their properties that matter.
struct Layout {
    std::size_t vertex_element = 0;
    std::optional<std::size_t> face_element;
    std::array<std::size_t, 3> position{};
    std::optional<std::array<std::size_t, 3>> normal;
    std::size_t face_indices = 0;
};

constexpr std::size_t longest_header = std::size_t{1} << 20;

// Lines the format does not know (Blender 2.47 wrote one saying so) are passed over with a warning.
Header read_header(std::string_view bytes, std::vector<std::string>& warnings) {
    Header header;
    std::size_t at = 0;
    std::size_t line_number = 0;
    bool format_seen = false;
    for (;;) {
        const std::size_t end = bytes.find('\n', at);
        if (end == std::string_view::npos || end > longest_header) {
            refuse_at("header", "no end_header line in the first " + std::to_string(longest_header) + " bytes");
        }
        std::string_view line = bytes.substr(at, end - at);
        if (line.ends_with('\r')) {
            line.remove_suffix(1);
        }
        at = end + 1;
        ++line_number;
        const std::string location = "header line " + std::to_string(line_number);
        std::vector<std::string_view> words;
        for (std::size_t word = line.find_first_not_of(" \t"); word != std::string_view::npos;) {
            const std::size_t word_end = std::min(line.find_first_of(" \t", word), line.size());
            words.push_back(line.substr(word, word_end - word));
            word = line.find_first_not_of(" \t", word_end);
        }
        if (line_number == 1) {
            if (words.size() != 1 || words[0] != "ply") {
                refuse_at(location, "not a PLY file: it does not begin with the line \"ply\"");
            }
            continue;
        }
        if (words.empty() || words[0] == "comment" || words[0] == "obj_info") {
            continue;
        }
        if (words[0] == "end_header") {
            if (!format_seen) {
                refuse_at(location, "no format line before end_header");
            }
            header.body_offset = at;
            header.body_first_line = line_number + 1;
            return header;
        }
        if (words[0] == "format") {
            if (words.size() != 3 || words[2] != "1.0") {
                refuse_at(location, "the format line is \"format ascii|binary_little_endian|binary_big_endian 1.0\"");
            }
            if (words[1] == "ascii") {
                header.encoding = Encoding::ascii;
            } else if (words[1] == "binary_little_endian") {
                header.encoding = Encoding::little_endian;
            } else if (words[1] == "binary_big_endian") {
                header.encoding = Encoding::big_endian;
            } else {
                refuse_at(location, "unknown format " + quote_word(words[1]));
            }
            format_seen = true;
        } else if (words[0] == "element") {
            std::uint64_t count = 0;
            const auto [stop, error] = words.size() == 3 ? std::from_chars(words[2].begin(), words[2].end(), count)
                                                         : std::from_chars_result{nullptr, std::errc::invalid_argument};
            if (error != std::errc{} || stop != words[2].end()) {
                refuse_at(location, "an element line is \"element NAME COUNT\"");
            }
            header.elements.push_back({std::string(words[1]), count, {}});
        } else if (words[0] == "property") {
            if (header.elements.empty()) {
                refuse_at(location, "a property before any element");
            }
            const bool list = words.size() == 5 && words[1] == "list";
            if (words.size() != (list ? 5 : 3)) {
                refuse_at(location,
                          "a property line is \"property TYPE NAME\" or \"property list COUNT_TYPE TYPE NAME\"");
            }
            const std::optional<Type> type = type_named(words[list ? 3 : 1]);
            const std::optional<Type> count_type = list ? type_named(words[2]) : std::nullopt;
            if (!type || (list && (!count_type || !is_integer(*count_type)))) {
                refuse_at(location, "unknown type in " + quote_word(line));
            }
            header.elements.back().properties.push_back({std::string(words.back()), *type, count_type});
        } else {
            warnings.push_back(location + " is not PLY and was passed over: " + quote_word(line));
        }
    }
}

std::optional<std::size_t> find_property(const Element& element, std::string_view name) {
    for (std::size_t p = 0; p < element.properties.size(); ++p) {
        if (element.properties[p].name == name) {
            return p;
        }
    }
    return std::nullopt;
}

Layout layout_of(const Header& header, std::size_t max_triangles, std::vector<std::string>& warnings) {
    Layout layout;
    std::optional<std::size_t> vertex_element;
    for (std::size_t e = 0; e < header.elements.size(); ++e) {
        const Element& element = header.elements[e];
        if (element.name == "vertex") {
            vertex_element = e;
        } else if (element.name == "face") {
            layout.face_element = e;
        } else if (element.name == "material") {
            warnings.push_back("materials (element material) are not used");
        }
    }
    if (!vertex_element) {
        refuse_at("header", "no element vertex");
    }
    layout.vertex_element = *vertex_element;
    const Element& vertices = header.elements[layout.vertex_element];
    if (vertices.count > max_vertices_for(max_triangles)) {
        refuse_too_many_vertices("header", vertices.count, max_triangles);
    }
    for (int axis = 0; axis < 3; ++axis) {
        const std::string name(1, "xyz"[axis]);
        const std::optional<std::size_t> position = find_property(vertices, name);
        if (!position || vertices.properties[*position].count_type) {
            refuse_at("header", "element vertex has no property " + name);
        }
        layout.position[axis] = *position;
    }
    const auto nx = find_property(vertices, "nx");
    const auto ny = find_property(vertices, "ny");
    const auto nz = find_property(vertices, "nz");
    if (nx && ny && nz && !vertices.properties[*nx].count_type && !vertices.properties[*ny].count_type &&
        !vertices.properties[*nz].count_type) {
        layout.normal = std::array{*nx, *ny, *nz};
    }
    static const std::set<std::string_view> colours{"red", "green", "blue",        "alpha",         "r",           "g",
                                                    "b",   "a",     "diffuse_red", "diffuse_green", "diffuse_blue"};
    static const std::set<std::string_view> texture{"u",         "v",         "s",         "t",       "texture_u",
                                                    "texture_v", "texture_s", "texture_t", "texcoord"};
    for (const std::optional<std::size_t> e :
         {std::optional<std::size_t>(layout.vertex_element), layout.face_element}) {
        if (!e) {
            continue;
        }
        std::string colour_names;
        bool texture_coordinates = false;
        for (const Property& property : header.elements[*e].properties) {
            if (colours.contains(property.name)) {
                colour_names += (colour_names.empty() ? "" : ", ") + property.name;
            }
            texture_coordinates = texture_coordinates || texture.contains(property.name);
        }
        const std::string& element = header.elements[*e].name;
        if (!colour_names.empty()) {
            warnings.push_back(element + " colours (" + colour_names + ") are not used");
        }
        if (texture_coordinates) {
            warnings.push_back(element + " texture coordinates are not used");
        }
    }
    if (!layout.face_element || header.elements[*layout.face_element].count == 0) {
        refuse_at("", "no triangles: the file has " + std::to_string(vertices.count) + " vertices and no faces");
    }
    const Element& faces = header.elements[*layout.face_element];
    if (*layout.face_element < layout.vertex_element) {
        refuse_at("header", "element face comes before element vertex (twinray reads files with vertices first)");
    }
    if (faces.count > max_triangles) {
        refuse_too_many_triangles(
            "header", "element face declares " + std::to_string(faces.count) + " faces, each at least one triangle",
            max_triangles);
    }
    std::optional<std::size_t> indices = find_property(faces, "vertex_indices");
    if (!indices) {
        indices = find_property(faces, "vertex_index");
    }
    if (!indices || !faces.properties[*indices].count_type || !is_integer(faces.properties[*indices].type)) {
        refuse_at("header", "element face has no list of integers named vertex_indices (or vertex_index)");
    }
    layout.face_indices = *indices;
    return layout;
}

// The fewest bytes the header's elements can take: a file shorter than that is refused before anything is
// allocated for it. Binary: every value and list count at its size; ASCII: a digit and a separator each.
void check_length(const Header& header, std::size_t body_size) {
    std::uint64_t needed = 0;
    for (const Element& element : header.elements) {
        std::uint64_t per_item = 0;
        for (const Property& property : element.properties) {
            per_item += header.encoding == Encoding::ascii ? 2 : size_of(property.count_type.value_or(property.type));
        }
        std::uint64_t bytes = 0;
        if (__builtin_mul_overflow(per_item, element.count, &bytes) || __builtin_add_overflow(needed, bytes, &needed)) {
            needed = std::numeric_limits<std::uint64_t>::max();
            break;
        }
    }
    if (needed > body_size) {
        refuse_at("", "truncated: the elements the header declares take at least " + std::to_string(needed) +
                          " bytes, and the file has " + std::to_string(body_size) + " after its header");
    }
}

// Values one after the other, at the size and in the byte order the header says.
class BinaryBody {
public:
    BinaryBody(std::string_view body, bool big_endian)
        : at_(body.data()), end_(body.data() + body.size()), big_endian_(big_endian) {}

    void begin(const Element& element, std::uint64_t index) {
        element_ = &element;
        index_ = index;
    }
    void end() {}
    std::string location() const { return element_->name + "[" + std::to_string(index_) + "]"; }

    double value(Type type) {
        switch (type) {
            case Type::int8: return take<std::int8_t>();
            case Type::uint8: return take<std::uint8_t>();
            case Type::int16: return take<std::int16_t>();
            case Type::uint16: return take<std::uint16_t>();
            case Type::int32: return take<std::int32_t>();
            case Type::uint32: return take<std::uint32_t>();
            case Type::float32: return take<float>();
            case Type::float64: return take<double>();
        }
        return 0;
    }

private:
    template <typename T>
    T take() {
        if (static_cast<std::size_t>(end_ - at_) < sizeof(T)) {
            refuse_at(location(), "the file ends inside this " + element_->name + " of " +
                                      std::to_string(element_->count) + ": truncated");
        }
        std::array<char, sizeof(T)> bytes;
        std::memcpy(bytes.data(), at_, sizeof(T));
        if (big_endian_) {
            std::reverse(bytes.begin(), bytes.end());
        }
        at_ += sizeof(T);
        T value;
        std::memcpy(&value, bytes.data(), sizeof(T));
        return value;
    }

    const char* at_;
    const char* end_;
    bool big_endian_;
    const Element* element_ = nullptr;
    std::uint64_t index_ = 0;
};

// One line per element, words separated by spaces.
class AsciiBody {
public:
    AsciiBody(std::string_view body, std::size_t first_line) : text_(body), line_number_(first_line) {}

    void begin(const Element& element, std::uint64_t index) {
        element_ = &element;
        index_ = index;
        // Blank lines between elements are passed over.
        while (at_ < text_.size() && rest_of_line_is_blank()) {
            next_line();
        }
        if (at_ == text_.size()) {
            refuse_at(location(), "the file ends before this " + element_->name + " of " +
                                      std::to_string(element_->count) + ": truncated");
        }
    }

    void end() {
        if (!rest_of_line_is_blank()) {
            refuse_at(location(), "more values than the header declares for a " + element_->name);
        }
        next_line();
    }

    std::string location() const {
        return "line " + std::to_string(line_number_) + " (" + element_->name + "[" + std::to_string(index_) + "])";
    }

    double value(Type type) {
        skip_spaces();
        if (at_ == text_.size() || text_[at_] == '\n') {
            refuse_at(location(), "fewer values than the header declares for a " + element_->name);
        }
        const std::size_t start = at_;
        while (at_ < text_.size() && !is_space(text_[at_]) && text_[at_] != '\n') {
            ++at_;
        }
        const std::string_view word = text_.substr(start, at_ - start);
        return is_integer(type) ? integer(word, type) : real(word);
    }

private:
    static bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r'; }

    void skip_spaces() {
        while (at_ < text_.size() && is_space(text_[at_])) {
            ++at_;
        }
    }

    bool rest_of_line_is_blank() {
        skip_spaces();
        return at_ == text_.size() || text_[at_] == '\n';
    }

    void next_line() {
        const std::size_t end = text_.find('\n', at_);
        at_ = end == std::string_view::npos ? text_.size() : end + 1;
        ++line_number_;
    }

    double integer(std::string_view word, Type type) {
        long long value = 0;
        const auto [stop, error] = std::from_chars(word.data(), word.data() + word.size(), value);
        const long long bits = static_cast<long long>(size_of(type)) * 8;
        const bool is_signed = type == Type::int8 || type == Type::int16 || type == Type::int32;
        const long long lowest = is_signed ? -(1LL << (bits - 1)) : 0;
        const long long highest = is_signed ? (1LL << (bits - 1)) - 1 : (1LL << bits) - 1;
        if (error != std::errc{} || stop != word.data() + word.size() || value < lowest || value > highest) {
            refuse_at(location(), quote_word(word) + " is not an integer of the type the header declares");
        }
        return static_cast<double>(value);
    }

    double real(std::string_view word) {
        const std::string_view digits = word.starts_with('+') ? word.substr(1) : word;
        double value = 0;
        const auto [stop, error] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
        if (error != std::errc{} || stop != digits.data() + digits.size()) {
            refuse_at(location(), quote_word(word) + " is not a number");
        }
        return value;
    }

    std::string_view text_;
    std::size_t at_ = 0;
    std::size_t line_number_;
    const Element* element_ = nullptr;
    std::uint64_t index_ = 0;
};

template <typename Body>
MeshReading read_body(Body& body, const Header& header, const Layout& layout, std::size_t max_triangles,
                      MeshReading reading) {
    const std::uint64_t vertex_count = header.elements[layout.vertex_element].count;
    std::vector<Vec3>& vertices = reading.meshes.front().vertices;
    std::vector<Vec3> normals;
    std::vector<std::array<std::uint32_t, 3>>& triangles = reading.meshes.front().triangles;
    vertices.reserve(vertex_count);
    triangles.reserve(header.elements[*layout.face_element].count);
    std::optional<std::string> unusable_normal;
    PolygonTriangulator triangulator;
    std::vector<std::uint32_t> polygon;
    std::vector<Vec3> corners;
    std::vector<double> values;
    for (std::size_t e = 0; e < header.elements.size(); ++e) {
        const Element& element = header.elements[e];
        const bool is_vertex = e == layout.vertex_element;
        const bool is_face = e == layout.face_element;
        for (std::uint64_t index = 0; index < element.count; ++index) {
            body.begin(element, index);
            values.clear();
            for (std::size_t p = 0; p < element.properties.size(); ++p) {
                const Property& property = element.properties[p];
                if (!property.count_type) {
                    values.push_back(body.value(property.type));
                    continue;
                }
                values.push_back(0);  // keeps the positions of the scalars after it
                const double declared = body.value(*property.count_type);
                if (declared < 0) {
                    refuse_at(body.location(), "a list of " + format_number(declared) + " values");
                }
                const auto items = static_cast<std::uint64_t>(declared);
                if (!is_face || p != layout.face_indices) {
                    for (std::uint64_t item = 0; item < items; ++item) {
                        body.value(property.type);  // read past, not used
                    }
                    continue;
                }
                if (items < 3) {
                    refuse_at(body.location(), "a face has at least 3 vertices, this one " + std::to_string(items));
                }
                if (triangles.size() + items - 2 > max_triangles) {
                    refuse_too_many_triangles(
                        body.location(),
                        "this face brings the triangles to " + std::to_string(triangles.size() + items - 2),
                        max_triangles);
                }
                polygon.clear();
                corners.clear();
                for (std::uint64_t item = 0; item < items; ++item) {
                    const double vertex = body.value(property.type);
                    if (vertex < 0 || vertex >= static_cast<double>(vertex_count)) {
                        refuse_at(body.location(), "vertex index " + format_number(vertex) +
                                                       " is out of range: the file has " +
                                                       std::to_string(vertex_count) + " vertices");
                    }
                    polygon.push_back(static_cast<std::uint32_t>(vertex));
                    corners.push_back(vertices[polygon.back()]);
                }
                for (const auto& [a, b, c] : triangulator.triangulate(corners)) {
                    triangles.push_back({polygon[a], polygon[b], polygon[c]});
                }
            }
            if (is_vertex) {
                const Vec3 position{values[layout.position[0]], values[layout.position[1]], values[layout.position[2]]};
                for (int axis = 0; axis < 3; ++axis) {
                    if (!std::isfinite(position[axis])) {
                        refuse_at(body.location(), std::string("coordinate ") + "xyz"[axis] + " is not finite (" +
                                                       format_number(position[axis]) + ")");
                    }
                }
                vertices.push_back(position);
                if (layout.normal) {
                    const Vec3 normal{values[(*layout.normal)[0]], values[(*layout.normal)[1]],
                                      values[(*layout.normal)[2]]};
                    const double size = length(normal);
                    if ((!(size > 0) || !std::isfinite(size)) && !unusable_normal) {
                        unusable_normal = body.location();
                    }
                    normals.push_back(normal);  // made unit length by the loader, as inline normals are
                }
            }
            body.end();
        }
    }
    if (unusable_normal) {
        reading.warnings.push_back("normals (nx, ny, nz) are not used: the one of " + *unusable_normal +
                                   " has no direction");
    } else if (layout.normal) {
        reading.meshes.front().normals = std::move(normals);
        reading.meshes.front().smooth = true;
    }
    return reading;
}

}  // namespace

MeshReading read_ply(const std::filesystem::path& file, std::size_t max_triangles) {
    const MappedFile mapped(file);
    MeshReading reading = one_mesh_reading();
    const Header header = read_header(mapped.bytes(), reading.warnings);
    const Layout layout = layout_of(header, max_triangles, reading.warnings);
    const std::string_view body = mapped.bytes().substr(header.body_offset);
    check_length(header, body.size());
    if (header.encoding == Encoding::ascii) {
        AsciiBody ascii(body, header.body_first_line);
        return read_body(ascii, header, layout, max_triangles, std::move(reading));
    }
    BinaryBody binary(body, header.encoding == Encoding::big_endian);
    return read_body(binary, header, layout, max_triangles, std::move(reading));
}

}  // namespace twinray::scene::meshio

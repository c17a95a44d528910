// OBJ through tinyobjloader's callback API (no copy of the file's faces in the library's own structures).
// tinyobjloader splits the file into lines and faces into indices; it reads numbers with a parser of its own
// that is not correctly rounded (57% of the coordinates of a 17-digit file came out up to 5 ulp off) and
// takes anything that is not a number, "nan" included, for 0 without a word. So each `v` and `vn` line's
// numbers are read again here, from the line tinyobjloader has just passed to us, with std::from_chars:
// correctly rounded to double, and a word that is not a finite number is refused with its line.
#define TINYOBJLOADER_USE_DOUBLE
#define TINYOBJLOADER_IMPLEMENTATION
#include <tiny_obj_loader.h>

#include "scene/meshio/polygon.h"
#include "scene/meshio/readers.h"

#include <charconv>
#include <cmath>
#include <cstdint>
#include <istream>
#include <limits>
#include <map>
#include <set>
#include <streambuf>
#include <unordered_map>

namespace twinray::scene::meshio {
namespace {

constexpr std::uint32_t no_normal = std::numeric_limits<std::uint32_t>::max();

// The mapped file as tinyobjloader's stream. Its callbacks run right after it has read a line up to and
// including its end (\n, \r\n or \r), so the line a callback is about ends where the stream stands.
class LineStream : public std::streambuf {
public:
    explicit LineStream(std::string_view text) {
        char* begin = const_cast<char*>(text.data());  // only ever read
        setg(begin, begin, begin + text.size());
    }

    std::string_view last_line() const {
        const char* end = gptr();
        if (end > eback() && end[-1] == '\n') {
            --end;
        }
        if (end > eback() && end[-1] == '\r') {
            --end;
        }
        const char* start = end;
        while (start > eback() && start[-1] != '\n' && start[-1] != '\r') {
            --start;
        }
        return {start, static_cast<std::size_t>(end - start)};
    }

    // "line 12", counting from 1; only for messages (it counts from the start of the file).
    std::string last_line_name() const { return line_name(last_line().data()); }

    std::string line_name(const char* start) const {
        std::size_t number = 1;
        for (const char* c = eback(); c < start; ++c) {
            number += *c == '\n' || (*c == '\r' && (c + 1 == start || c[1] != '\n'));
        }
        return "line " + std::to_string(number);
    }
};

struct Corner {
    std::uint32_t vertex;
    std::uint32_t normal;  // no_normal when the face gives none
};

class ObjReader {
public:
    ObjReader(LineStream& lines, std::size_t max_triangles) : lines_(lines), max_triangles_(max_triangles) {}

    static tinyobj::callback_t callbacks() {
        tinyobj::callback_t callbacks;
        callbacks.vertex_cb = [](void* self, double, double, double, double) { as_reader(self).vertex(); };
        callbacks.normal_cb = [](void* self, double, double, double) { as_reader(self).normal(); };
        callbacks.texcoord_cb = [](void* self, double, double, double) { as_reader(self).texture_coordinates_ = true; };
        callbacks.index_cb = [](void* self, tinyobj::index_t* indices, int count) {
            as_reader(self).face(indices, count);
        };
        callbacks.usemtl_cb = [](void* self, const char* name, int) { as_reader(self).materials_.insert(name); };
        return callbacks;
    }

    // Material libraries are named, never read.
    class MaterialNames : public tinyobj::MaterialReader {
    public:
        explicit MaterialNames(ObjReader& reader) : reader_(reader) {}
        bool operator()(const std::string& library, std::vector<tinyobj::material_t>*, std::map<std::string, int>*,
                        std::string*, std::string*) override {
            reader_.material_libraries_.insert(library);
            return false;
        }

    private:
        ObjReader& reader_;
    };

    MeshReading finish() {
        MeshReading reading = one_mesh_reading();
        if (triangles_.empty()) {
            refuse_at("", "no triangles: the file has " + std::to_string(vertices_.size()) + " vertices and no faces");
        }
        if (colours_) {
            reading.warnings.push_back("vertex colours (v lines with six or seven numbers) are not used");
        }
        if (texture_coordinates_) {
            reading.warnings.push_back("texture coordinates (vt) are not used");
        }
        if (!materials_.empty() || !material_libraries_.empty()) {
            reading.warnings.push_back("materials are not used: " + names("mtllib", material_libraries_) +
                                       (material_libraries_.empty() || materials_.empty() ? "" : "; ") +
                                       names("usemtl", materials_));
        }
        if (!corner_normals_.empty()) {
            attach_normals(reading);
        }
        MeshData& mesh = reading.meshes.front();
        mesh.triangles = std::move(triangles_);
        mesh.vertices = std::move(vertices_);
        if (mesh.vertices.size() > max_vertices_for(max_triangles_)) {
            refuse_too_many_vertices("", mesh.vertices.size(), max_triangles_);
        }
        return reading;
    }

private:
    static ObjReader& as_reader(void* self) { return *static_cast<ObjReader*>(self); }

    // The numbers after the line's keyword (v, vn): at most seven, each a finite double.
    std::size_t numbers_of_line(std::array<double, 7>& numbers) {
        const std::string_view line = lines_.last_line();
        const char* at = line.data();
        const char* const end = at + line.size();
        const auto is_space = [](char c) { return c == ' ' || c == '\t'; };
        while (at < end && is_space(*at)) {
            ++at;
        }
        while (at < end && !is_space(*at)) {
            ++at;  // the keyword
        }
        std::size_t count = 0;
        for (;;) {
            while (at < end && is_space(*at)) {
                ++at;
            }
            if (at == end || *at == '#') {
                return count;
            }
            const char* word_end = at;
            while (word_end < end && !is_space(*word_end)) {
                ++word_end;
            }
            const std::string_view word(at, static_cast<std::size_t>(word_end - at));
            if (count == numbers.size()) {
                refuse_at(lines_.last_line_name(), "more than " + std::to_string(numbers.size()) + " numbers");
            }
            const char* digits = *at == '+' ? at + 1 : at;
            const auto [stop, error] = std::from_chars(digits, word_end, numbers[count]);
            if (error == std::errc::result_out_of_range) {
                refuse_at(lines_.last_line_name(), quote_word(word) + " is beyond the range of a double");
            }
            if (error != std::errc{} || stop != word_end) {
                refuse_at(lines_.last_line_name(), quote_word(word) + " is not a number");
            }
            if (!std::isfinite(numbers[count])) {
                refuse_at(lines_.last_line_name(), quote_word(word) + " is not a finite number");
            }
            ++count;
            at = word_end;
        }
    }

    void vertex() {
        std::array<double, 7> numbers{};
        const std::size_t count = numbers_of_line(numbers);
        // x y z, then an optional w (for rational curves: meaningless for a polygon) and/or a colour.
        if (count < 3 || count == 5) {
            refuse_at(lines_.last_line_name(), "a vertex has x, y and z, optionally w and a colour (r g b), not " +
                                                   std::to_string(count) + " numbers");
        }
        colours_ = colours_ || count >= 6;
        if (vertices_.size() == max_vertices_for(max_triangles_)) {
            refuse_too_many_vertices(lines_.last_line_name(), vertices_.size() + 1, max_triangles_);
        }
        vertices_.push_back({numbers[0], numbers[1], numbers[2]});
    }

    void normal() {
        std::array<double, 7> numbers{};
        if (numbers_of_line(numbers) != 3) {
            refuse_at(lines_.last_line_name(), "a normal (vn) has three numbers");
        }
        normals_.push_back({numbers[0], numbers[1], numbers[2]});
    }

    // OBJ counts from 1, and from the end (-1 the last) when negative; relative indices count what the file
    // has defined before the face, and so do absolute ones here, as every writer puts them.
    std::uint32_t resolve(int index, std::size_t defined, const char* what) {
        const long long resolved = index > 0 ? index - 1LL : static_cast<long long>(defined) + index;
        if (index == 0 || resolved < 0 || resolved >= static_cast<long long>(defined)) {
            refuse_at(lines_.last_line_name(), std::string(what) + " index " + std::to_string(index) +
                                                   " refers to no " + what + ": " + std::to_string(defined) +
                                                   " are defined before this line");
        }
        return static_cast<std::uint32_t>(resolved);
    }

    void face(const tinyobj::index_t* indices, int count) {
        if (count < 3) {
            refuse_at(lines_.last_line_name(), "a face has at least 3 vertices, this one " + std::to_string(count));
        }
        const auto added = static_cast<std::size_t>(count - 2);
        if (triangles_.size() + added > max_triangles_) {
            refuse_too_many_triangles(lines_.last_line_name(),
                                      "this face brings the triangles to " + std::to_string(triangles_.size() + added),
                                      max_triangles_);
        }
        corners_.clear();
        positions_.clear();
        for (int i = 0; i < count; ++i) {
            const tinyobj::index_t& index = indices[i];
            const std::uint32_t vertex = resolve(index.vertex_index, vertices_.size(), "vertex");
            // 0 is tinyobjloader's word for "no normal given".
            const std::uint32_t normal =
                index.normal_index == 0 ? no_normal : resolve(index.normal_index, normals_.size(), "normal");
            corners_.push_back({vertex, normal});
            positions_.push_back(vertices_[vertex]);
        }
        if (count == 3) {  // most faces: no triangulation to ask for
            triangles_.push_back({corners_[0].vertex, corners_[1].vertex, corners_[2].vertex});
            add_corner_normals(corners_[0].normal, corners_[1].normal, corners_[2].normal);
            return;
        }
        for (const auto& [a, b, c] : triangulator_.triangulate(positions_)) {
            triangles_.push_back({corners_[a].vertex, corners_[b].vertex, corners_[c].vertex});
            add_corner_normals(corners_[a].normal, corners_[b].normal, corners_[c].normal);
        }
    }

    // Kept from the first face that gives a normal on; the faces before it are recorded as giving none.
    void add_corner_normals(std::uint32_t a, std::uint32_t b, std::uint32_t c) {
        const bool any = a != no_normal || b != no_normal || c != no_normal;
        if (corner_normals_.empty() && !any) {
            if (!first_face_without_normals_) {
                first_face_without_normals_ = lines_.last_line().data();
            }
            return;
        }
        if (corner_normals_.empty()) {
            corner_normals_.assign(triangles_.size() - 1, {no_normal, no_normal, no_normal});
        }
        if ((a == no_normal || b == no_normal || c == no_normal) && !first_face_without_normals_) {
            first_face_without_normals_ = lines_.last_line().data();
        }
        corner_normals_.push_back({a, b, c});
    }

    // One normal per vertex: a vertex that faces give with different normals is split, its first normal
    // keeping the file's index and each further one a new vertex at the end. Not used at all (a warning) when
    // some face gives none or a given normal has no direction.
    void attach_normals(MeshReading& reading) {
        if (first_face_without_normals_) {
            reading.warnings.push_back("normals (vn) are not used: some faces give none, the first at " +
                                       lines_.line_name(first_face_without_normals_));
            return;
        }
        std::vector<std::uint32_t> normal_of(vertices_.size(), no_normal);
        std::unordered_map<std::uint64_t, std::uint32_t> split;
        for (std::size_t t = 0; t < triangles_.size(); ++t) {
            for (int k = 0; k < 3; ++k) {
                std::uint32_t& vertex = triangles_[t][k];
                const std::uint32_t normal = corner_normals_[t][k];
                if (normal_of[vertex] == no_normal) {
                    normal_of[vertex] = normal;
                } else if (normal_of[vertex] != normal) {
                    const std::uint64_t key = std::uint64_t{vertex} << 32 | normal;
                    const auto [added, inserted] = split.try_emplace(key, static_cast<std::uint32_t>(vertices_.size()));
                    if (inserted) {
                        vertices_.push_back(vertices_[vertex]);
                        normal_of.push_back(normal);
                    }
                    vertex = added->second;
                }
            }
        }
        std::vector<Vec3> normals(vertices_.size(), Vec3{0, 0, 1});  // a vertex no face uses is never shaded
        for (std::size_t v = 0; v < vertices_.size(); ++v) {
            if (normal_of[v] == no_normal) {
                continue;
            }
            const Vec3 given = normals_[normal_of[v]];
            const double size = length(given);
            if (!(size > 0) || !std::isfinite(size)) {
                reading.warnings.push_back("normals (vn) are not used: normal " + std::to_string(normal_of[v] + 1) +
                                           " has no direction");
                return;
            }
            normals[v] = given;  // made unit length by the loader, as inline normals are
        }
        reading.meshes.front().normals = std::move(normals);
        reading.meshes.front().smooth = true;
    }

    static std::string names(const char* keyword, const std::set<std::string>& names) {
        return names.empty() ? "" : std::string(keyword) + " " + quoted_names(names);
    }

    LineStream& lines_;
    std::size_t max_triangles_;
    std::vector<Vec3> vertices_;
    std::vector<Vec3> normals_;
    std::vector<std::array<std::uint32_t, 3>> triangles_;
    std::vector<std::array<std::uint32_t, 3>> corner_normals_;  // per triangle corner, once a face gives any
    const char* first_face_without_normals_ = nullptr;          // where its line begins
    bool colours_ = false;
    bool texture_coordinates_ = false;
    std::set<std::string> materials_;
    std::set<std::string> material_libraries_;
    PolygonTriangulator triangulator_;
    std::vector<Corner> corners_;
    std::vector<Vec3> positions_;
};

}  // namespace

MeshReading read_obj(const std::filesystem::path& file, std::size_t max_triangles) {
    const MappedFile mapped(file);
    LineStream lines(mapped.bytes());
    std::istream stream(&lines);
    ObjReader reader(lines, max_triangles);
    ObjReader::MaterialNames material_names(reader);
    std::string library_warnings;  // ours say more (which materials, which line)
    std::string library_errors;
    if (!tinyobj::LoadObjWithCallback(stream, ObjReader::callbacks(), &reader, &material_names, &library_warnings,
                                      &library_errors)) {
        refuse_at("", "tinyobjloader: " + printable(library_errors));
    }
    return reader.finish();
}

}  // namespace twinray::scene::meshio

#include "cli/generate/mesh_file_writer.h"

#include <bit>
#include <cerrno>
#include <cstdint>
#include <stdexcept>
#include <system_error>

namespace twinray::cli::generate {
namespace {

// Hands the text to the stream in pieces of about a mebibyte, stopping at the first failed write.
class StreamBuffer {
public:
    explicit StreamBuffer(std::FILE* stream) : stream_(stream) {}
    std::string& text() { return text_; }
    void flush_if_full() {
        if (text_.size() >= (std::size_t{1} << 20)) {
            flush();
        }
    }
    void flush() {
        if (std::fwrite(text_.data(), 1, text_.size(), stream_) != text_.size()) {
            throw std::system_error(errno, std::generic_category());
        }
        text_.clear();
    }

private:
    std::FILE* stream_;
    std::string text_;
};

void append_point(std::string& text, const char* tag, Vec3 point) {
    text += tag;
    for (double coordinate : {point.x, point.y, point.z}) {
        text += ' ';
        append_shortest(text, coordinate);
    }
    text += '\n';
}

// Vertices, then normals (`vn`, one per vertex, so each corner's normal has its vertex's number), then the
// faces, numbered from 1.
void write_obj(StreamBuffer& out, const MeshLists& lists) {
    out.text() += "# twinray generate\n";
    lists.vertices([&](Vec3 vertex) {
        append_point(out.text(), "v", vertex);
        out.flush_if_full();
    });
    if (lists.normals) {
        lists.normals([&](Vec3 normal) {
            append_point(out.text(), "vn", normal);
            out.flush_if_full();
        });
    }
    lists.triangles([&](int a, int b, int c) {
        out.text() += 'f';
        for (int index : {a, b, c}) {
            std::string number = std::to_string(index + 1);
            out.text() += ' ' + number + (lists.normals ? "//" + number : "");
        }
        out.text() += '\n';
        out.flush_if_full();
    });
}

void append_little_endian(std::string& bytes, std::uint64_t value, int size) {
    for (int i = 0; i < size; ++i) {
        bytes += static_cast<char>((value >> (8 * i)) & 0xff);
    }
}

// Binary little-endian whatever the machine: each vertex x, y, z (and nx, ny, nz) as doubles, each face a
// uint8 count of 3 and three int32 indices.
void write_ply(StreamBuffer& out, const MeshLists& lists, MeshCounts counts) {
    std::string& bytes = out.text();
    bytes += "ply\nformat binary_little_endian 1.0\ncomment twinray generate\n";
    bytes += "element vertex " + std::to_string(counts.vertices) + "\n";
    bytes += "property double x\nproperty double y\nproperty double z\n";
    if (lists.normals) {
        bytes += "property double nx\nproperty double ny\nproperty double nz\n";
    }
    bytes += "element face " + std::to_string(counts.triangles) + "\n";
    bytes += "property list uchar int vertex_indices\nend_header\n";
    std::vector<Vec3> normals;
    if (lists.normals) {
        normals.reserve(static_cast<std::size_t>(counts.vertices));
        lists.normals([&](Vec3 normal) { normals.push_back(normal); });
    }
    std::size_t next = 0;
    lists.vertices([&](Vec3 vertex) {
        for (double coordinate : {vertex.x, vertex.y, vertex.z}) {
            append_little_endian(bytes, std::bit_cast<std::uint64_t>(coordinate), 8);
        }
        if (!normals.empty()) {
            const Vec3& normal = normals[next];
            for (double coordinate : {normal.x, normal.y, normal.z}) {
                append_little_endian(bytes, std::bit_cast<std::uint64_t>(coordinate), 8);
            }
        }
        ++next;
        out.flush_if_full();
    });
    lists.triangles([&](int a, int b, int c) {
        bytes += static_cast<char>(3);
        for (int index : {a, b, c}) {
            append_little_endian(bytes, static_cast<std::uint32_t>(index), 4);
        }
        out.flush_if_full();
    });
}

}  // namespace

const std::vector<std::string>& mesh_file_formats() {
    static const std::vector<std::string> formats = {"obj", "ply"};
    return formats;
}

void write_mesh_file(std::FILE* stream, const std::string& format, const MeshLists& lists, MeshCounts counts) {
    StreamBuffer out(stream);
    if (format == "obj") {
        write_obj(out, lists);
    } else if (format == "ply") {
        write_ply(out, lists, counts);
    } else {
        throw std::invalid_argument("unknown mesh file format \"" + format + "\"; allowed: obj, ply");
    }
    out.flush();
}

}  // namespace twinray::cli::generate

// The body of libtwinray_mesh_library.so (library.h): the format by the extension, every failure a refusal.
#include "scene/meshio/library.h"
#include "scene/meshio/readers.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <new>
#include <stdexcept>
#include <system_error>

namespace twinray::scene::meshio {

std::string printable(std::string_view text, std::size_t longest) {
    std::string result;
    for (const char c : text.substr(0, longest)) {
        result += std::isprint(static_cast<unsigned char>(c)) ? c : '?';
    }
    return text.size() > longest ? result + "..." : result;
}

std::string quote_word(std::string_view text) {
    return "\"" + printable(text, 40) + "\"";
}

std::string quoted_names(const std::set<std::string>& names) {
    constexpr std::size_t most = 8;
    std::string text;
    std::size_t listed = 0;
    for (const std::string& name : names) {
        if (listed == most) {
            return text + " and " + std::to_string(names.size() - most) + " more";
        }
        text += (listed++ == 0 ? "" : ", ") + quote_word(name);
    }
    return text;
}

MappedFile::MappedFile(const std::filesystem::path& file) {
    const int descriptor = ::open(file.c_str(), O_RDONLY | O_CLOEXEC);
    struct stat status {};
    if (descriptor < 0 || ::fstat(descriptor, &status) != 0) {
        const std::string reason = std::error_code(errno, std::generic_category()).message();
        if (descriptor >= 0) {
            ::close(descriptor);
        }
        refuse_at("", "cannot open file: " + reason);
    }
    size_ = static_cast<std::size_t>(status.st_size);
    if (size_ > 0) {
        void* mapped = ::mmap(nullptr, size_, PROT_READ, MAP_PRIVATE, descriptor, 0);
        data_ = mapped == MAP_FAILED ? nullptr : static_cast<const char*>(mapped);
    }
    const int mapping_error = errno;
    ::close(descriptor);
    if (size_ == 0) {
        refuse_at("", "the file is empty");
    }
    if (!data_) {
        refuse_at("", "cannot read file: " + std::error_code(mapping_error, std::generic_category()).message());
    }
}

MappedFile::~MappedFile() {
    ::munmap(const_cast<char*>(data_), size_);
}

namespace {

MeshReading read_by_extension(const std::filesystem::path& file, std::size_t max_triangles) {
    std::string extension = file.extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (extension == ".obj") {
        return read_obj(file, max_triangles);
    }
    if (extension == ".ply") {
        return read_ply(file, max_triangles);
    }
    if (extension == ".stl") {
        return read_stl(file, max_triangles);
    }
    if (extension == ".gltf" || extension == ".glb") {
        return read_gltf(file, max_triangles);
    }
    refuse_at("", "unknown mesh file extension " + quote_word(extension) +
                      ": twinray reads .obj, .ply, .stl, .gltf and .glb");
}

MeshReading refused(Refusal refusal) {
    MeshReading reading;
    reading.refusal = std::move(refusal);
    return reading;
}

}  // namespace

MeshReading read_mesh(const std::filesystem::path& file, std::size_t max_triangles) {
    try {
        return read_by_extension(file, max_triangles);
    } catch (const Refusal& refusal) {
        return refused(refusal);
    } catch (const std::bad_alloc&) {
        return refused({"", "out of memory while reading the file"});
    } catch (const std::exception& error) {
        return refused({"", error.what()});
    }
}

namespace {
const MeshLibraryFunctions functions{read_mesh};
}

}  // namespace twinray::scene::meshio

extern "C" const twinray::scene::meshio::MeshLibraryFunctions* twinray_mesh_library_functions() {
    return &twinray::scene::meshio::functions;
}

#include "io/atomic_file.h"

#include "io/file_handle.h"

#include <unistd.h>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <system_error>

namespace twinray::io {
namespace {

namespace fs = std::filesystem;

fs::path temporary_sibling(const fs::path& path) {
    std::string name = ".";
    name += path.stem().string();
    name += ".tmp";
    name += std::to_string(::getpid());
    name += path.extension().string();
    fs::path temporary = path;
    temporary.replace_filename(name);
    return temporary;
}

}  // namespace

void write_atomically(const fs::path& path, const std::function<void(const fs::path&)>& write) {
    fs::path temporary = temporary_sibling(path);
    try {
        write(temporary);
        fs::rename(temporary, path);
    } catch (const std::exception& error) {
        std::error_code ignored;
        fs::remove(temporary, ignored);
        if (dynamic_cast<const FileWriteError*>(&error) != nullptr) {
            throw;
        }
        throw FileWriteError("cannot write " + path.string() + ": " + error.what());
    }
}

void write_stream_atomically(const fs::path& path, const std::function<void(std::FILE*)>& write) {
    write_atomically(path, [&](const fs::path& temporary) {
        io::FileHandle stream(std::fopen(temporary.c_str(), "wb"));
        if (!stream) {
            throw FileWriteError("cannot write " + path.string() + ": " + std::strerror(errno));
        }
        write(stream.get());
        bool flushed = std::fflush(stream.get()) == 0;
        if (!flushed || std::ferror(stream.get()) != 0) {
            throw FileWriteError("cannot write " + path.string() + ": " + std::strerror(errno));
        }
    });
}

void write_text_atomically(const fs::path& path, std::string_view text) {
    write_stream_atomically(path, [&](std::FILE* stream) { std::fwrite(text.data(), 1, text.size(), stream); });
}

std::string output_folder_problem(const fs::path& path) {
    fs::path folder = path.parent_path().empty() ? fs::path(".") : path.parent_path();
    std::error_code error;
    fs::file_status status = fs::status(folder, error);
    if (error && error != std::errc::no_such_file_or_directory && error != std::errc::not_a_directory) {
        return "folder " + folder.string() + " cannot be reached: " + error.message();
    }
    if (!fs::is_directory(status)) {
        return "folder " + folder.string() + " does not exist";
    }
    if (::access(folder.c_str(), W_OK) != 0) {
        return "folder " + folder.string() + " is not writable";
    }
    return "";
}

}  // namespace twinray::io

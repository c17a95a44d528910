#include "io/atomic_file.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <system_error>
#include <unistd.h>

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

struct CloseFile {
    void operator()(std::FILE* stream) const { std::fclose(stream); }
};

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

void write_text_atomically(const fs::path& path, std::string_view text) {
    write_atomically(path, [&](const fs::path& temporary) {
        std::unique_ptr<std::FILE, CloseFile> stream(std::fopen(temporary.c_str(), "wb"));
        if (!stream) {
            throw FileWriteError("cannot write " + path.string() + ": " + std::strerror(errno));
        }
        bool written = std::fwrite(text.data(), 1, text.size(), stream.get()) == text.size();
        bool flushed = std::fflush(stream.get()) == 0;
        if (!written || !flushed) {
            throw FileWriteError("cannot write " + path.string() + ": " + std::strerror(errno));
        }
    });
}

}  // namespace twinray::io

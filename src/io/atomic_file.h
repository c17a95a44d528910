// Writing files so that nothing is ever half-written: everything goes to a temporary file in the same
// folder (so the final rename is atomic), which replaces the target only once complete. A failure or
// an interruption leaves the old file, if any, untouched.
#pragma once

#include <cstdio>
#include <filesystem>
#include <functional>
#include <stdexcept>
#include <string>
#include <string_view>

namespace twinray::io {

class FileWriteError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// Calls write(temporary_path), then renames the temporary over `path`. The temporary keeps the
// target's extension (some writers choose the format by it). On any exception the temporary is
// removed and the error is rethrown as FileWriteError naming `path`.
void write_atomically(const std::filesystem::path& path,
                      const std::function<void(const std::filesystem::path&)>& write);

// For a writer that streams its text rather than holding all of it: `write` gets the temporary, open
// for binary writing. Once it returns, the stream is flushed and its error flag checked, so a write
// that failed anywhere (a full disk) throws FileWriteError naming `path`, with the system's reason.
void write_stream_atomically(const std::filesystem::path& path, const std::function<void(std::FILE*)>& write);

void write_text_atomically(const std::filesystem::path& path, std::string_view text);

// Why a file could not be written at `path` (its folder is missing, unreachable or not writable), or ""
// if it can be: asked before a long job, so that the job is not wasted.
std::string output_folder_problem(const std::filesystem::path& path);

}  // namespace twinray::io

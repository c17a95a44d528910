// A C stream that closes itself when it goes out of scope. Writers flush and check ferror before that (so
// fclose has nothing left to fail on); readers have nothing to lose.
#pragma once

#include <cstdio>
#include <memory>

namespace twinray::io {

struct CloseFile {
    void operator()(std::FILE* stream) const { std::fclose(stream); }
};

using FileHandle = std::unique_ptr<std::FILE, CloseFile>;

}  // namespace twinray::io

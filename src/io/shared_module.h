// A module of ours (a shared library built beside twinray) loaded with dlopen on first use, so that the
// libraries behind it (OpenImageIO's hundreds, Embree and TBB) cost nothing to commands that never use
// them. Each module exports one function, `entry_symbol`, returning its table of functions.
#pragma once

#include <dlfcn.h>
#include <unistd.h>

#include <climits>
#include <stdexcept>
#include <string>

namespace twinray::io {

// Where a file of ours that the running executable needs lives: `installed`, relative to the executable's own
// folder (the layout `cmake --install` writes: modules in lib/twinray/ beside bin/), where it is there, else
// `built`, its path in the build tree. A prefix can be moved anywhere; a build tree runs from anywhere too.
inline std::string installed_or_built(const char* installed, const char* built) {
    char executable[PATH_MAX];
    ssize_t length = readlink("/proc/self/exe", executable, sizeof executable - 1);
    if (length > 0) {
        std::string folder(executable, static_cast<std::size_t>(length));
        folder.erase(folder.find_last_of('/') + 1);
        std::string candidate = folder + installed;
        if (access(candidate.c_str(), F_OK) == 0) {
            return candidate;
        }
    }
    return built;
}

// `path` is the module's path (installed_or_built); `what` names it in errors ("the Embree module").
template <typename Functions>
const Functions& load_shared_module(const char* path, const char* entry_symbol, const std::string& what) {
    void* module = dlopen(path, RTLD_LAZY | RTLD_LOCAL);
    if (!module) {
        throw std::runtime_error("cannot load " + what + ": " + dlerror());
    }
    using Entry = const Functions* (*)();
    auto entry = reinterpret_cast<Entry>(dlsym(module, entry_symbol));
    if (!entry) {
        throw std::runtime_error(what + " is broken: " + dlerror());
    }
    return *entry();
}

}  // namespace twinray::io

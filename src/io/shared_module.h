// A module of ours (a shared library built beside twinray) loaded with dlopen on first use, so that the
// libraries behind it (OpenImageIO's hundreds, Embree and TBB) cost nothing to commands that never use
// them. Each module exports one function, `entry_symbol`, returning its table of functions.
#pragma once

#include <dlfcn.h>

#include <stdexcept>
#include <string>

namespace twinray::io {

// `path` is the module's path in the build tree; `what` names it in errors ("the Embree module").
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

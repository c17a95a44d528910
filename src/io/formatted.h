// printf-style text of a few values, for one line of a report or a message (cut at 511 bytes).
#pragma once

#include <cstdio>
#include <string>

namespace twinray::io {

template <typename... Values>
std::string formatted(const char* pattern, Values... values) {
    char text[512];
    std::snprintf(text, sizeof text, pattern, values...);
    return text;
}

}  // namespace twinray::io

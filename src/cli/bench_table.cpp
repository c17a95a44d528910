#include "cli/bench_table.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace twinray::cli {

std::string cell(const char* format, double value) {
    if (std::isinf(value)) {
        return value > 0 ? "inf" : "-inf";
    }
    char text[64];
    std::snprintf(text, sizeof text, format, value);
    return text;
}

std::string to_console(const BenchTable& table) {
    std::vector<std::size_t> widths(table.headers.size());
    for (std::size_t i = 0; i < table.headers.size(); ++i) {
        widths[i] = table.headers[i].size();
        for (const auto& row : table.rows) {
            widths[i] = std::max(widths[i], row[i].size());
        }
    }
    auto line = [&](const std::vector<std::string>& cells) {
        std::string text;
        for (std::size_t i = 0; i < cells.size(); ++i) {
            std::string padding(widths[i] - cells[i].size(), ' ');
            text += i == 0 ? cells[i] + padding : "  " + padding + cells[i];
        }
        return text + "\n";
    };
    std::string text = table.title + "\n\n" + line(table.headers);
    for (const auto& row : table.rows) {
        text += line(row);
    }
    return text + "\n";
}

namespace {

// "ref<double>" would read as an HTML tag in Markdown.
std::string escape_html(const std::string& text) {
    std::string escaped;
    for (char c : text) {
        escaped += c == '<' ? "&lt;" : c == '>' ? "&gt;" : std::string(1, c);
    }
    return escaped;
}

}  // namespace

std::string to_markdown(const BenchTable& table) {
    auto line = [](const std::vector<std::string>& cells) {
        std::string text = "|";
        for (const std::string& c : cells) {
            text += " " + escape_html(c) + " |";
        }
        return text + "\n";
    };
    std::string text = "### " + escape_html(table.title) + "\n\n" + line(table.headers) + "| --- |";
    for (std::size_t i = 1; i < table.headers.size(); ++i) {
        text += " ---: |";
    }
    text += "\n";
    for (const auto& row : table.rows) {
        text += line(row);
    }
    return text + "\n";
}

std::string to_csv(const BenchTable& table) {
    auto line = [](const std::vector<std::string>& cells) {
        std::string text;
        for (std::size_t i = 0; i < cells.size(); ++i) {
            text += (i == 0 ? "" : ",") + cells[i];
        }
        return text + "\n";
    };
    std::string text = line(table.headers);
    for (const auto& row : table.rows) {
        text += line(row);
    }
    return text;
}

}  // namespace twinray::cli

// The tables `twinray bench` prints, and writes as Markdown and CSV: one set of cells, three renderings.
#pragma once

#include <string>
#include <vector>

namespace twinray::cli {

struct BenchTable {
    std::string title;
    std::vector<std::string> headers;
    std::vector<std::vector<std::string>> rows;

    void add_row(std::vector<std::string> cells) { rows.push_back(std::move(cells)); }
};

// printf-style formatting of one cell.
std::string cell(const char* format, double value);

std::string to_console(const BenchTable& table);   // aligned columns under the title
std::string to_markdown(const BenchTable& table);  // a GitHub table under a "### title" heading
std::string to_csv(const BenchTable& table);       // a header line, then the rows; no title

}  // namespace twinray::cli

// What `fovea bench` writes from the sweep's rows: the JSON object (issues 5-8 shape plus every
// variant), the table, the CSV with a '#' header (date, device, driver, seeds, command), the PNG
// of time against error with the Pareto front, and the Markdown summary the README embeds.
#pragma once

#include <cstdio>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench_sweep.hpp"

namespace fovea::bench {

// Rows the Pareto front is taken over: the first display's foveated variants that ran.
// Cost ms/frame (median), quality the mean band PSNR (the foveal PSNR saturates at 100 dB).
std::vector<size_t> pareto_rows(const std::vector<Row>& rows);

std::string variant_label(const Row& row, const std::string& primary_display);

// "methods": one representative per method (the first display, default settings, no post)
// with atd from the same method under TAA and atd_no_taa without; "variants": every row;
// "pareto_front": variant labels along the front.
nlohmann::json to_json(const std::vector<Row>& rows, int frames);

void print_table(std::FILE* out, const std::vector<Row>& rows);
bool write_csv(const std::string& path, const std::vector<Row>& rows,
               const std::vector<std::string>& header_lines);
bool write_plot(const std::string& path, const std::vector<Row>& rows);
bool write_summary(const std::string& path, const std::vector<Row>& rows,
                   const std::vector<std::string>& header_lines, const std::string& png_name);

}  // namespace fovea::bench

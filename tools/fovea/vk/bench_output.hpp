// What `fovea bench` writes from the sweep's rows: the JSON object (issues 5-8 shape plus every
// variant), the table, the CSV with a '#' header (date, device, driver, seeds, command), the PNGs
// of time against error (mean FLIP, and pooled PSNR) with their Pareto fronts, and the Markdown
// summary the README embeds.
#pragma once

#include <cstdio>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench_sweep.hpp"

namespace fovea::bench {

// Rows the Pareto fronts are taken over: the first display's foveated variants that ran, at the
// sweep's frame count (not the temporal runs). Cost ms/frame (median); error the mean FLIP, or
// minus the pooled PSNR of the whole frame.
enum class FrontMetric { kFlip, kPsnr };
std::vector<size_t> pareto_rows(const std::vector<Row>& rows, FrontMetric metric);

std::string variant_label(const Row& row, const std::string& primary_display);

// "methods": one representative per method (the first display, default settings, no post) with
// atd from the same method under TAA and atd_no_taa without, and "temporal" from the temporal
// runs; "variants": every row; "pareto_front" (on FLIP) and "pareto_front_psnr": labels.
nlohmann::json to_json(const std::vector<Row>& rows, int frames);

void print_table(std::FILE* out, const std::vector<Row>& rows);
bool write_csv(const std::string& path, const std::vector<Row>& rows,
               const std::vector<std::string>& header_lines);
// Time against mean FLIP at `flip_path`, against pooled PSNR at `psnr_path`.
bool write_plots(const std::string& flip_path, const std::string& psnr_path,
                 const std::vector<Row>& rows);
// `bench` is to_json()'s object with "model" and the measured saccade recovery added.
bool write_summary(const std::string& path, const std::vector<Row>& rows,
                   const std::vector<std::string>& header_lines, const nlohmann::json& bench,
                   const std::string& flip_png, const std::string& psnr_png);

// "x.png" -> "x_psnr.png": the second plot's default path.
std::string psnr_plot_path(const std::string& flip_png);

}  // namespace fovea::bench

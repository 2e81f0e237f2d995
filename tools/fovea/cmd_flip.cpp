// fovea flip REF.png TEST.png [--ppd P] [--json] [--map OUT.png]: LDR-FLIP (Andersson et al.
// 2020) of a test image against a reference with the CPU reference implementation, pooled like
// NVIDIA's tool (mean, weighted median and quartiles, min, max). The default ppd is the tool's
// (67.02: a 0.7 m wide 4K monitor at 0.7 m), so figures compare with published ones.
#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

#include "command.hpp"
#include "fovea/metrics/flip.hpp"
#include "fovea/metrics/image.hpp"

namespace fovea::cli {
namespace {

struct FlipOptions {
    std::string reference, test, map;
    double ppd = metrics::kFlipDefaultPpd;
    bool json = false;
};

void run_flip(const FlipOptions& o) {
    auto ref = metrics::load_png(o.reference);
    if (!ref) throw std::runtime_error("flip: " + ref.error().message);
    auto test = metrics::load_png(o.test);
    if (!test) throw std::runtime_error("flip: " + test.error().message);
    if (ref->width != test->width || ref->height != test->height)
        throw std::runtime_error("flip: image sizes differ: " + o.reference + " is " +
                                 std::to_string(ref->width) + "x" + std::to_string(ref->height) +
                                 ", " + o.test + " is " + std::to_string(test->width) + "x" +
                                 std::to_string(test->height));
    const std::vector<float> map = metrics::flip_map(
        ref->view(), test->view(), metrics::PpdField::uniform(ref->width, ref->height, o.ppd));
    const metrics::FlipPooled p = metrics::pool_flip(map);
    if (!o.map.empty() &&
        !metrics::write_png(o.map, metrics::map_to_grey(map, ref->width, ref->height).view()))
        throw std::runtime_error("flip: cannot write " + o.map);
    if (o.json) {
        nlohmann::json j;
        j["metric"] = "LDR-FLIP";
        j["reference"] = o.reference;
        j["test"] = o.test;
        j["resolution"] = {ref->width, ref->height};
        j["ppd"] = o.ppd;
        j["mean"] = p.mean;
        j["weighted_median"] = p.weighted_median;
        j["weighted_quartile1"] = p.weighted_quartile1;
        j["weighted_quartile3"] = p.weighted_quartile3;
        j["min"] = p.min;
        j["max"] = p.max;
        std::printf("%s\n", j.dump().c_str());
        return;
    }
    std::printf("LDR-FLIP of %s against %s, %ux%u at %.4g ppd\n", o.test.c_str(),
                o.reference.c_str(), ref->width, ref->height, o.ppd);
    std::printf("  mean                   %.6f\n", p.mean);
    std::printf("  weighted median        %.6f\n", p.weighted_median);
    std::printf("  weighted 1st quartile  %.6f\n", p.weighted_quartile1);
    std::printf("  weighted 3rd quartile  %.6f\n", p.weighted_quartile3);
    std::printf("  min                    %.6f\n", p.min);
    std::printf("  max                    %.6f\n", p.max);
    if (!o.map.empty()) std::printf("  map                    %s\n", o.map.c_str());
}

void setup(CLI::App& app) {
    auto o = std::make_shared<FlipOptions>();
    app.add_option("reference", o->reference, "Reference image (PNG)")->required();
    app.add_option("test", o->test, "Test image (PNG, same size)")->required();
    app.add_option("--ppd", o->ppd,
                   "Pixels per degree of the observer (default 67.02, the FLIP tool's)")
        ->check(CLI::Range(0.01, 1000.0));
    app.add_flag("--json", o->json, "Print one JSON object");
    app.add_option("--map", o->map, "Write the FLIP map as a grey PNG (0 black, 1 white)");
    app.callback([o] { run_flip(*o); });
}

const Command kFlip{
    "flip", "LDR-FLIP of a test image against a reference (mean, weighted median, max)", &setup};

}  // namespace
}  // namespace fovea::cli

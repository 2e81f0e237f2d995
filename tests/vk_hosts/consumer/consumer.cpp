// One foveated frame through the installed SDK: headless device, the host's shading from
// shading.glsl, a cleared G-buffer. Prints "consumer ok <shaded fraction>" and exits 0.
#include <cstdio>
#include <fstream>
#include <sstream>

#include "fovea/vk/device.hpp"
#include "fovea/vk/foveator.hpp"
#include "fovea/vk/projection.hpp"

int main() {
    auto device = fovea::vk::Device::create_headless();
    if (!device) {
        std::fprintf(stderr, "consumer: %s\n", device.error().message.c_str());
        return 1;
    }
    std::ifstream in(CONSUMER_SHADING);
    std::stringstream glsl;
    glsl << in.rdbuf();
    fovea::vk::FoveatorConfig c;
    c.extent = {128, 96};
    c.display = fovea::vk::EyeDisplay::from_fov(128, 96, 40.0, 30.0);
    c.method = "cps";
    c.shading_glsl = glsl.str();
    auto f = fovea::vk::Foveator::create(*device, c);
    if (!f) {
        std::fprintf(stderr, "consumer: %s\n", f.error().message.c_str());
        return 1;
    }
    f->render_blocking(0, fovea::vk::FrameInputs{}, {});
    const auto p = fovea::vk::jittered_projection({}, f->jitter(0), c.extent);
    std::printf("consumer ok %.3f %zu\n", f->stats().shaded_fraction, p.size());
    return 0;
}

// The viewer's scene file (TOML, toml++): models placed in the world, lights, the environment, the
// display and a camera path. Bad input gets one line naming the key, the file and what was
// expected; nothing is guessed. Format (every key but [[model]] optional):
//
//   data_dir = "../../../../../shared/data"  # model files are relative to it; relative to this
//                                             # file; $FOVEA_SHARED_DATA_DIR or --data-dir win
//   [display]      width = 1920  height = 1080  fov_h_deg = 47.8  fov_v_deg = 28.0
//   [environment]  sky = [r, g, b]  horizon = [r, g, b]  ground = [r, g, b]  intensity = 1.0
//   [[light]]      type = "directional" | "point"  direction = [x, y, z] (directional, travel
//                  direction)  position = [x, y, z] (point)  color = [r, g, b]  intensity = 3.0
//   [camera]       near = 0.02  far = 100.0
//   [[camera.key]] t = 0.0  position = [x, y, z]  target = [x, y, z]   # seconds; >= 1 key
//   [[model]]      file = "scenes/Avocado/glTF/Avocado.gltf"  fit = 0.2 (largest edge, scene
//                  units; 0 = as authored)  translation = [x, y, z]  rotation_deg = [x, y, z]
//                  scale = 1.0
#pragma once

#include <array>
#include <string>
#include <vector>

#include "gltf_viewer/math.hpp"

namespace gltfv {

struct LightDesc {
    bool directional = true;
    Vec3 direction{-0.3f, -1.f, -0.4f};  // the light travels along it
    Vec3 position{0.f, 2.f, 0.f};
    Vec3 color{1.f, 1.f, 1.f};
    float intensity = 3.f;
};

struct ModelDesc {
    std::string file;  // resolved path
    float fit = 0.f;
    Vec3 translation{0.f, 0.f, 0.f};
    Vec3 rotation_deg{0.f, 0.f, 0.f};
    float scale = 1.f;
    Mat4 placement() const;
};

struct CameraKey {
    double t_s = 0.0;
    Vec3 position{0.f, 0.f, 1.f};
    Vec3 target{0.f, 0.f, 0.f};
};

struct SceneFile {
    std::string path;
    uint32_t width = 1920, height = 1080;
    float fov_h_deg = 47.8f, fov_v_deg = 28.0f;
    Vec3 sky{0.45f, 0.6f, 0.9f}, horizon{0.85f, 0.85f, 0.82f}, ground{0.22f, 0.2f, 0.18f};
    float env_intensity = 1.f;
    std::vector<LightDesc> lights;
    float near_z = 0.02f, far_z = 100.f;
    std::vector<CameraKey> camera;
    std::vector<ModelDesc> models;

    // Eye and target at time t: linear between keys with smoothstep easing, held at the ends.
    CameraKey camera_at(double t_s) const;
};

// Parses `path`. data_dir_override (non-empty) replaces the file's data_dir.
// Returns an empty string or one line naming the problem.
std::string load_scene_file(const std::string& path, const std::string& data_dir_override,
                            SceneFile& out);

}  // namespace gltfv

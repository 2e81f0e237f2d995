# The glTF viewer's host code as a library: the standalone viewer (CMakeLists.txt, against the
# installed SDK) and `fovea bench --scene` (in-tree) build the same sources and shaders with
#   gltf_viewer_add_host(<target>)
# Needs targets fovea::vk and fovea::client, fovea_GLSL_INCLUDE_DIR (the SDK's GLSL contract, from
# find_package(fovea)), TinyGLTF::TinyGLTF (libtinygltf-dev), pkg-config modules tomlplusplus and
# stb, and glslangValidator (glslang-tools).
set(GLTF_VIEWER_DIR ${CMAKE_CURRENT_LIST_DIR})

function(gltf_viewer_add_host target)
    find_package(TinyGLTF REQUIRED)
    find_package(PkgConfig REQUIRED)
    pkg_check_modules(GLTF_VIEWER_TOML REQUIRED IMPORTED_TARGET tomlplusplus)
    pkg_check_modules(GLTF_VIEWER_STB REQUIRED IMPORTED_TARGET stb)
    find_program(GLTF_VIEWER_GLSLANG glslangValidator REQUIRED)
    set(_src ${GLTF_VIEWER_DIR}/src)
    add_library(${target} STATIC
        ${_src}/frame_host.cpp ${_src}/gaze_source.cpp ${_src}/host_device.cpp
        ${_src}/image_io.cpp ${_src}/math.cpp ${_src}/model.cpp ${_src}/renderer.cpp
        ${_src}/scene_file.cpp ${_src}/vk_util.cpp)
    set(_spv_dir ${CMAKE_CURRENT_BINARY_DIR}/${target}_spv)
    file(MAKE_DIRECTORY ${_spv_dir})
    file(GLOB _incs CONFIGURE_DEPENDS ${GLTF_VIEWER_DIR}/shaders/*.glsl)
    set(_headers)
    foreach(_s viewer_mesh.vert viewer_forward.frag viewer_sky.vert viewer_sky_forward.frag
               viewer_gbuffer.frag viewer_sky_gbuffer.frag)
        string(MAKE_C_IDENTIFIER ${_s} _id)
        add_custom_command(OUTPUT ${_spv_dir}/${_id}.spv.h
            COMMAND ${GLTF_VIEWER_GLSLANG} -V --target-env vulkan1.1
                    -I${GLTF_VIEWER_DIR}/shaders -I${fovea_GLSL_INCLUDE_DIR} --vn ${_id}
                    -o ${_spv_dir}/${_id}.spv.h ${GLTF_VIEWER_DIR}/shaders/${_s}
            DEPENDS ${GLTF_VIEWER_DIR}/shaders/${_s} ${_incs}
            COMMENT "gltf_viewer: compiling ${_s}" VERBATIM)
        list(APPEND _headers ${_spv_dir}/${_id}.spv.h)
    endforeach()
    # The deferred path's fovea_shade() as one string (the SDK compiles it at run time), checked
    # against the SDK's GLSL contract at build time.
    set(_shade_files ${GLTF_VIEWER_DIR}/shaders/viewer_scene.glsl
        ${GLTF_VIEWER_DIR}/shaders/viewer_pbr.glsl ${GLTF_VIEWER_DIR}/shaders/viewer_gbuffer.glsl
        ${GLTF_VIEWER_DIR}/shaders/viewer_shade.glsl)
    add_custom_command(OUTPUT ${_spv_dir}/viewer_shading_glsl.h ${_spv_dir}/viewer_shading.glsl
        COMMAND ${CMAKE_COMMAND} -DOUT=${_spv_dir}/viewer_shading_glsl.h
                -DGLSL=${_spv_dir}/viewer_shading.glsl -DNAME=kViewerShadingGlsl "-DPREFIX=#define VIEWER_SCENE_SET FOVEA_HOST_SET"
                "-DFILES=${_shade_files}" -P ${GLTF_VIEWER_DIR}/embed_glsl.cmake
        DEPENDS ${_shade_files} ${GLTF_VIEWER_DIR}/embed_glsl.cmake
        COMMENT "gltf_viewer: embedding its shading function" VERBATIM)
    list(APPEND _headers ${_spv_dir}/viewer_shading_glsl.h)
    if(COMMAND fovea_check_shading)  # the installed SDK's (foveaConfig.cmake)
        fovea_check_shading(${target}_shading ${_spv_dir}/viewer_shading.glsl)
    endif()
    target_sources(${target} PRIVATE ${_headers})
    target_include_directories(${target} PUBLIC ${GLTF_VIEWER_DIR}/include PRIVATE ${_spv_dir})
    target_link_libraries(${target}
        PUBLIC fovea::vk fovea::client
        PRIVATE TinyGLTF::TinyGLTF PkgConfig::GLTF_VIEWER_TOML PkgConfig::GLTF_VIEWER_STB)
    target_compile_features(${target} PUBLIC cxx_std_20)
    if(COMMAND fovea_target_defaults)  # in-tree: the project's warnings (and -Werror in CI)
        fovea_target_defaults(${target})
        # Vulkan structs are initialised as `VkFooInfo info{VK_STRUCTURE_TYPE_FOO_INFO};`, as in
        # the SDK (sdk/vk.cmake).
        target_compile_options(${target} PRIVATE
            $<$<CXX_COMPILER_ID:GNU,Clang>:-Wno-missing-field-initializers>)
    endif()
endfunction()

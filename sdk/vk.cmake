# fovea::vk — the Vulkan foveation module (DESIGN.md §5). Included by sdk/CMakeLists.txt when
# FOVEA_BUILD_VK. Sources: every sdk/src/vk/**/*.cpp (methods and post passes add files, plus one
# registry line); shaders: every shaders/*.comp|*.glsl (cmake/FoveaShaders.cmake).
find_package(Vulkan REQUIRED)
find_package(glslang CONFIG REQUIRED)
include(FoveaShaders)

file(GLOB_RECURSE _fovea_vk_sources CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/src/vk/*.cpp)
# Shared, with Debian's static glslang linked in and its symbols kept local (--exclude-libs):
# one copy of the compiler per system instead of one inside every host binary, and no clash
# with a host that links its own glslang (engines often do). The C++ API has no ABI promise
# before 1.0, so the SOVERSION is major.minor.
add_library(fovea_vk SHARED ${_fovea_vk_sources})
add_library(fovea::vk ALIAS fovea_vk)
set_target_properties(fovea_vk PROPERTIES
    VERSION ${PROJECT_VERSION}
    SOVERSION ${PROJECT_VERSION_MAJOR}.${PROJECT_VERSION_MINOR})
target_link_options(fovea_vk PRIVATE "LINKER:--exclude-libs,ALL" "LINKER:--no-undefined")
target_include_directories(fovea_vk
    PUBLIC $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
    PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/src/vk ${PROJECT_SOURCE_DIR}/shaders)
target_link_libraries(fovea_vk
    PUBLIC fovea_headers Vulkan::Vulkan
    PRIVATE glslang::glslang glslang::SPIRV glslang::glslang-default-resource-limits
            Threads::Threads)
fovea_embed_shaders(fovea_vk ${PROJECT_SOURCE_DIR}/shaders)
# The GLSL contract hosts compile against (installed under include/fovea/vk/glsl, exported as
# fovea_GLSL_INCLUDE_DIR and fovea_check_shading() by foveaConfig.cmake).
set(FOVEA_GLSL_CONTRACT
    ${PROJECT_SOURCE_DIR}/shaders/fovea_frame.glsl
    ${PROJECT_SOURCE_DIR}/shaders/fovea_gbuffer.glsl
    ${PROJECT_SOURCE_DIR}/shaders/fovea_acuity.glsl
    ${PROJECT_SOURCE_DIR}/shaders/fovea_check.shade.comp
    CACHE INTERNAL "GLSL files installed for hosts")
fovea_target_defaults(fovea_vk)
# Only in AddressSanitizer trees: the drivers the loader opens stay mapped until exit, so LSan can
# tell their heap from ours (the file says why).
if(FOVEA_SANITIZE MATCHES "address")
    target_sources(fovea_vk PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/sanitizer/keep_drivers_loaded.cpp)
endif()
# Debian's glslang is built without RTTI, so UBSan's vptr check, which needs the typeinfo of every
# polymorphic class it sees, cannot link against TShader/TProgram: the one file that uses them
# goes without that check (it keeps the rest of UBSan and ASan).
if(FOVEA_SANITIZE MATCHES "undefined")
    set_source_files_properties(${CMAKE_CURRENT_SOURCE_DIR}/src/vk/shader_compiler.cpp
        PROPERTIES COMPILE_OPTIONS -fno-sanitize=vptr)
endif()
# Vulkan structs are initialised as `VkFooInfo info{VK_STRUCTURE_TYPE_FOO_INFO};` (the rest zero).
target_compile_options(fovea_vk PRIVATE $<$<CXX_COMPILER_ID:GNU,Clang>:-Wno-missing-field-initializers>)

# Internal headers (gpu.hpp, method.hpp, ...) for the demo host, GPU tests and benchmarks in this
# tree; not installed.
add_library(fovea_vk_internal INTERFACE)
add_library(fovea::vk_internal ALIAS fovea_vk_internal)
target_include_directories(fovea_vk_internal INTERFACE ${CMAKE_CURRENT_SOURCE_DIR}/src/vk)
target_link_libraries(fovea_vk_internal INTERFACE fovea_vk)
target_compile_options(fovea_vk_internal INTERFACE
    $<$<CXX_COMPILER_ID:GNU,Clang>:-Wno-missing-field-initializers>)

# The CPU half of the shared acuity model must round like the GPU half (`precise`, no FMA).
set_source_files_properties(${CMAKE_CURRENT_SOURCE_DIR}/src/vk/acuity.cpp PROPERTIES
    COMPILE_OPTIONS "$<$<CXX_COMPILER_ID:GNU,Clang>:-ffp-contract=off>")

# fovea_post_model: CPU reference models and metrics of the post-process chain (TAA, contrast
# and noise enhancement, ATD / wavelet / RMS contrast). No Vulkan; included by the TAA tests and
# by whoever links the metrics (fovea bench). Safe to include more than once.
if(NOT TARGET fovea_post_model)
    set(_post_dir ${CMAKE_CURRENT_LIST_DIR})
    add_library(fovea_post_model STATIC
        ${_post_dir}/taa_model.cpp
        ${_post_dir}/enhance_model.cpp
        ${_post_dir}/metrics_model.cpp
        ${_post_dir}/saccade_model.cpp
        ${_post_dir}/bench_metrics.cpp
        ${_post_dir}/stability_model.cpp)
    target_include_directories(fovea_post_model PUBLIC ${_post_dir})
    target_link_libraries(fovea_post_model PUBLIC fovea::headers)
    fovea_target_defaults(fovea_post_model)
endif()

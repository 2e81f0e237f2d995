# fovea_check_shading(<name> <shading.glsl> [BACKGROUND] [DEFINES d1 d2 ...])
# Compiles a host's shading function (what it passes as FoveatorConfig::shading_glsl) against the
# installed GLSL contract at build time, as the module's shading passes will at run time, and
# adds the result to target <name> (a custom target built with ALL). BACKGROUND also checks
# fovea_background(). Needs glslangValidator (Debian: glslang-tools).
# Included by foveaConfig.cmake; fovea_GLSL_INCLUDE_DIR is the contract's directory.
function(fovea_check_shading name glsl)
    cmake_parse_arguments(C "BACKGROUND" "" "DEFINES" ${ARGN})
    find_program(FOVEA_GLSLANG_VALIDATOR glslangValidator REQUIRED)
    get_filename_component(_glsl "${glsl}" ABSOLUTE)
    set(_dir ${CMAKE_CURRENT_BINARY_DIR}/fovea_check_${name})
    set(_defs)
    foreach(_d IN LISTS C_DEFINES)
        list(APPEND _defs "-D${_d}")
    endforeach()
    if(C_BACKGROUND)
        list(APPEND _defs "-DFOVEA_CHECK_BACKGROUND")
    endif()
    # The check shader includes "fovea_host.glsl": the host's file under that name.
    add_custom_command(OUTPUT ${_dir}/check.spv
        COMMAND ${CMAKE_COMMAND} -E make_directory ${_dir}
        COMMAND ${CMAKE_COMMAND} -E copy ${_glsl} ${_dir}/fovea_host.glsl
        COMMAND ${FOVEA_GLSLANG_VALIDATOR} -V --target-env vulkan1.1 ${_defs} -I${_dir}
                -I${fovea_GLSL_INCLUDE_DIR} -o ${_dir}/check.spv
                ${fovea_GLSL_INCLUDE_DIR}/fovea_check.shade.comp
        DEPENDS ${_glsl}
        COMMENT "Checking ${glsl} against the Fovea shading contract" VERBATIM)
    add_custom_target(${name} ALL DEPENDS ${_dir}/check.spv)
endfunction()

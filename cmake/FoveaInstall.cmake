# Install layout (issue 10): binaries, the systemd unit + socket, sysusers and udev files, the
# example configuration, the client headers and shared library, foveaConfig.cmake (fovea::client,
# fovea::vk when built, with the GLSL contract and fovea_check_shading()), fovea.pc and
# fovea-vk.pc, and a .deb through CPack. The unit's ExecStart and the config
# location follow CMAKE_INSTALL_PREFIX at configure time: for the .deb configure with
# -DCMAKE_INSTALL_PREFIX=/usr (then the config goes to /etc/fovea and udev/systemd/sysusers
# files to /usr/lib/...).
include(CMakePackageConfigHelpers)

set(FOVEA_SYSTEMD_UNIT_DIR "lib/systemd/system" CACHE STRING
    "systemd unit directory, relative to the install prefix")
set(FOVEA_SYSUSERS_DIR "lib/sysusers.d" CACHE STRING
    "sysusers.d directory, relative to the install prefix")
set(FOVEA_UDEV_RULES_DIR "lib/udev/rules.d" CACHE STRING
    "udev rules directory, relative to the install prefix")
if(CMAKE_INSTALL_PREFIX STREQUAL "/usr")
    set(_fovea_confdir_default "/etc/fovea")
else()
    set(_fovea_confdir_default "${CMAKE_INSTALL_SYSCONFDIR}/fovea")
endif()
set(FOVEA_CONFIG_DIR "${_fovea_confdir_default}" CACHE STRING
    "Where fovead.toml is installed (fovead reads /etc/fovea/fovead.toml)")
set(FOVEA_CMAKE_DIR "${CMAKE_INSTALL_LIBDIR}/cmake/fovea")

# --- service files --------------------------------------------------------------------------
set(FOVEA_SBINDIR "${CMAKE_INSTALL_FULL_SBINDIR}")
configure_file(${PROJECT_SOURCE_DIR}/daemon/systemd/fovead.service.in
               ${PROJECT_BINARY_DIR}/systemd/fovead.service @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/systemd/fovead.service
              ${PROJECT_SOURCE_DIR}/daemon/systemd/fovead.socket
        DESTINATION ${FOVEA_SYSTEMD_UNIT_DIR} COMPONENT service)
install(FILES ${PROJECT_SOURCE_DIR}/daemon/systemd/fovea.conf
        DESTINATION ${FOVEA_SYSUSERS_DIR} COMPONENT service)
install(FILES ${PROJECT_SOURCE_DIR}/udev/70-fovea.rules
        DESTINATION ${FOVEA_UDEV_RULES_DIR} COMPONENT service)
install(FILES ${PROJECT_SOURCE_DIR}/daemon/systemd/fovead.toml
        DESTINATION ${FOVEA_CONFIG_DIR} COMPONENT service)

# Installed executables find libfovea next to them under any prefix.
foreach(_t fovead fovea)
    if(TARGET ${_t})
        set_target_properties(${_t} PROPERTIES INSTALL_RPATH "$ORIGIN/../${CMAKE_INSTALL_LIBDIR}")
    endif()
endforeach()

# --- SDK: headers, libfovea, CMake package, pkg-config --------------------------------------
set(_fovea_header_excludes)
if(NOT TARGET fovea_vk)
    set(_fovea_header_excludes PATTERN "vk" EXCLUDE)
endif()
install(DIRECTORY ${PROJECT_SOURCE_DIR}/sdk/include/fovea DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
        COMPONENT sdk FILES_MATCHING PATTERN "*.h" PATTERN "*.hpp" ${_fovea_header_excludes})

set_target_properties(fovea_headers PROPERTIES EXPORT_NAME headers)
set(_fovea_export_targets fovea_client fovea_headers)
set(FOVEA_CONFIG_HAVE_VK OFF)
if(TARGET fovea_vk)
    set_target_properties(fovea_vk PROPERTIES EXPORT_NAME vk)
    list(APPEND _fovea_export_targets fovea_vk)
    set(FOVEA_CONFIG_HAVE_VK ON)
    # The GLSL contract for hosts' own shaders and build-time checks (foveaConfig.cmake).
    install(FILES ${FOVEA_GLSL_CONTRACT}
            DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/fovea/vk/glsl COMPONENT sdk)
    install(FILES ${CMAKE_CURRENT_LIST_DIR}/foveaShading.cmake
            DESTINATION ${FOVEA_CMAKE_DIR} COMPONENT sdk)
endif()
install(TARGETS ${_fovea_export_targets} EXPORT foveaTargets
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT sdk
        NAMELINK_COMPONENT sdk
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT sdk
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT sdk
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(EXPORT foveaTargets NAMESPACE fovea:: FILE foveaTargets.cmake
        DESTINATION ${FOVEA_CMAKE_DIR} COMPONENT sdk)
configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/foveaConfig.cmake.in
    ${PROJECT_BINARY_DIR}/cmake/foveaConfig.cmake INSTALL_DESTINATION ${FOVEA_CMAKE_DIR}
    PATH_VARS CMAKE_INSTALL_INCLUDEDIR)
# The SOVERSION is the ring ABI version; the package version is the project version.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/cmake/foveaConfigVersion.cmake
    VERSION ${PROJECT_VERSION} COMPATIBILITY SameMajorVersion)
install(FILES ${PROJECT_BINARY_DIR}/cmake/foveaConfig.cmake
              ${PROJECT_BINARY_DIR}/cmake/foveaConfigVersion.cmake
        DESTINATION ${FOVEA_CMAKE_DIR} COMPONENT sdk)

# fovea.pc finds its prefix from its own location, so an install under any --prefix works.
file(RELATIVE_PATH FOVEA_PC_TO_PREFIX "/${CMAKE_INSTALL_LIBDIR}/pkgconfig" "/")
string(REGEX REPLACE "/$" "" FOVEA_PC_TO_PREFIX "${FOVEA_PC_TO_PREFIX}")
configure_file(${CMAKE_CURRENT_LIST_DIR}/fovea.pc.in ${PROJECT_BINARY_DIR}/pkgconfig/fovea.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/pkgconfig/fovea.pc
        DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig COMPONENT sdk)
if(TARGET fovea_vk)  # `pkg-config fovea-vk`: the Vulkan module (Requires fovea and vulkan)
    configure_file(${CMAKE_CURRENT_LIST_DIR}/fovea-vk.pc.in ${PROJECT_BINARY_DIR}/pkgconfig/fovea-vk.pc
                   @ONLY)
    install(FILES ${PROJECT_BINARY_DIR}/pkgconfig/fovea-vk.pc
            DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig COMPONENT sdk)
endif()

# --- .deb -----------------------------------------------------------------------------------
set(CPACK_GENERATOR "DEB")
set(CPACK_PACKAGE_NAME "fovea")
set(CPACK_PACKAGE_VENDOR "Fovea")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "${PROJECT_DESCRIPTION}")
set(CPACK_PACKAGE_VERSION "${PROJECT_VERSION}")
set(CPACK_PACKAGE_CONTACT "Fovea maintainers <fovea@localhost>")
set(CPACK_PACKAGING_INSTALL_PREFIX "${CMAKE_INSTALL_PREFIX}")
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION "science")
set(CPACK_DEBIAN_PACKAGE_DEPENDS "systemd, udev")
find_program(FOVEA_DPKG_SHLIBDEPS dpkg-shlibdeps)
if(FOVEA_DPKG_SHLIBDEPS)
    set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
endif()
set(_fovea_deb_dir ${PROJECT_BINARY_DIR}/deb)
configure_file(${CMAKE_CURRENT_LIST_DIR}/deb/postinst.in ${_fovea_deb_dir}/postinst @ONLY
               FILE_PERMISSIONS OWNER_READ OWNER_WRITE OWNER_EXECUTE GROUP_READ GROUP_EXECUTE
               WORLD_READ WORLD_EXECUTE)
configure_file(${CMAKE_CURRENT_LIST_DIR}/deb/prerm ${_fovea_deb_dir}/prerm COPYONLY
               FILE_PERMISSIONS OWNER_READ OWNER_WRITE OWNER_EXECUTE GROUP_READ GROUP_EXECUTE
               WORLD_READ WORLD_EXECUTE)
configure_file(${CMAKE_CURRENT_LIST_DIR}/deb/postrm ${_fovea_deb_dir}/postrm COPYONLY
               FILE_PERMISSIONS OWNER_READ OWNER_WRITE OWNER_EXECUTE GROUP_READ GROUP_EXECUTE
               WORLD_READ WORLD_EXECUTE)
set(CPACK_DEBIAN_PACKAGE_CONTROL_EXTRA
    ${_fovea_deb_dir}/postinst ${_fovea_deb_dir}/prerm ${_fovea_deb_dir}/postrm)
if(IS_ABSOLUTE "${FOVEA_CONFIG_DIR}")
    file(WRITE ${_fovea_deb_dir}/conffiles "${FOVEA_CONFIG_DIR}/fovead.toml\n")
    list(APPEND CPACK_DEBIAN_PACKAGE_CONTROL_EXTRA ${_fovea_deb_dir}/conffiles)
endif()
include(CPack)

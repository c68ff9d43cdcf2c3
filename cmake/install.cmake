# Install layout (docs/install.md), the CMake package for other programs and
# the Debian package (cpack -G DEB). Per-target rules live next to the targets
# (lib/, tools/, upid-db/).
install(DIRECTORY ${PROJECT_SOURCE_DIR}/schemas/ DESTINATION ${CMAKE_INSTALL_DATADIR}/lmcfg/schemas
        COMPONENT runtime)
# Simulated drives to try the tools without hardware (--port sim:FILE works on a copy).
install(DIRECTORY ${PROJECT_SOURCE_DIR}/tests/fixtures/sim/ DESTINATION ${CMAKE_INSTALL_DATADIR}/lmcfg/sim
        COMPONENT runtime)

# lmcfg serve as a systemd service (docs/serve.md), with the installed lmcfg's path.
configure_file(${PROJECT_SOURCE_DIR}/packaging/lmcfg-serve.service.in
               ${PROJECT_BINARY_DIR}/lmcfg-serve.service @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/lmcfg-serve.service DESTINATION lib/systemd/system
        COMPONENT runtime)
# Its example inventory, to copy to /etc/lmcfg/plant.toml.
install(FILES ${PROJECT_SOURCE_DIR}/packaging/plant.example.toml
        DESTINATION ${CMAKE_INSTALL_DOCDIR}/examples RENAME plant.toml COMPONENT runtime)

# find_package(lmcfg) -> lmcfg::lmcfg
include(CMakePackageConfigHelpers)
set(LMCFG_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/lmcfg)
install(EXPORT lmcfgTargets NAMESPACE lmcfg:: DESTINATION ${LMCFG_CMAKE_DIR} COMPONENT development)
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/lmcfgConfig.cmake.in
  ${PROJECT_BINARY_DIR}/lmcfgConfig.cmake INSTALL_DESTINATION ${LMCFG_CMAKE_DIR}
  PATH_VARS CMAKE_INSTALL_DATADIR)
write_basic_package_version_file(${PROJECT_BINARY_DIR}/lmcfgConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/lmcfgConfig.cmake ${PROJECT_BINARY_DIR}/lmcfgConfigVersion.cmake
        DESTINATION ${LMCFG_CMAKE_DIR} COMPONENT development)

# Debian package: everything in one package, lmcfg_VERSION-1_ARCH.deb, with
# the Python package (component python, python/CMakeLists.txt) in
# /usr/lib/python3/dist-packages/lmcfg/ when the bindings are built.
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME lmcfg)
set(CPACK_PACKAGE_VENDOR "lmcfg")
set(CPACK_PACKAGE_CONTACT "lmcfg maintainers <lmcfg@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "Back up, diff, default and restore LinMot drive configurations over LinRS")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_RELEASE 1)
set(CPACK_DEBIAN_PACKAGE_SECTION utils)
# Runtime libraries from dpkg-shlibdeps (libsqlite3-0, libpugixml1v5, libgit2-1.5, libtomlplusplus3, libstdc++6, libc6).
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
# For the installed CMake package (headers and static library): what lmcfgConfig.cmake finds.
set(CPACK_DEBIAN_PACKAGE_SUGGESTS "libsqlite3-dev, libpugixml-dev, libgit2-dev, libtomlplusplus-dev, nlohmann-json3-dev, pkg-config, bash-completion")
# The Python module is built for one interpreter's ABI (python3.X of the build
# machine): recommended when the package ships it (the program does not need it).
if(LMCFG_PYTHON_DEB_RECOMMENDS)
  set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "${LMCFG_PYTHON_DEB_RECOMMENDS}")
endif()
include(CPack)

# The libraries lmcfg.exe links, as scripts/build-windows.sh leaves them:
# static libraries built for MinGW-w64 from Debian's source packages in
# LMCFG_WINDOWS_DEPS (lib/, include/), zlib from libz-mingw-w64-dev, and the
# header-only libraries through LMCFG_WINDOWS_HEADERS (links to Debian's
# headers, one folder each). The target names are the Linux build's, so
# lib/CMakeLists.txt declares each layer once.
if(NOT LMCFG_WINDOWS_DEPS OR NOT LMCFG_WINDOWS_HEADERS)
  message(FATAL_ERROR "a Windows build needs LMCFG_WINDOWS_DEPS and LMCFG_WINDOWS_HEADERS: "
                      "run scripts/build-windows.sh")
endif()

function(lmcfg_windows_lib name)
  cmake_parse_arguments(W "" "" "FILES;SYSTEM;INCLUDES" ${ARGN})
  add_library(${name} INTERFACE IMPORTED GLOBAL)
  set(files)
  foreach(f IN LISTS W_FILES)
    if(NOT EXISTS ${f})
      message(FATAL_ERROR "${f} missing: run scripts/build-windows.sh")
    endif()
    list(APPEND files ${f})
  endforeach()
  target_link_libraries(${name} INTERFACE ${files} ${W_SYSTEM})
  target_include_directories(${name} SYSTEM INTERFACE ${W_INCLUDES})
endfunction()

set(dep_lib ${LMCFG_WINDOWS_DEPS}/lib)
set(dep_inc ${LMCFG_WINDOWS_DEPS}/include)
lmcfg_windows_lib(PkgConfig::SQLITE3 FILES ${dep_lib}/libsqlite3.a INCLUDES ${dep_inc})
lmcfg_windows_lib(pugixml::pugixml FILES ${dep_lib}/libpugixml.a INCLUDES ${dep_inc})
# libgit2's static library and what its libgit2.pc lists under Libs.private.
lmcfg_windows_lib(PkgConfig::LIBGIT2
  FILES ${dep_lib}/libgit2.a ${dep_lib}/libpcre2-8.a ${dep_lib}/libhttp_parser.a
  SYSTEM z rpcrt4 crypt32 ole32 ws2_32 secur32 advapi32
  INCLUDES ${dep_inc})
target_compile_definitions(PkgConfig::LIBGIT2 INTERFACE PCRE2_STATIC)
# lmcfg serve's HTTPS (lib/web/web_tls_win32.cpp); Mbed TLS 2.28 gathers
# entropy with CryptGenRandom (advapi32).
lmcfg_windows_lib(MbedTLS::mbedtls
  FILES ${dep_lib}/libmbedtls.a ${dep_lib}/libmbedx509.a ${dep_lib}/libmbedcrypto.a
  SYSTEM advapi32 ws2_32 bcrypt
  INCLUDES ${dep_inc})
# lmcfg serve's webhook client: cpp-httplib's single header from Debian's
# source package (Debian's libcpp-httplib-dev is a compiled library and its
# header declarations only), without OpenSSL: http:// webhooks.
if(NOT EXISTS ${dep_inc}/httplib.h)
  message(FATAL_ERROR "${dep_inc}/httplib.h missing: run scripts/build-windows.sh")
endif()
lmcfg_windows_lib(PkgConfig::HTTPLIB SYSTEM ws2_32 INCLUDES ${dep_inc})
lmcfg_windows_lib(PkgConfig::TOMLPLUSPLUS INCLUDES ${LMCFG_WINDOWS_HEADERS})
lmcfg_windows_lib(nlohmann_json::nlohmann_json INCLUDES ${LMCFG_WINDOWS_HEADERS})
lmcfg_windows_lib(CLI11::CLI11 INCLUDES ${LMCFG_WINDOWS_HEADERS})
# The cross-built unit tests (LMCFG_BUILD_TESTS): Catch2 v2 is one header.
lmcfg_windows_lib(Catch2::Catch2 INCLUDES ${LMCFG_WINDOWS_HEADERS})
set(THREADS_PREFER_PTHREAD_FLAG ON)
find_package(Threads REQUIRED)

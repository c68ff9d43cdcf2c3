# Cross-compiling lmcfg.exe on Debian with MinGW-w64 (g++-mingw-w64-x86-64-posix:
# the posix thread model, so std::thread and std::mutex exist). Used by
# scripts/build-windows.sh; docs/windows.md.
set(CMAKE_SYSTEM_NAME Windows)
set(CMAKE_SYSTEM_PROCESSOR x86_64)
set(triple x86_64-w64-mingw32)
set(CMAKE_C_COMPILER ${triple}-gcc-posix)
set(CMAKE_CXX_COMPILER ${triple}-g++-posix)
set(CMAKE_RC_COMPILER ${triple}-windres)
set(CMAKE_AR ${triple}-gcc-ar-posix CACHE FILEPATH "")
set(CMAKE_RANLIB ${triple}-gcc-ranlib-posix CACHE FILEPATH "")

# Only the MinGW sysroot and the dependencies built for it: never a header or
# library of the Linux host.
set(CMAKE_FIND_ROOT_PATH /usr/${triple} ${LMCFG_WINDOWS_DEPS})
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)

# One lmcfg.exe without DLLs beyond Windows' own: libstdc++, libgcc and
# winpthread linked in.
# No link time in the PE header (--no-insert-timestamp): the same sources
# give the same lmcfg.exe (scripts/release.sh).
set(CMAKE_EXE_LINKER_FLAGS_INIT "-static -static-libgcc -static-libstdc++ -Wl,--no-insert-timestamp")

# Programs the build runs (the UPID database compiler) run under Wine.
find_program(LMCFG_WINE NAMES wine64 wine PATHS /usr/lib/wine NO_CMAKE_FIND_ROOT_PATH)
if(LMCFG_WINE)
  set(CMAKE_CROSSCOMPILING_EMULATOR ${LMCFG_WINE})
endif()

# MinGW's GCC 12 reports the -Wrestrict/-Warray-bounds/-Wstringop-overflow
# false positives inside libstdc++'s std::string (GCC bug 105651) in many more
# files than the Linux build's (lib/CMakeLists.txt silences them per target
# there).
# LMCFG_WINDOWS_EXTRA_FLAGS: more flags from scripts/build-windows.sh (the
# release's source path map).
set(CMAKE_CXX_FLAGS_INIT "-Wno-restrict -Wno-array-bounds -Wno-stringop-overflow ${LMCFG_WINDOWS_EXTRA_FLAGS}")
set(CMAKE_C_FLAGS_INIT "${LMCFG_WINDOWS_EXTRA_FLAGS}")

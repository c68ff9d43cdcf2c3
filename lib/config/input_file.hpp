#pragma once
// The few calls read_text_file (text_file.cpp) needs from the platform, on a
// C runtime file descriptor: POSIX open/read in atomic_file.cpp, the Windows
// CRT's _wopen/_read (binary mode) in atomic_file_win32.cpp. Private to the
// config layer: not an installed header.
#include <cstddef>
#include <filesystem>

namespace lmcfg::config::input_file {

// Opens `path` for reading; -1 with errno set when it cannot.
int open(const std::filesystem::path& path);
// Standard input, switched to binary where the platform translates line ends.
int standard_input();
// The size of a regular file; -1 for anything else (pipe, device, terminal).
long long regular_size(int fd);
// Up to `n` bytes; 0 at the end; -1 with errno set on an error (EINTR retried).
long read(int fd, char* buf, std::size_t n);
void close(int fd);

}  // namespace lmcfg::config::input_file

#pragma once
// What the bearer tokens and the console's sessions need from the operating
// system (token_file.cpp: POSIX modes and /dev/urandom; token_file_win32.cpp:
// the file's access list and BCryptGenRandom). Private to the serve layer.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "common/result.hpp"

namespace lmcfg::serve {

// Errc::file_error when a user other than the file's owner may write to it
// (whoever can write the tokens file can give themselves a token), saying
// who and what to run. A file that does not exist passes (reading it fails).
Result<void> check_owner_only(const std::string& path);
bool file_exists(const std::string& path);
// Appends `line`, creating the file writable and readable by its owner only
// (POSIX mode 0600; Windows: an access list of the user, SYSTEM and
// Administrators). Errc::file_error naming the file.
Result<void> append_owner_only(const std::string& path, const std::string& line);
// `n` bytes from the operating system's cryptographic random source.
Result<std::vector<std::uint8_t>> random_bytes(std::size_t n);

}  // namespace lmcfg::serve
